"""Ride comfort (EN 12299): weighted accelerations, the mean comfort index N_MV (standard
method) and continuous comfort Cc, from acceleration series on the car body floor.

- weighted accelerations: x and y with Wd, z with Wb (filters.py);
- 5 s rms values of consecutive blocks; over each 5 min period their 95 % values
  a_XP95, a_YP95, a_ZP95 (nearest rank of the 60 values) and
  N_MV = 6 sqrt(a_XP95^2 + a_YP95^2 + a_ZP95^2);
- continuous comfort Cc_x,y,z(t): rms of the weighted acceleration over the 5 s before t.

SECONDARY SOURCE (EN 12299 not at hand; definitions as the ride-comfort literature quotes the
standard, e.g. Iwnicki (ed.), Handbook of Railway Vehicle Dynamics, chapter on passenger
comfort): the comfort scale N_MV < 1 very comfortable, 1-2 comfortable, 2-4 medium, 4-5
uncomfortable, > 5 very uncomfortable. The standard sets no limit: ``limit`` is null.
"""
from __future__ import annotations

import numpy as np

from .filters import apply_weighting
from .quantity import Quantity, not_available
from .windows import WindowError, block_rms, percentile, sliding_mean

__all__ = ["DIRECTION_WEIGHTINGS", "weighted_accelerations", "mean_comfort",
           "continuous_comfort", "comfort_quantities", "BLOCK", "PERIOD"]

#: EN 12299 floor measurement: weighting per direction of the car body axes
DIRECTION_WEIGHTINGS = {"x": "Wd", "y": "Wd", "z": "Wb"}
BLOCK = 5.0       #: s, rms blocks and the Cc window
PERIOD = 300.0    #: s, the N_MV evaluation period
_SOURCE = "secondary: EN 12299 as quoted in the literature (docs/assessment.md)"


def _rate(t: np.ndarray) -> float:
    dt = np.diff(t)
    if dt.size == 0 or np.any(dt <= 0):
        raise WindowError("the time axis is not increasing")
    if np.ptp(dt) > 1e-6 * np.mean(dt):
        raise WindowError("the output interval is not constant: the weighting filters need "
                          "equally spaced samples")
    return 1.0 / float(np.mean(dt))


def weighted_accelerations(t, ax, ay, az) -> dict[str, np.ndarray]:
    """The weighted accelerations a_Xw (Wd), a_Yw (Wd), a_Zw (Wb) [m/s^2]. Each signal is
    taken relative to its first sample, i.e. as if the run had been preceded by its initial
    state for ever: the weightings remove a constant (H(0) = 0), and an accelerometer's
    +g (specific force) then starts no switch-on transient."""
    t = np.asarray(t, float)
    fs = _rate(t)
    out = {}
    for d, a in zip("xyz", (ax, ay, az)):
        a = np.asarray(a, float)
        out[d] = apply_weighting(DIRECTION_WEIGHTINGS[d], a - a[0], fs)
    return out


def mean_comfort(t, ax, ay, az, period: float = PERIOD) -> tuple[float, float, dict[str, float]]:
    """N_MV of the worst complete period (default 5 min): returns (N_MV, end time of that
    period, {direction: 95 % value of its 5 s rms values})."""
    t = np.asarray(t, float)
    if t.size < 2 or t[-1] - t[0] < period - 1e-9:
        raise WindowError(f"the run covers {t[-1] - t[0] if t.size > 1 else 0:.3g} s; N_MV is "
                          f"taken over {period:g} s periods")
    weighted = weighted_accelerations(t, ax, ay, az)
    blocks = {d: block_rms(t, w, BLOCK) for d, w in weighted.items()}
    ends = blocks["x"][0]
    per_period = int(round(period / BLOCK))
    best = None
    for p in range(len(ends) // per_period):
        sl = slice(p * per_period, (p + 1) * per_period)
        p95 = {d: percentile(blocks[d][1][sl], 95.0) for d in "xyz"}
        n = 6.0 * np.sqrt(sum(v**2 for v in p95.values()))
        if best is None or n > best[0]:
            best = (float(n), float(ends[sl][-1]), p95)
    return best


def continuous_comfort(t, ax, ay, az) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Cc per direction: (times t, rms of the weighted acceleration over [t - 5 s, t])."""
    t = np.asarray(t, float)
    weighted = weighted_accelerations(t, ax, ay, az)
    out = {}
    for d, w in weighted.items():
        centres, mean_square = sliding_mean(t, w**2, BLOCK, unit="s")
        out[d] = (centres + BLOCK / 2, np.sqrt(np.maximum(mean_square, 0.0)))
    return out


def comfort_quantities(sensor: str, t, acceleration, position_at) -> list[Quantity]:
    """N_MV and the largest Cc per direction of one sensor; ``acceleration`` (n, 3) x y z in
    the car body axes [m/s^2]; ``position_at(time)`` gives the sensor's track position."""
    a = np.asarray(acceleration, float)
    out = []
    try:
        n_mv, t_end, p95 = mean_comfort(t, a[:, 0], a[:, 1], a[:, 2])
        out.append(Quantity("N_MV", "1", n_mv, None, float(position_at(t_end)), sensor=sensor,
                            clause="EN 12299 mean comfort, standard method: 6 sqrt(a_XP95^2 + "
                                   "a_YP95^2 + a_ZP95^2), Wd Wd Wb, 5 s rms, 5 min; a_P95 = " +
                                   " / ".join(f"{p95[d]:.4g}" for d in "xyz") + " m/s^2",
                            source=_SOURCE))
    except WindowError as e:
        out.append(not_available("N_MV", "1", str(e), sensor=sensor))
    try:
        cc = continuous_comfort(t, a[:, 0], a[:, 1], a[:, 2])
        for d in "xyz":
            times, values = cc[d]
            k = int(np.argmax(values))
            out.append(Quantity("Cc", "m/s^2", float(values[k]), None, float(position_at(times[k])),
                                sensor=sensor, direction=d,
                                clause=f"EN 12299 continuous comfort Cc_{d}: rms of the "
                                       f"{DIRECTION_WEIGHTINGS[d]}-weighted acceleration over the "
                                       "preceding 5 s (largest value)",
                                source=_SOURCE, series={"time": times, "value": values}))
    except WindowError as e:
        for d in "xyz":
            out.append(not_available("Cc", "m/s^2", str(e), sensor=sensor, direction=d))
    return out
