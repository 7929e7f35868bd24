"""Contact mechanics calculators of raildyn through ctypes (src/c_api/raildyn_calculators.h).

    >>> from raildyn.calculators import hertz, creep
    >>> hertz([1/0.46, 0.0, 0.0, 1/0.3], normal_force=100e3, young_modulus=210e9)["a"]
    >>> creep("fastsim", a=6e-3, b=4e-3, normal_force=50e3, xi=1e-3)

SI units; forces and spin moment on the wheel in contact-frame components, spin creepage in
1/m (docs/conventions.md). The shared library is the one ``raildyn.find_library`` finds
(``RAILDYN_LIB``, the build tree, or the installed library).
"""
import ctypes

from .model import find_library

__all__ = ["hertz", "creep", "CalculatorError", "HERTZ_WARNINGS"]

#: Warning bits of :func:`hertz` (``warning`` entry), see rd_hertz.f90.
HERTZ_WARNINGS = {
    1: "relative curvature along x clamped (conformal/concave)",
    2: "relative curvature along y clamped (conformal/concave)",
    4: "a/b outside [0.1, 10]",
    8: "NaN/Inf input",
}

_lib = None


class CalculatorError(ValueError):
    """Raised when the library refuses the input (status 1)."""


def _library():
    global _lib
    if _lib is not None:
        return _lib
    lib = ctypes.CDLL(find_library())
    d, i = ctypes.c_double, ctypes.c_int
    pd, pi = ctypes.POINTER(d), ctypes.POINTER(i)
    lib.rd_hertz_patch.argtypes = [d * 4, d, d, i, d, pd, pd, pd, pd, pd, pd, pi]
    lib.rd_hertz_patch.restype = i
    lib.rd_creep_forces.argtypes = [ctypes.c_char_p, d, d, d, d, d, d, d, d, d, i, pd, pd, pd]
    lib.rd_creep_forces.restype = i
    _lib = lib
    return lib


def hertz(curvatures, normal_force=None, penetration=None, young_modulus=2 * 82e9 * 1.28, poisson=0.28):
    """Hertz patch. ``curvatures`` = (kappa_wheel_x, kappa_wheel_y, kappa_rail_x, kappa_rail_y)
    [1/m], signed (convex > 0); give exactly one of ``normal_force`` [N] or ``penetration`` [m].
    Returns a dict with a, b [m] (a along the rolling direction), normal_force [N],
    approach [m], p0 [Pa], stiffness [N/m] and warning (bits, see HERTZ_WARNINGS)."""
    if (normal_force is None) == (penetration is None):
        raise CalculatorError("give exactly one of normal_force [N] or penetration [m]")
    if len(curvatures) != 4:
        raise CalculatorError("curvatures must hold 4 values (kxw, kyw, kxr, kyr) [1/m]")
    kind, load = (0, normal_force) if normal_force is not None else (1, penetration)
    out = [ctypes.c_double() for _ in range(6)]
    warning = ctypes.c_int()
    status = _library().rd_hertz_patch((ctypes.c_double * 4)(*curvatures), young_modulus, poisson, kind,
                                       load, *[ctypes.byref(o) for o in out], ctypes.byref(warning))
    if status != 0:
        raise CalculatorError("rd_hertz_patch refused the input (E > 0, 0 <= nu < 0.5, finite values)")
    keys = ("a", "b", "normal_force", "approach", "p0", "stiffness")
    result = {k: o.value for k, o in zip(keys, out)}
    result["warning"] = warning.value
    return result


def creep(law, a, b, normal_force, shear_modulus=82e9, poisson=0.28, friction=0.3,
          xi=0.0, eta=0.0, phi=0.0, grid=20):
    """Creep forces on the wheel by ``law`` ('linear', 'fastsim' or 'polach').
    Returns a dict with fx, fy [N] and mz [N m] in the contact frame."""
    fx, fy, mz = ctypes.c_double(), ctypes.c_double(), ctypes.c_double()
    status = _library().rd_creep_forces(law.encode(), a, b, normal_force, shear_modulus, poisson, friction,
                                        xi, eta, phi, int(grid), ctypes.byref(fx), ctypes.byref(fy),
                                        ctypes.byref(mz))
    if status != 0:
        raise CalculatorError(f"rd_creep_forces refused the input (law {law!r}: linear, fastsim or polach; "
                              "a, b > 0, N >= 0, G > 0, 0 <= nu <= 0.5, mu >= 0, finite values)")
    return {"fx": fx.value, "fy": fy.value, "mz": mz.value}
