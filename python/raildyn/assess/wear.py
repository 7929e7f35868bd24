"""Wear number T gamma and a rolling-contact-fatigue index, from the patch series of a results
file (docs/output.md: creepages ``xi``, ``eta``, creep forces ``creep_force_x``,
``creep_force_y`` on the wheel, contact frame; ``normal_force``; Hertz semi-axes
``semi_axis_a``, ``semi_axis_b``).

T gamma of a patch = |Fx xi| + |Fy eta| [N = J/m]: the energy the creep forces dissipate per
metre rolled (spin left out, as in the Whole Life Rail Model: M. C. Burstow, AEA Technology
Rail report AEATR-ES-2004-880, 2004; SECONDARY SOURCE, the definition as the wear literature
quotes it). T gamma of a wheel is the sum over its patches (empty slots, kind 0, carry no force).

RCF index: the surface fatigue index of A. Ekberg, E. Kabo and H. Andersson, "An engineering
model for prediction of rolling contact fatigue of railway wheels", Fatigue & Fracture of
Engineering Materials & Structures 25 (2002) 899-909, a shakedown criterion for
surface-initiated fatigue:

    FI_surf = f - 2 pi a b k / (3 F_z),    f = sqrt(F_x^2 + F_y^2) / F_z

with f the traction coefficient of the patch, a and b the semi-axes of its Hertz ellipse,
F_z its normal force and k the yield limit in pure shear of the (work-hardened) material.
3 F_z / (2 pi a b) is the Hertz peak pressure p0, so FI_surf = f - k / p0: the distance of the
patch's load point (f, p0 / k) above the shakedown limit p0 / k = 1 / f of the shakedown map
for full slip (Johnson's shakedown diagram, high traction branch). FI_surf > 0 predicts
surface-initiated RCF, a larger value faster crack initiation; it says nothing about wear,
which may remove the cracks (T gamma above). The formula is quoted from the paper as the
literature reproduces it (SECONDARY SOURCE; docs/assessment.md). k = 300 MPa by default is
raildyn's choice (the material must be set for an assessment: ``shear_yield``).
"""
from __future__ import annotations

import numpy as np

from .layout import SIDES, WheelsetData
from .quantity import Quantity, not_available

__all__ = ["patch_t_gamma", "surface_fatigue_index", "patch_surface_fatigue_index",
           "wear_quantities", "SHEAR_YIELD_DEFAULT"]

SHEAR_YIELD_DEFAULT = 300e6     #: Pa, k of FI_surf (raildyn's default, docs/assessment.md)
_SOURCE_TG = "secondary: wear number of the Whole Life Rail Model (Burstow 2004) as quoted in the literature"
_SOURCE_RCF = ("secondary: surface fatigue index FI_surf of Ekberg, Kabo & Andersson, Fatigue "
               "Fract. Engng Mater. Struct. 25 (2002) 899-909, as quoted in the literature; "
               "k raildyn's (docs/assessment.md)")


def patch_t_gamma(patch: dict[str, np.ndarray]) -> np.ndarray:
    """T gamma [N] of one patch slot per row: |Fx xi| + |Fy eta|; 0 where the slot is empty."""
    tg = np.abs(patch["creep_force_x"] * patch["xi"]) + np.abs(patch["creep_force_y"] * patch["eta"])
    return np.where(patch["kind"] > 0, tg, 0.0)


def surface_fatigue_index(fx, fy, fz, a, b, shear_yield: float = SHEAR_YIELD_DEFAULT) -> np.ndarray:
    """FI_surf = sqrt(fx^2 + fy^2)/fz - 2 pi a b k / (3 fz) (Ekberg, Kabo & Andersson 2002);
    forces [N], semi-axes [m], k = ``shear_yield`` [Pa]. NaN where fz <= 0 (no contact)."""
    fx, fy, fz, a, b = (np.asarray(v, float) for v in (fx, fy, fz, a, b))
    with np.errstate(divide="ignore", invalid="ignore"):
        fi = (np.hypot(fx, fy) - 2.0 * np.pi * a * b * shear_yield / 3.0) / fz
    return np.where(fz > 0, fi, np.nan)


def patch_surface_fatigue_index(patch: dict[str, np.ndarray],
                                shear_yield: float = SHEAR_YIELD_DEFAULT) -> np.ndarray:
    """FI_surf of one patch slot per row; NaN where the slot is empty or carries no load."""
    fi = surface_fatigue_index(patch["creep_force_x"], patch["creep_force_y"], patch["normal_force"],
                               patch["semi_axis_a"], patch["semi_axis_b"], shear_yield)
    return np.where(patch["kind"] > 0, fi, np.nan)


def wear_quantities(ws: WheelsetData, shear_yield: float = SHEAR_YIELD_DEFAULT) -> list[Quantity]:
    """Largest T gamma per patch slot that held a patch and per wheel, and the largest
    surface fatigue index per wheel."""
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
                                f"{j} (largest over the run)", source=_SOURCE_TG))
        wheel = np.sum(per_patch, axis=0)
        k = int(np.argmax(wheel))
        out.append(Quantity("T_gamma", "N", float(wheel[k]), None, float(s[k]), ws.name, side,
                            clause="T gamma of the wheel: sum over its patches (largest over the run)",
                            source=_SOURCE_TG, series={"position": s, "value": wheel}))
        fi = np.array([patch_surface_fatigue_index(p, shear_yield) for p in patches])
        loaded = np.any(np.isfinite(fi), axis=0)
        if not loaded.any():
            out.append(not_available("RCF_index", "1", "no patch of this wheel carried a normal force",
                                     wheelset=ws.name, side=side))
            continue
        worst = np.full(s.shape, np.nan)
        worst[loaded] = np.nanmax(fi[:, loaded], axis=0)
        k = int(np.nanargmax(worst))
        out.append(Quantity("RCF_index", "1", float(worst[k]), None, float(s[k]), ws.name, side,
                            clause="surface fatigue index FI_surf = f - 2 pi a b k / (3 Fz) of the "
                                   f"wheel's worst patch, k = {shear_yield / 1e6:g} MPa (largest "
                                   "over the run; > 0: surface-initiated RCF predicted)",
                            source=_SOURCE_RCF, series={"position": s[loaded], "value": worst[loaded]}))
    return out
