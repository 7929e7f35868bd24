"""T gamma and the RCF damage index of raildyn.assess.wear, by hand."""
import numpy as np
import pytest

from raildyn.assess.wear import patch_t_gamma, rcf_damage_index


def test_t_gamma_of_one_patch_by_hand():
    """Fx = -1000 N at xi = 0.002 and Fy = 3000 N at eta = -0.004: T gamma = 2 + 12 = 14 N;
    an empty slot (kind 0) counts nothing whatever it holds."""
    patch = {"kind": np.array([1.0, 2.0, 0.0]), "creep_force_x": np.array([-1000.0, 500.0, -1000.0]),
             "xi": np.array([0.002, -0.01, 0.002]), "creep_force_y": np.array([3000.0, 0.0, 3000.0]),
             "eta": np.array([-0.004, 0.3, -0.004])}
    np.testing.assert_allclose(patch_t_gamma(patch), [14.0, 5.0, 0.0])


@pytest.mark.parametrize("t_gamma, index", [(0.0, 0.0), (15.0, 0.0), (40.0, 0.5), (65.0, 1.0),
                                            (120.0, 0.5), (175.0, 0.0), (300.0, 0.0)])
def test_rcf_damage_function_shape(t_gamma, index):
    """Burstow's WLRM function normalised: 0 up to 15 N, peak 1 at 65 N, 0 again from 175 N."""
    assert rcf_damage_index([t_gamma])[0] == pytest.approx(index, abs=1e-12)
