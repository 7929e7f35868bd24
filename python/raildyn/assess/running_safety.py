"""Running safety (EN 14363): derailment quotient Y/Q per wheel and guiding force sum Y per
wheelset as 2 m sliding means against their limits, and the instability criterion (rms of
sum Y over a sliding 100 m window against half the Prud'homme limit).

SECONDARY SOURCE for the limits and filters (the text of EN 14363 was not at hand; values as
the vehicle-dynamics literature quotes them, e.g. Iwnicki (ed.), Handbook of Railway Vehicle
Dynamics, chapter on acceptance testing; UIC 518):
- forces low-pass filtered at 20 Hz before evaluation;
- (Y/Q)_lim = 0.8 (curves of radius >= 250 m; the standard treats smaller radii separately:
  raildyn states the 0.8 limit and the smallest radius the wheelset saw);
- Prud'homme (sum Y)_lim = alpha (10 kN + 2 Q0 / 3), Q0 the static wheel force, alpha = 1
  (0.85 for freight wagons: ``prudhomme_alpha``);
- instability: sum Y band-pass filtered f0 +- 2 Hz (f0 the instability frequency), rms over
  a 100 m sliding window, limit (sum Y)_lim / 2.
"""
from __future__ import annotations

import numpy as np

from .filters import butterworth_bandpass_gain, magnitude_filter
from .layout import SIDES, WheelsetData
from .quantity import Quantity, not_available
from .windows import WindowError, sliding_mean, sliding_rms

__all__ = ["YQ_LIMIT", "prudhomme_limit", "static_wheel_load", "running_safety",
           "dominant_frequency"]

YQ_LIMIT = 0.8
SLIDING_LENGTH = 2.0          #: m, Y/Q and sum Y
INSTABILITY_LENGTH = 100.0    #: m
_SOURCE = "secondary: EN 14363 as quoted in the literature (docs/assessment.md)"


def static_wheel_load(ws: WheelsetData) -> float:
    """Q0 [N]: the median over the run of the wheelset's mean wheel force (Q_left + Q_right)/2.
    In a curve the wheels share the axle load unequally, their mean stays the static load."""
    q = 0.5 * (ws.wheel["left"]["force_vertical_Q"] + ws.wheel["right"]["force_vertical_Q"])
    return float(np.median(q))


def prudhomme_limit(q0: float, alpha: float = 1.0) -> float:
    """(sum Y)_lim = alpha (10 kN + 2 Q0 / 3) [N] (Q0 static wheel force [N])."""
    return alpha * (10e3 + 2.0 * q0 / 3.0)


def dominant_frequency(t: np.ndarray, y: np.ndarray, f_min: float = 0.5,
                       f_max: float = 15.0) -> float | None:
    """Frequency [Hz] of the largest spectral line of y (mean removed) in [f_min, f_max]."""
    if t.size < 8:
        return None
    fs = 1.0 / float(np.median(np.diff(t)))
    spectrum = np.abs(np.fft.rfft((y - y.mean()) * np.hanning(y.size)))
    f = np.fft.rfftfreq(y.size, 1.0 / fs)
    band = (f >= f_min) & (f <= min(f_max, fs / 2))
    if not band.any() or spectrum[band].max() == 0:
        return None
    return float(f[band][np.argmax(spectrum[band])])


def _at_max(centres, values, abs_value=True):
    k = int(np.argmax(np.abs(values) if abs_value else values))
    return float(values[k]), float(centres[k])


def running_safety(ws: WheelsetData, t: np.ndarray, lowpass, alpha: float = 1.0,
                   instability_frequency: float | None = None) -> list[Quantity]:
    """The running-safety quantities of one wheelset; ``lowpass(y)`` is the 20 Hz filter."""
    out: list[Quantity] = []
    if set(ws.wheel) != set(SIDES):
        reason = "the file has no wheel series (wheelsets/<name>/<side>/wheel; &output groups)"
        for side in SIDES:
            out.append(not_available("Y/Q", "1", reason, wheelset=ws.name, side=side))
        out.append(not_available("sum_Y", "N", reason, wheelset=ws.name))
        out.append(not_available("sum_Y_rms", "N", reason, wheelset=ws.name))
        return out
    s = ws.position
    radius_note = ""
    if ws.curvature is not None and np.any(np.abs(ws.curvature) > 0):
        radius_note = f"; smallest radius {1.0 / np.max(np.abs(ws.curvature)):.0f} m"
    for side in SIDES:
        yq = lowpass(ws.wheel[side]["Y_over_Q"])
        try:
            centres, mean = sliding_mean(s, yq, SLIDING_LENGTH)
        except WindowError as e:
            out.append(not_available("Y/Q", "1", str(e), wheelset=ws.name, side=side))
            continue
        value, pos = _at_max(centres, mean, abs_value=False)
        out.append(Quantity("Y/Q", "1", value, YQ_LIMIT, pos, ws.name, side,
                            clause="EN 14363 running safety: Y/Q, 2 m sliding mean" + radius_note,
                            source=_SOURCE, series={"position": centres, "value": mean}))
    q0 = static_wheel_load(ws)
    limit = prudhomme_limit(q0, alpha)
    sum_y = lowpass(ws.wheel["left"]["force_lateral_Y"] + ws.wheel["right"]["force_lateral_Y"])
    try:
        centres, mean = sliding_mean(s, sum_y, SLIDING_LENGTH)
        value, pos = _at_max(centres, np.abs(mean))
        out.append(Quantity("sum_Y", "N", value, limit, pos, ws.name,
                            clause=f"EN 14363 running safety: sum Y, 2 m sliding mean, against "
                                   f"Prud'homme alpha (10 kN + 2 Q0/3), alpha = {alpha:g}, "
                                   f"Q0 = {q0:.0f} N",
                            source=_SOURCE, series={"position": centres, "value": mean}))
    except WindowError as e:
        out.append(not_available("sum_Y", "N", str(e), wheelset=ws.name, limit=limit))
    f0 = instability_frequency or dominant_frequency(t, sum_y)
    if f0 is None:
        out.append(not_available("sum_Y_rms", "N", "no oscillation of sum Y between 0.5 and 15 Hz "
                                 "to take as instability frequency", wheelset=ws.name,
                                 limit=limit / 2))
        return out
    fs = 1.0 / float(np.median(np.diff(t)))
    band = magnitude_filter(sum_y, fs, lambda f: butterworth_bandpass_gain(f, max(f0 - 2.0, 0.1), f0 + 2.0))
    try:
        centres, rms = sliding_rms(s, band, INSTABILITY_LENGTH)
        value, pos = _at_max(centres, rms)
        out.append(Quantity("sum_Y_rms", "N", value, limit / 2, pos, ws.name,
                            clause=f"EN 14363 instability: sum Y band-passed {f0:.2f} +- 2 Hz, "
                                   "rms over 100 m sliding window, limit (sum Y)_lim / 2",
                            source=_SOURCE, series={"position": centres, "value": rms}))
    except WindowError as e:
        out.append(not_available("sum_Y_rms", "N", str(e), wheelset=ws.name, limit=limit / 2))
    return out
