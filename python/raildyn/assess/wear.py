"""Wear number T gamma and a rolling-contact-fatigue damage index, from the patch series of a
results file (docs/output.md: creepages ``xi``, ``eta`` and creep forces ``creep_force_x``,
``creep_force_y`` on the wheel, contact frame).

T gamma of a patch = |Fx xi| + |Fy eta| [N = J/m]: the energy the creep forces dissipate per
metre rolled (spin left out, as in the Whole Life Rail Model); T gamma of a wheel is the sum
over its patches (empty slots, kind 0, carry no force).

RCF damage index: the shape of Burstow's Whole-Life-Rail-Model damage function for R260 rail
(M. C. Burstow, "Whole Life Rail Model application and development for RSSB - continued
development of an RCF damage parameter", AEA Technology Rail report AEATR-ES-2004-880, 2004;
also in M. Burstow and J. Evans, Vehicle System Dynamics 44 suppl., 2006): no damage below
T gamma = 15 J/m, rising linearly to its largest value at 65 J/m, falling linearly to zero at
175 J/m where wear removes cracks faster than they grow. SECONDARY SOURCE, and raildyn reports
it normalised (1 = the function's peak): the absolute damage per axle passage of the report
could not be checked, so it is not reproduced (docs/assessment.md).
"""
from __future__ import annotations

import numpy as np

from .layout import SIDES, WheelsetData
from .quantity import Quantity, not_available

__all__ = ["patch_t_gamma", "rcf_damage_index", "wear_quantities", "RCF_ONSET", "RCF_PEAK",
           "RCF_END"]

RCF_ONSET, RCF_PEAK, RCF_END = 15.0, 65.0, 175.0     #: J/m (N)
_SOURCE_RCF = ("secondary: Burstow 2004 (AEATR-ES-2004-880) WLRM damage function shape, "
               "normalised (docs/assessment.md)")


def patch_t_gamma(patch: dict[str, np.ndarray]) -> np.ndarray:
    """T gamma [N] of one patch slot per row: |Fx xi| + |Fy eta|; 0 where the slot is empty."""
    tg = np.abs(patch["creep_force_x"] * patch["xi"]) + np.abs(patch["creep_force_y"] * patch["eta"])
    return np.where(patch["kind"] > 0, tg, 0.0)


def rcf_damage_index(t_gamma) -> np.ndarray:
    """Normalised WLRM RCF damage index of T gamma [N]: 0 below 15, 1 at 65, 0 from 175."""
    tg = np.asarray(t_gamma, float)
    rise = (tg - RCF_ONSET) / (RCF_PEAK - RCF_ONSET)
    fall = (RCF_END - tg) / (RCF_END - RCF_PEAK)
    return np.clip(np.where(tg <= RCF_PEAK, rise, fall), 0.0, None)


def wear_quantities(ws: WheelsetData) -> list[Quantity]:
    """Largest T gamma per patch slot that held a patch and per wheel, and the largest RCF index per wheel."""
    out: list[Quantity] = []
    s = ws.position
    for side in SIDES:
        patches = ws.patches.get(side) or []
        if not patches:
            reason = "the file has no patch series (wheelsets/<name>/<side>/patch<j>; &output groups 'patches')"
            out.append(not_available("T_gamma", "N", reason, wheelset=ws.name, side=side))
            out.append(not_available("RCF_index", "1", reason, wheelset=ws.name, side=side))
            continue
        per_patch = [patch_t_gamma(p) for p in patches]
        for j, (patch, tg) in enumerate(zip(patches, per_patch), start=1):
            if not np.any(patch["kind"] > 0):
                continue          # a slot no patch ever filled
            k = int(np.argmax(tg))
            out.append(Quantity("T_gamma", "N", float(tg[k]), None, float(s[k]), ws.name, side,
                                patch=j, clause="T gamma = |Fx xi| + |Fy eta| of patch slot "
                                f"{j} (largest over the run)",
                                source="wear number of the Whole Life Rail Model (Burstow 2004)"))
        wheel = np.sum(per_patch, axis=0)
        k = int(np.argmax(wheel))
        out.append(Quantity("T_gamma", "N", float(wheel[k]), None, float(s[k]), ws.name, side,
                            clause="T gamma of the wheel: sum over its patches (largest over the run)",
                            source="wear number of the Whole Life Rail Model (Burstow 2004)",
                            series={"position": s, "value": wheel}))
        damage = np.sum([rcf_damage_index(tg) for tg in per_patch], axis=0)
        k = int(np.argmax(damage))
        out.append(Quantity("RCF_index", "1", float(damage[k]), None, float(s[k]), ws.name, side,
                            clause="RCF damage index: WLRM damage function of each patch's "
                                   "T gamma, summed over the wheel's patches, normalised to the "
                                   "function's peak (largest over the run)",
                            source=_SOURCE_RCF, series={"position": s, "value": damage}))
    return out
