"""Track loading (EN 14363): the maximum vertical wheel force Q_max, the quasi-static lateral
and vertical wheel forces Y_qst and Q_qst in circular curves, and the wheel unloading
Delta Q / Q.

SECONDARY SOURCE (EN 14363 not at hand; values as the vehicle-dynamics literature and UIC 518
quote them; docs/assessment.md):
- forces low-pass filtered at 20 Hz;
- Q_max: the 99.85 % value of the filtered wheel force over the run (the standard's estimate
  of the maximum of a section), against Q_lim = 200 kN up to 160 km/h, 190 kN to 200 km/h,
  180 kN to 250 km/h, 170 kN to 300 km/h, 160 kN above;
- Y_qst, Q_qst: the 50 % value (median) of the filtered wheel force over each circular-curve
  section (constant non-zero curvature under the wheelset), against 60 kN and 145 kN;
- Delta Q / Q = (Q0 - Q) / Q0 with Q0 the static wheel force, largest over the run, against
  0.6 (the limit of the twist test).
"""
from __future__ import annotations

import numpy as np

from .layout import SIDES, WheelsetData
from .quantity import Quantity, not_available
from .running_safety import static_wheel_load
from .windows import percentile

__all__ = ["q_limit", "curve_sections", "track_loading", "YQST_LIMIT", "QQST_LIMIT",
           "UNLOADING_LIMIT"]

YQST_LIMIT = 60e3
QQST_LIMIT = 145e3
UNLOADING_LIMIT = 0.6
Q_PERCENTILE = 99.85
_SOURCE = "secondary: EN 14363 / UIC 518 as quoted in the literature (docs/assessment.md)"


def q_limit(max_speed: float) -> float:
    """Q_lim [N] for the largest running speed [m/s]."""
    kmh = max_speed * 3.6
    for v, q in ((160, 200e3), (200, 190e3), (250, 180e3), (300, 170e3)):
        if kmh <= v + 1e-9:
            return q
    return 160e3


def curve_sections(curvature: np.ndarray, rel_tol: float = 1e-6) -> list[tuple[int, int]]:
    """Row ranges [start, stop) where the curvature is non-zero and constant (circular
    curves; transitions, whose curvature changes from row to row, are left out)."""
    k = np.asarray(curvature, float)
    scale = max(float(np.max(np.abs(k))) if k.size else 0.0, 1e-12)
    sections, start = [], None
    for i in range(k.size):
        in_curve = abs(k[i]) > 1e-9 * scale + 1e-12
        same = start is not None and abs(k[i] - k[start]) <= rel_tol * abs(k[start])
        if start is not None and not same:
            if i - start >= 2:
                sections.append((start, i))
            start = None
        if start is None and in_curve:
            start = i
    if start is not None and k.size - start >= 2:
        sections.append((start, k.size))
    return sections


def track_loading(ws: WheelsetData, speed: np.ndarray, lowpass) -> list[Quantity]:
    """The track-loading quantities of one wheelset."""
    out: list[Quantity] = []
    if set(ws.wheel) != set(SIDES):
        reason = "the file has no wheel series (wheelsets/<name>/<side>/wheel; &output groups)"
        for name, unit in (("Q_max", "N"), ("Y_qst", "N"), ("Q_qst", "N"), ("DeltaQ/Q", "1")):
            for side in SIDES:
                out.append(not_available(name, unit, reason, wheelset=ws.name, side=side))
        return out
    q_lim = q_limit(float(np.max(np.abs(speed))) if speed.size else 0.0)
    q0 = static_wheel_load(ws)
    s = ws.position
    sections = [] if ws.curvature is None else curve_sections(ws.curvature)
    for side in SIDES:
        q = lowpass(ws.wheel[side]["force_vertical_Q"])
        y = lowpass(ws.wheel[side]["force_lateral_Y"])
        value = percentile(q, Q_PERCENTILE)
        k = int(np.argmin(np.abs(q - value)))
        out.append(Quantity("Q_max", "N", value, q_lim, float(s[k]), ws.name, side,
                            clause=f"EN 14363 track loading: Q_max, {Q_PERCENTILE} % value of "
                                   "the 20 Hz filtered wheel force",
                            source=_SOURCE, series={"position": s, "value": q}))
        if ws.curvature is None:
            reason = "the file has no track frame series for this wheelset (&output groups 'track')"
            out.append(not_available("Y_qst", "N", reason, wheelset=ws.name, side=side, limit=YQST_LIMIT))
            out.append(not_available("Q_qst", "N", reason, wheelset=ws.name, side=side, limit=QQST_LIMIT))
        elif not sections:
            reason = "the wheelset ran through no circular curve"
            out.append(not_available("Y_qst", "N", reason, wheelset=ws.name, side=side, limit=YQST_LIMIT))
            out.append(not_available("Q_qst", "N", reason, wheelset=ws.name, side=side, limit=QQST_LIMIT))
        else:
            for name, signal, limit in (("Y_qst", y, YQST_LIMIT), ("Q_qst", q, QQST_LIMIT)):
                per_section = [(abs(percentile(signal[a:b], 50.0)), percentile(signal[a:b], 50.0),
                                0.5 * (s[a] + s[b - 1]), 1.0 / abs(ws.curvature[a])) for a, b in sections]
                _, value, pos, radius = max(per_section)
                out.append(Quantity(name, "N", value, limit, float(pos), ws.name, side,
                                    clause=f"EN 14363 track loading in curves: 50 % value over the "
                                           f"circular curve (R = {radius:.0f} m; "
                                           f"{len(sections)} curve section(s), the largest shown)",
                                    source=_SOURCE))
        unloading = (q0 - q) / q0
        k = int(np.argmax(unloading))
        out.append(Quantity("DeltaQ/Q", "1", float(unloading[k]), UNLOADING_LIMIT, float(s[k]),
                            ws.name, side,
                            clause=f"wheel unloading (Q0 - Q)/Q0, Q0 = {q0:.0f} N (EN 14363 / "
                                   "UIC 518 twist limit 0.6)",
                            source=_SOURCE, series={"position": s, "value": unloading}))
    return out
