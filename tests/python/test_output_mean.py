"""Interval-mean records (`&output mean_samples`): against the closed-form mean of an undamped
oscillator, against the trapezoid rule applied by the test to a dense run, no extra integrator
steps, and the same records when the C API advances in uneven pieces."""
import subprocess

import h5py
import numpy as np
import pytest

import raildyn


#: A 1-DOF lateral oscillator: 10 kg on a lateral spring of k = m (2 pi f)^2 with f = 3.16 Hz,
#: started at y = 0 with 0.02 m/s, so y(t) = (v0 / w) sin(w t).
MASS, STIFFNESS, V0 = 10.0, 3947.8417604357434, 0.02
OMEGA = np.sqrt(STIFFNESS / MASS)
#: Two runs of the deck (rtol 1e-10) whose integrator stop points differ agree to this
#: fraction of the amplitude (global error of ~1e3 steps).
INTEGRATION_AGREEMENT = 1e-7
DECK = """&simulation title = 'oscillator', t_end = 1.0, speed = 0.0, equilibrium = 'none' /
&solver method = 'bdf', rtol = 1e-10, atol = 1e-13, initial_step = 1e-4 /
&output file = '{file}', interval = {interval}, mean_samples = {samples} /
&segment type = 'straight', length = 100.0 /
&body name = 'b', mass = {mass}, ixx = 1.0, iyy = 1.0, izz = 1.0, position = 0.0, 0.0, 0.5,
      velocity = 0.0, {v0}, 0.0, frozen = 'x', 'z', 'yaw', 'roll', 'pitch' /
&element name = 'k', type = 'spring_damper', body1 = 'ground', body2 = 'b',
      point1 = 0.0, 0.0, 0.5, stiffness = 0.0, {k!r}, 0.0 /
"""


def write_deck(tmp_path, name, interval, samples):
    p = tmp_path / f"{name}.nml"
    p.write_text(DECK.format(file=f"{name}.h5", interval=interval, samples=samples, mass=MASS,
                             v0=V0, k=STIFFNESS))
    return p


def lateral(path):
    r = raildyn.Results(path)
    return r.time, r.get("bodies/b/position_track")[:, 1]


def run(exe, deck):
    res = subprocess.run([exe, "run", deck], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    return deck.with_suffix(".h5")


def test_records_are_the_interval_means_of_the_motion(raildyn_exe, tmp_path):
    h, n = 0.05, 20
    t, y = lateral(run(raildyn_exe, write_deck(tmp_path, "mean", h, n)))
    assert np.allclose(t, np.arange(21) * h)
    with h5py.File(tmp_path / "mean.h5") as f:
        assert f.attrs["output_mean_samples"] == n
    amp = V0 / OMEGA
    exact = amp * (np.cos(OMEGA * (t[1:] - h)) - np.cos(OMEGA * t[1:])) / (OMEGA * h)
    # composite trapezoid rule on a sine: error <= h_s^2 / 12 * max|y''| = amp (w h / n)^2 / 12
    bound = amp * (OMEGA * h / n) ** 2 / 12
    err = np.max(np.abs(y[1:] - exact))
    assert err <= 1.05 * bound, (err, bound)
    assert y[0] == 0.0                      # the first record is the initial state
    # the records are not samples: the state at the record times differs by far more
    sampled = amp * np.sin(OMEGA * t[1:])
    assert np.max(np.abs(sampled - exact)) > 100 * bound


def test_records_equal_the_trapezoid_means_of_a_dense_run(raildyn_exe, tmp_path):
    h, n = 0.05, 20
    _, y = lateral(run(raildyn_exe, write_deck(tmp_path, "mean", h, n)))
    _, yd = lateral(run(raildyn_exe, write_deck(tmp_path, "dense", h / n, 0)))
    means = [(0.5 * yd[n * (k - 1)] + yd[n * (k - 1) + 1:n * k].sum() + 0.5 * yd[n * k]) / n
             for k in range(1, len(y))]
    # the same motion sampled at the same times; the integrator stops exactly at each sample
    # (tstop), so the two step sequences differ and agree to the global integration error:
    # rtol = 1e-10 per step, 1e-7 of the amplitude allows 1e3 steps of accumulation
    assert np.max(np.abs(y[1:] - means)) < INTEGRATION_AGREEMENT * V0 / OMEGA


def test_sub_samples_cost_no_integrator_steps(raildyn_exe, tmp_path):
    """The integrator stops only at the run's end (the runner's horizon) and interpolates the
    records and the sub-samples, so a run with means takes exactly the steps of the same run writing samples
    (given the first step: CVODE estimates it from the first target time, a sub-sample or a
    record)."""
    stats = []
    for name, samples in (("samples", 0), ("means", 20)):
        path = run(raildyn_exe, write_deck(tmp_path, name, 0.05, samples))
        with h5py.File(path) as f:
            stats.append({k: int(f["meta/solver"].attrs[k]) for k in ("n_steps", "n_rhs")})
    assert stats[0] == stats[1]
    assert stats[0]["n_steps"] > 100


def test_uneven_advances_give_the_same_records(raildyn_exe, tmp_path):
    h, n = 0.05, 8
    t1, y1 = lateral(run(raildyn_exe, write_deck(tmp_path, "one", h, n)))
    deck = write_deck(tmp_path, "pieces", h, n)
    with raildyn.Model.from_file(deck) as m:
        m.initialize(write_output=True)
        for t in np.concatenate([np.cumsum(np.full(80, 0.0123)), [1.0]]):
            if t <= 1.0:
                m.advance(t)
        m.finalize()
    t2, y2 = lateral(deck.with_suffix(".h5"))
    assert np.array_equal(t1, t2)
    # the pieces add stop points of the integrator (see the dense-run test)
    assert np.allclose(y1, y2, rtol=0, atol=INTEGRATION_AGREEMENT * V0 / OMEGA)


def test_mean_samples_out_of_range_names_the_deck_line(raildyn_exe, tmp_path):
    deck = write_deck(tmp_path, "bad", 0.05, -1)
    res = subprocess.run([raildyn_exe, "run", deck], capture_output=True, text=True, timeout=60)
    assert res.returncode != 0
    assert "bad.nml:3" in res.stderr and "mean_samples" in res.stderr, res.stderr
