"""T gamma and the RCF index (surface fatigue index FI_surf) of raildyn.assess.wear, by hand."""
import numpy as np
import pytest

from raildyn.assess.wear import patch_surface_fatigue_index, patch_t_gamma, surface_fatigue_index


def test_t_gamma_of_one_patch_by_hand():
    """Fx = -1000 N at xi = 0.002 and Fy = 3000 N at eta = -0.004: T gamma = 2 + 12 = 14 N;
    an empty slot (kind 0) counts nothing whatever it holds."""
    patch = {"kind": np.array([1.0, 2.0, 0.0]), "creep_force_x": np.array([-1000.0, 500.0, -1000.0]),
             "xi": np.array([0.002, -0.01, 0.002]), "creep_force_y": np.array([3000.0, 0.0, 3000.0]),
             "eta": np.array([-0.004, 0.3, -0.004])}
    np.testing.assert_allclose(patch_t_gamma(patch), [14.0, 5.0, 0.0])


def test_surface_fatigue_index_by_hand():
    """Ekberg, Kabo & Andersson (2002): FI_surf = f - 2 pi a b k / (3 Fz). Fz = 100 kN on an
    ellipse a = 6 mm, b = 4 mm, Fx = 20 kN, Fy = -15 kN, k = 300 MPa:
    f = 25 kN / 100 kN = 0.25; 2 pi (6e-3)(4e-3)(3e8) / (3e5) = 0.048 pi = 0.1507964;
    FI_surf = 0.0992036."""
    fi = surface_fatigue_index(20e3, -15e3, 100e3, 6e-3, 4e-3, 300e6)
    assert fi == pytest.approx(0.25 - 0.048 * np.pi, rel=1e-12)
    assert fi == pytest.approx(0.0992036, abs=5e-8)


def test_surface_fatigue_index_is_the_distance_above_shakedown():
    """The same index read off the shakedown map: the Hertz peak pressure p0 = 3 Fz / (2 pi a b)
    (the peak of the Hertz ellipsoidal pressure, computed here on its own) and the full-slip shakedown limit
    p0 / k = 1 / f: FI_surf = f - k / p0 is > 0 exactly above the limit."""
    fz, a, b, k = 80e3, 7e-3, 5e-3, 350e6
    p0 = 3 * fz / (2 * np.pi * a * b)
    for f in (0.2, k / p0, 0.5):
        fi = surface_fatigue_index(f * fz, 0.0, fz, a, b, k)
        assert fi == pytest.approx(f - k / p0, abs=1e-14)
        assert (fi > 1e-12) == (p0 / k > 1 / f * (1 + 1e-9))


def test_patch_index_of_empty_or_unloaded_slots_is_nan():
    """A slot without a patch (kind 0) or without normal force has no index (NaN), whatever its
    columns hold; a loaded slot gives the formula's value."""
    patch = {"kind": np.array([1.0, 0.0, 2.0]), "creep_force_x": np.array([0.0, 5e3, 1e3]),
             "creep_force_y": np.array([4e3, 5e3, 0.0]), "normal_force": np.array([40e3, 40e3, 0.0]),
             "semi_axis_a": np.array([5e-3, 5e-3, 5e-3]), "semi_axis_b": np.array([5e-3, 5e-3, 5e-3])}
    fi = patch_surface_fatigue_index(patch, 300e6)
    assert fi[0] == pytest.approx(0.1 - 2 * np.pi * 25e-6 * 300e6 / 120e3, rel=1e-12)
    assert np.isnan(fi[1]) and np.isnan(fi[2])
