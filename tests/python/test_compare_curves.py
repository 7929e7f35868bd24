"""raildyn.compare on synthetic curves with known answers: |a - b| <= rtol*range(b) + atol."""

import numpy as np
import pytest

from raildyn import Results, compare_curves, compare_results, plot_failures


def test_equal_curves_pass_with_zero_error():
    t = np.linspace(0, 2 * np.pi, 201)
    c = compare_curves(t, np.sin(t), t, np.sin(t), rtol=1e-6, atol=0.0)
    assert c.passed
    assert c.max_normalized_error == 0.0
    assert c.reference_range == pytest.approx(2.0, abs=1e-3)


def test_offset_beyond_and_within_tolerance():
    t = np.linspace(0, 2 * np.pi, 2001)
    b = np.sin(t)
    rng = b.max() - b.min()
    bad = compare_curves(t, b + 0.02 * rng, t, b, rtol=0.01, atol=0.0)
    assert not bad.passed
    assert bad.max_normalized_error == pytest.approx(2.0, rel=1e-12)   # 0.02 rng / 0.01 rng
    assert bad.max_abs_error == pytest.approx(0.02 * rng, rel=1e-12)
    good = compare_curves(t, b + 0.005 * rng, t, b, rtol=0.01, atol=0.0)
    assert good.passed
    assert good.max_normalized_error == pytest.approx(0.5, rel=1e-12)


def test_time_shift_fails_where_the_slope_is_largest():
    t = np.linspace(0, 2 * np.pi, 20001)
    b = np.sin(t)
    a = np.sin(t - 0.05)       # a lag of 0.05 s: |a - b| <= 2 sin(0.025) ~ 0.05
    c = compare_curves(t, a, t, b, rtol=1e-2, atol=0.0)
    assert not c.passed
    assert c.max_abs_error == pytest.approx(2 * np.sin(0.025), rel=1e-4)
    # max of |sin(t - d) - sin t| = 2 sin(d/2) |cos(t - d/2)|: at t = d/2 (+ k pi)
    assert min(abs(c.time_of_max - 0.025 - k * np.pi) for k in range(3)) < 1e-3


def test_localised_spike_is_located():
    t = np.linspace(0, 3, 3001)
    b = t ** 2
    a = b.copy()
    a[1234] += 1.0
    c = compare_curves(t, a, t, b, rtol=1e-3, atol=0.0)
    assert not c.passed
    assert c.time_of_max == pytest.approx(t[1234], abs=1e-12)
    assert c.max_abs_error == pytest.approx(1.0)


def test_different_time_bases_linear_is_exact():
    """Linear interpolation reproduces a straight line, so different grids agree."""
    ta = np.linspace(0.0, 2.0, 201)
    tb = np.arange(0.0, 2.0 + 1e-12, 0.037)
    c = compare_curves(ta, 3 * ta + 1, tb, 3 * tb + 1, rtol=1e-12, atol=0.0)
    assert c.passed, c
    # only the overlap [0, tb[-1]] counts
    assert c.reference_range == pytest.approx(3 * tb[-1], rel=1e-12)


def test_different_time_bases_interpolation_error_bound():
    """Coarse reference of sin with step h: interpolation error <= h^2/8 max|f''| = h^2/8."""
    h = 0.1
    ta = np.linspace(0, 2 * np.pi, 6284)
    tb = np.arange(0, 2 * np.pi, h)
    c_pass = compare_curves(ta, np.sin(ta), tb, np.sin(tb), rtol=0.0, atol=h ** 2 / 8)
    assert c_pass.passed
    assert c_pass.max_abs_error > 0.5 * h ** 2 / 8      # the bound is nearly reached
    c_fail = compare_curves(ta, np.sin(ta), tb, np.sin(tb), rtol=0.0, atol=0.25 * h ** 2 / 8)
    assert not c_fail.passed


