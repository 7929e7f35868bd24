"""Sliding means, rms values and percentiles of raildyn.assess.windows against closed forms."""
import numpy as np
import pytest

from raildyn.assess.windows import WindowError, block_rms, percentile, sliding_mean, sliding_rms


def test_constant():
    s = np.linspace(0.0, 50.0, 201)
    c, m = sliding_mean(s, np.full_like(s, 3.5), 2.0)
    assert c[0] == pytest.approx(1.0) and c[-1] == pytest.approx(49.0)
    np.testing.assert_allclose(m, 3.5, rtol=1e-14)


def test_step_gives_a_ramp_over_the_window():
    """A unit step at s0: the 2 m mean rises linearly from s0 - 1 to s0 + 1 (exact for samples
    that hold the step between two of them, as the linear interpolant does)."""
    s = np.arange(0.0, 40.0 + 1e-9, 0.1)
    s0 = 20.05                                  # between two samples: interpolant ramps over 0.1 m
    y = (s > s0).astype(float)
    c, m = sliding_mean(s, y, 2.0)
    expected = np.clip((c - s0 + 1.0) / 2.0, 0.0, 1.0)
    np.testing.assert_allclose(m, expected, atol=1e-12 + 0.1 / 8)    # the 0.1 m interpolation ramp
    far = np.abs(c - s0) > 1.1
    np.testing.assert_allclose(m[far], expected[far], atol=1e-12)


@pytest.mark.parametrize("wavelength", [1.5, 3.0, 10.0, 25.0])
def test_sine_is_scaled_by_the_window_sinc(wavelength):
    """mean over [s - L/2, s + L/2] of sin(2 pi s / lambda) = sinc(L / lambda) sin(2 pi s / lambda),
    sinc(x) = sin(pi x) / (pi x); trapezoid error of the sampled sine O((2 pi h / lambda)^2 / 12)."""
    h = 0.002
    s = np.arange(0.0, 60.0 + 1e-9, h)
    c, m = sliding_mean(s, np.sin(2 * np.pi * s / wavelength), 2.0)
    x = 2.0 / wavelength
    expected = np.sin(np.pi * x) / (np.pi * x) * np.sin(2 * np.pi * c / wavelength)
    np.testing.assert_allclose(m, expected, atol=2 * (2 * np.pi * h / wavelength) ** 2 / 12)


def test_uneven_sampling_and_standstill():
    """Samples closer in one place, a standstill (repeated position) in another: the mean is
    an integral along the track, so both leave the result of a linear signal exact."""
    s = np.concatenate([np.linspace(0, 10, 11), np.full(5, 10.0), np.linspace(10.01, 20, 1000)])
    y = 2.0 * s + 1.0
    c, m = sliding_mean(s, y, 4.0)
    np.testing.assert_allclose(m, 2.0 * c + 1.0, rtol=1e-12)


def test_rms_of_a_sine_over_whole_periods():
    t = np.arange(0.0, 20.0 + 1e-9, 0.001)
    c, r = sliding_rms(t, 3.0 * np.sin(2 * np.pi * 2.0 * t), 5.0, unit="s")
    np.testing.assert_allclose(r, 3.0 / np.sqrt(2.0), rtol=1e-5)


def test_block_rms():
    """Consecutive 5 s blocks of a sine whose amplitude is k in block k: rms k / sqrt(2)."""
    fs = 100.0
    t = np.arange(0, int(50 * fs) + 1) / fs
    amplitude = np.minimum(np.floor(t / 5.0) + 1, 10)
    ends, r = block_rms(t, amplitude * np.sin(2 * np.pi * 1.0 * t), 5.0)
    np.testing.assert_allclose(ends, 5.0 * np.arange(1, 11))
    np.testing.assert_allclose(r, np.arange(1, 11) / np.sqrt(2.0), rtol=2e-3)


def test_windows_refuse_short_or_backward_data():
    with pytest.raises(WindowError, match="shorter than the 2 m window"):
        sliding_mean([0.0, 1.0, 1.5], [1, 2, 3], 2.0)
    with pytest.raises(WindowError, match="backwards"):
        sliding_mean([0.0, 2.0, 1.0, 5.0], [1, 2, 3, 4], 2.0)


def test_percentile_nearest_rank():
    v = np.random.default_rng(1).permutation(np.arange(1, 101))
    assert percentile(v, 95) == 95 and percentile(v, 50) == 50 and percentile(v, 100) == 100
    assert percentile(v, 99.85) == 100 and percentile(np.arange(1, 61), 95) == 57


def test_percentiles_of_known_distributions():
    """Exponential (quantile -ln(1 - p)) and arcsine (a sine sampled evenly in phase:
    quantile A sin(pi (p - 1/2))) distributions, sampled by their quantile function."""
    n = 200000
    u = (np.arange(n) + 0.5) / n
    rng = np.random.default_rng(7)
    exponential = rng.permutation(-np.log(1.0 - u))
    sine = 2.0 * np.sin(2 * np.pi * np.arange(n) / n)
    for p in (50.0, 95.0, 99.85):
        assert percentile(exponential, p) == pytest.approx(-np.log(1 - p / 100), rel=1e-3)
        assert percentile(sine, p) == pytest.approx(2.0 * np.sin(np.pi * (p / 100 - 0.5)), abs=1e-3)
