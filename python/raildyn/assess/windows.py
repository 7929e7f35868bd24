"""Sliding means, sliding rms values and percentiles along the track or in time.

A sliding mean over a length L at position s is the mean of the signal over the stretch
``[s - L/2, s + L/2]``: the integral of the linearly interpolated samples (trapezoid rule
along the abscissa) divided by L. It is evaluated at every sample whose whole window lies
inside the data, so its value does not depend on the sampling, and a stretch the vehicle did
not move over (speed 0) carries no weight. The abscissa may be a track position [m] (EN 14363's
2 m and 100 m windows) or a time [s] (EN 12299's 5 s windows).

Percentiles follow the nearest-rank definition: the p-th percentile of N values is the
smallest value that at least p % of the values do not exceed (the ``ceil(p N / 100)``-th
smallest). SECONDARY SOURCE: EN 12299 and EN 14363 speak of the p % values of the
cumulative frequency distribution; the nearest-rank reading is raildyn's (docs/assessment.md).
"""
from __future__ import annotations

import numpy as np

__all__ = ["WindowError", "sliding_mean", "sliding_rms", "percentile", "block_rms"]


class WindowError(ValueError):
    """The data cannot carry the window (too short, abscissa going backwards): the message
    says why and becomes the quantity's 'not available' reason."""


def _check_abscissa(x: np.ndarray, length: float, what: str) -> None:
    if x.size < 2:
        raise WindowError(f"{x.size} sample(s): a {length:g} {what} window needs a stretch of data")
    if np.any(np.diff(x) < 0):
        raise WindowError(f"the {what} abscissa goes backwards (vehicle reversing): sliding "
                          "windows along it are not defined")
    if x[-1] - x[0] < length:
        raise WindowError(f"the data cover {x[-1] - x[0]:.3g} {what}, shorter than the "
                          f"{length:g} {what} window")


def sliding_mean(x, y, length: float, unit: str = "m") -> tuple[np.ndarray, np.ndarray]:
    """Centred sliding mean of y(x) over ``length``: returns (x_centres, means) for every
    sample whose window ``[x - length/2, x + length/2]`` lies inside the data."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    _check_abscissa(x, length, unit)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])
    inside = (x - length / 2 >= x[0]) & (x + length / 2 <= x[-1])
    centres = x[inside]
    # the integral of a linear interpolant is piecewise quadratic: integrate exactly from
    # the sample below each window end
    upper = _integral_at(x, y, integral, centres + length / 2)
    lower = _integral_at(x, y, integral, centres - length / 2)
    return centres, (upper - lower) / length


def _integral_at(x, y, integral, at):
    """Integral of the linear interpolant of y(x) from x[0] to each point of ``at``."""
    k = np.clip(np.searchsorted(x, at, side="right") - 1, 0, x.size - 2)
    dx = x[k + 1] - x[k]
    h = at - x[k]
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = np.where(dx > 0, (y[k + 1] - y[k]) / np.where(dx > 0, dx, 1.0), 0.0)
    return integral[k] + y[k] * h + 0.5 * slope * h**2


def sliding_rms(x, y, length: float, unit: str = "m") -> tuple[np.ndarray, np.ndarray]:
    """Centred sliding rms of y(x): the square root of the sliding mean of y^2 (y^2 of the
    samples interpolated linearly, the same rule as ``sliding_mean``)."""
    centres, mean_square = sliding_mean(x, np.asarray(y, float) ** 2, length, unit)
    return centres, np.sqrt(np.maximum(mean_square, 0.0))


def block_rms(t, y, length: float) -> tuple[np.ndarray, np.ndarray]:
    """rms values of consecutive, non-overlapping blocks of ``length`` seconds (EN 12299's
    5 s values): returns (block end times, rms); a last incomplete block is dropped."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    _check_abscissa(t, length, "s")
    n_blocks = int(np.floor((t[-1] - t[0]) / length + 1e-9))
    ends = t[0] + length * np.arange(1, n_blocks + 1)
    square = y**2
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (square[1:] + square[:-1]) * np.diff(t))])
    at = np.concatenate([[t[0]], ends])
    values = _integral_at(t, square, integral, at)
    return ends, np.sqrt(np.maximum(np.diff(values) / length, 0.0))


def percentile(values, p: float) -> float:
    """Nearest-rank p-th percentile (0 < p <= 100) of ``values``."""
    v = np.sort(np.asarray(values, float).ravel())
    if v.size == 0:
        raise WindowError("no values to take a percentile of")
    if not 0 < p <= 100:
        raise ValueError(f"percentile {p} outside (0, 100]")
    rank = int(np.ceil(p / 100.0 * v.size - 1e-9))
    return float(v[max(rank, 1) - 1])
