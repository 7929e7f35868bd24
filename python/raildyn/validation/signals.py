"""Signal analysis of the cases: window means, wavelengths, band curves; the growth-rate
estimator is the product's (raildyn.stability, ``raildyn critical-speed --method bisection``)."""
from __future__ import annotations

import math

import numpy as np

from ..stability import growth_rate, half_cycle_peaks  # noqa: F401  (the harness's names)
from .core import CaseError


def window_mask(t: np.ndarray, t_from: float, t_to: float) -> np.ndarray:
    return (t >= t_from - 1e-12) & (t <= t_to + 1e-12)


def window_mean(t: np.ndarray, y: np.ndarray, t_from: float, t_to: float) -> float:
    m = window_mask(t, t_from, t_to)
    if m.sum() < 2:
        raise CaseError(f"window [{t_from:g}, {t_to:g}] s holds fewer than 2 output points "
                        f"(results cover {t[0]:g} to {t[-1]:g} s)" if t.size else "no output rows")
    return float(np.mean(y[m]))


def oscillation_wavelength(t: np.ndarray, y: np.ndarray, speed: float) -> float:
    """Wavelength [m] = speed x period, the period from the mean spacing of the zero
    crossings (two per period, linearly interpolated)."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    i = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
    if i.size < 3:
        raise CaseError("fewer than 3 zero crossings: no oscillation to measure a wavelength")
    tc = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    return float(speed * 2.0 * np.mean(np.diff(tc)))


def compare_band_curve(t: np.ndarray, y: np.ndarray, t_ref: np.ndarray, lower: np.ndarray,
                       upper: np.ndarray) -> tuple[bool, float, float, int]:
    """Interpolate the result (t, y) at the reference times inside the result's time span
    and check lower <= y <= upper. Returns (passed, largest violation [channel unit], time of
    it, number of points compared); no overlap fails."""
    m = (t_ref >= t[0] - 1e-12) & (t_ref <= t[-1] + 1e-12)
    if not m.any():
        return False, math.inf, math.nan, 0
    yi = np.interp(t_ref[m], t, y)
    viol = np.maximum(lower[m] - yi, yi - upper[m])
    k = int(np.argmax(viol))
    return bool(np.all(viol <= 0)), float(max(viol[k], 0.0)), float(t_ref[m][k]), int(m.sum())