def test_constant_channel_zero_range():
    t = np.linspace(0, 1, 11)
    b = np.full_like(t, 5.0)
    assert compare_curves(t, b.copy(), t, b, rtol=1e-3, atol=0.0).passed
    tiny = compare_curves(t, b + 1e-13, t, b, rtol=1e-3, atol=1e-12)
    assert tiny.passed and tiny.reference_range == 0.0 and tiny.tolerance == 1e-12
    off = compare_curves(t, b + 1e-9, t, b, rtol=1e-3, atol=1e-12)
    assert not off.passed
    assert off.max_normalized_error == pytest.approx(1e3, rel=1e-3)
    zero_tol = compare_curves(t, b + 1e-9, t, b, rtol=1e-3, atol=0.0)
    assert not zero_tol.passed and zero_tol.max_normalized_error == np.inf


def test_no_overlap_and_nan_fail():
    t = np.linspace(0, 1, 11)
    c = compare_curves(t, t, t + 5, t)
    assert not c.passed and "overlap" in c.note
    a = t.copy()
    a[3] = np.nan
    c = compare_curves(t, a, t, t)
    assert not c.passed and "non-finite" in c.note


def _two_runs(make_results_file, y_offset=0.0, drop=False):
    t = np.linspace(0, 1, 101)
    pose = np.column_stack([20 * t, 0.003 * np.sin(6 * t), 0.46 + 0 * t])
    force = np.column_stack([1e4 * np.cos(3 * t), 7.5e4 + 0 * t])
    ref = {"bodies/car/position_track": (pose, "m", "x y z", ""),
           "wheelsets/ws1/left/contact_force": (force, "N", "fy fz", "")}
    b = make_results_file("ref.h5", t, ref)
    tt = np.linspace(0, 1, 73)           # the test run has another output grid
    pose_t = np.column_stack([20 * tt, 0.003 * np.sin(6 * tt) + y_offset, 0.46 + 0 * tt])
    force_t = np.column_stack([1e4 * np.cos(3 * tt), 7.5e4 + 0 * tt])
    test = {"bodies/car/position_track": (pose_t, "m", "x y z", "")}
    if not drop:
        test["wheelsets/ws1/left/contact_force"] = (force_t, "N", "fy fz", "")
    a = make_results_file("test.h5", tt, test)
    return a, b


def test_compare_results_reports_the_failing_channel(make_results_file, tmp_path):
    a, b = _two_runs(make_results_file, y_offset=1e-4)
    report = compare_results(a, b, rtol=1e-3, atol=1e-9)
    failed = [c.channel for c in report.failed()]
    assert failed == ["bodies/car/position_track:y"]
    y = report["bodies/car/position_track:y"]
    assert y.unit == "m"
    # range(y_ref) ~ 0.006 m (the sampled sine); offset 1e-4 -> ~ 1e-4 / (1e-3 * 0.006) ~ 17
    assert 15 < y.max_normalized_error < 18
    assert report["wheelsets/ws1/left/contact_force:fz"].passed   # constant channel
    assert "FAIL" in report.summary() and "4 of 5 channels pass" in report.summary()
    # per-channel tolerances by pattern
    loose = compare_results(a, b, rtol={"*:y": 0.05, "*": 1e-3}, atol=1e-9)
    assert loose.passed, loose.summary()
    # plots of the failures only
    files = plot_failures(report, a, b, tmp_path / "plots")
    assert len(files) == 1
    with open(files[0], "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_compare_results_missing_channel_and_selection(make_results_file):
    a, b = _two_runs(make_results_file, drop=True)
    report = compare_results(Results(a), Results(b), rtol=1e-3, atol=1e-9)
    missing = [c for c in report.failed()]
    assert [c.channel for c in missing] == ["wheelsets/ws1/left/contact_force:fy",
                                            "wheelsets/ws1/left/contact_force:fz"]
    assert all("missing in test run" in c.note for c in missing)
    only = compare_results(a, b, channels=["bodies/car/position_track"], rtol=1e-3, atol=1e-9)
    assert only.passed and len(only.channels) == 3
    one = compare_results(a, b, channels=["bodies/car/position_track:x"])
    assert [c.channel for c in one.channels] == ["bodies/car/position_track:x"]
