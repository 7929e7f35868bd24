"""The closed-form tipping limit of a wheelset on one wheel's contact, read from a results file
(bench/extremes/run.py's classifier and bench/extremes/rigid_track.py).

Take moments about the loaded wheel's contact point of the forces that act at the wheelset
centre (weight and suspension, vertical resultant W, at the lateral distance y_c of that point
from the centre; the lateral forces that hold the wheelset against the flange, resultant F, at
the point's depth r below the centre): the other wheel keeps a load while F r < W y_c, and with
it off the rail the contact carries Q = W and Y = F, so it lifts at

    Y / Q = y_c / r = |wheel_point_y| / |wheel_point_z| of the loaded patch

(1.50-1.55 on the flange face of an S1002 wheel). The suspension's roll moment and the contact
forces' own moments move the point by a few per cent; tests/python/test_quasi_static_tipping.py
checks the lifts of a hunting wheelset against it.
"""
from __future__ import annotations

import numpy as np

#: a lifted wheel counts as tipped where the other wheel's Y/Q is within this share of its limit
TIPPING_SHARE = (0.85, 1.0)


def wheel_series(f, ws: str, side: str):
    """(lost, Y/Q, tipping limit y_c / r of the most loaded patch) per output sample of one wheel."""
    wheel = f[f"wheelsets/{ws}/{side}/wheel"][()]
    patches = np.stack([f[f"wheelsets/{ws}/{side}/patch{j}"][()] for j in range(1, 5)])
    comp = f[f"wheelsets/{ws}/{side}/patch1"].attrs["components"]
    comp = (comp.decode() if isinstance(comp, bytes) else str(comp)).split()
    iy, iz, inf = comp.index("wheel_point_y"), comp.index("wheel_point_z"), comp.index("normal_force")
    loaded = patches[np.argmax(patches[:, :, inf], axis=0), np.arange(patches.shape[1])]
    limit = np.abs(loaded[:, iy]) / np.maximum(np.abs(loaded[:, iz]), 1e-9)
    return wheel[:, 0] == 0, wheel[:, 4], limit


def lift_ratios(f) -> np.ndarray:
    """For every output sample and wheel without contact: the other wheel's Y/Q over its tipping
    limit (a wheel whose partner is also off the rail gives 0)."""
    out = []
    for ws in f["wheelsets"]:
        s = {side: wheel_series(f, ws, side) for side in ("left", "right")}
        for side, other in (("left", "right"), ("right", "left")):
            lost = s[side][0]
            lost_other, yq, limit = s[other]
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = yq[lost] / limit[lost]
            out += list(np.where(lost_other[lost], 0.0, ratio))
    return np.array(out)


def all_tipped(ratios: np.ndarray) -> bool:
    """Every lift is the wheelset tipping over its other wheel's contact (and there is one)."""
    lo, hi = TIPPING_SHARE
    return ratios.size > 0 and bool(np.all((ratios >= lo) & (ratios <= hi)))
