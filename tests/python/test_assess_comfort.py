"""N_MV and Cc of raildyn.assess.comfort on synthetic accelerations with known answers."""
import numpy as np
import pytest

from raildyn.assess.comfort import continuous_comfort, mean_comfort
from raildyn.assess.filters import weighting_response
from raildyn.assess.windows import WindowError


def _weighted_rms(name, f, amplitude):
    return amplitude * abs(weighting_response(name, [f])[0]) / np.sqrt(2.0)


def test_n_mv_of_steady_sines():
    """x 0.3 m/s^2 at 1 Hz, y 0.4 at 2 Hz, z 0.5 at 4 Hz for 5 min: every 5 s rms value is the
    weighted amplitude / sqrt(2) (the switch-on transient touches the first block only, and
    the 95 % value of 60 blocks leaves out the 3 largest), N_MV = 6 sqrt(sum of squares)."""
    fs = 100.0
    t = np.arange(int(300 * fs) + 1) / fs
    ax, ay, az = 0.3 * np.sin(2 * np.pi * t), 0.4 * np.sin(4 * np.pi * t), 0.5 * np.sin(8 * np.pi * t)
    n_mv, t_end, p95 = mean_comfort(t, ax, ay, az)
    expected = {"x": _weighted_rms("Wd", 1.0, 0.3), "y": _weighted_rms("Wd", 2.0, 0.4),
                "z": _weighted_rms("Wb", 4.0, 0.5)}
    for d in "xyz":
        assert p95[d] == pytest.approx(expected[d], rel=1e-4)
    assert n_mv == pytest.approx(6 * np.sqrt(sum(v**2 for v in expected.values())), rel=1e-4)
    assert t_end == pytest.approx(300.0)


def test_n_mv_takes_the_95_percent_value_of_the_blocks():
    """Block k (1..60) carries amplitude k/10 at 2 Hz laterally: the 95 % value of the 60 block
    rms values is that of block 57 (nearest rank)."""
    fs = 100.0
    t = np.arange(int(300 * fs) + 1) / fs
    block = np.minimum(np.floor(t / 5.0), 59)
    ay = (block + 1) / 10 * np.sin(4 * np.pi * t)
    zero = np.zeros_like(t)
    n_mv, _, p95 = mean_comfort(t, zero, ay, zero)
    # each amplitude change makes a short filter transient: 0.2 % of a block's rms
    assert p95["y"] == pytest.approx(_weighted_rms("Wd", 2.0, 5.7), rel=2e-3)
    assert n_mv == pytest.approx(6 * p95["y"], rel=1e-12)


def test_n_mv_needs_five_minutes():
    t = np.arange(0, 100.0, 0.01)
    with pytest.raises(WindowError, match="N_MV is taken over 300 s periods"):
        mean_comfort(t, t * 0, t * 0, t * 0)


def test_continuous_comfort_of_a_steady_sine():
    """Cc_z(t) = rms of the Wb-weighted acceleration over the preceding 5 s: once the switch-on
    transient has died out (20 s) it is the weighted amplitude / sqrt(2) (32 whole periods in 5 s)."""
    fs = 200.0
    t = np.arange(int(40 * fs) + 1) / fs
    az = 0.8 * np.sin(2 * np.pi * 6.4 * t)
    times, cc = continuous_comfort(t, 0 * t, 0 * t, az)["z"]
    assert times[0] == pytest.approx(5.0) and times[-1] == pytest.approx(40.0)
    late = times >= 25.0
    np.testing.assert_allclose(cc[late], _weighted_rms("Wb", 6.4, 0.8), rtol=1e-3)
