"""Invariances of a dynamic scene (issue: multibody core, item 5; MOM6-style tests that need
no reference data), on the TGV 001 knife-edge bogie running through the transition into the
canted R 1000 m curve (inputs/tgv_bogie_curve.nml): stepping through the C API in many small
chunks equals one run; halving the output interval does not change the solution; splitting a
track segment into two identical halves changes nothing; a failing integration stops with a
clear message and keeps every step written so far."""
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import raildyn

REPO = Path(__file__).resolve().parents[2]
INPUTS = REPO / "inputs"
# base deck, shortened: from 2 s before the transition to 6 s into it (the transition starts at 1000 m)
BASE = f"""&include file = '{INPUTS / 'tgv_bogie_curve.nml'}' /
&simulation start_sigma = 960.0, t_end = 8.0 /
&solver rtol = 1e-8, atol = 1e-10 /
&output interval = {{interval}} /
"""
CHANNELS = ["bodies/ws1/position_track", "bodies/ws2/position_track",
            "bodies/bogie1/position_track", "bodies/ws1/velocity_track"]


def positions(model):
    return np.concatenate([model.output(c) for c in CHANNELS])


def scale(a):
    return max(1e-6, float(np.max(np.abs(a))))


def test_chunks_equal_one_run():
    one = raildyn.Model.from_string(BASE.format(interval=0.01), base_dir=str(INPUTS))
    one.initialize(write_output=False)
    one.advance(8.0)
    many = raildyn.Model.from_string(BASE.format(interval=0.01), base_dir=str(INPUTS))
    many.initialize(write_output=False)
    for t in np.linspace(0, 8.0, 801)[1:]:
        many.advance(float(t))
    a, b = positions(one), positions(many)
    # lateral motions are millimetres: agreement to the integration tolerance
    assert np.max(np.abs(a - b)) < 1e-6 * scale(a) + 1e-9, (a, b)
    assert abs(one.output("bodies/ws1/position_track")[1]) > 1e-4, "the bogie must move"
    one.close()
    many.close()


def run_file(tmp_path, text, name):
    deck = tmp_path / f"{name}.nml"
    deck.write_text(text)
    exe = Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")).resolve() / "bin" / "raildyn"
    res = subprocess.run([str(exe), "run", str(deck), "-o", str(tmp_path / f"{name}.h5")],
                         capture_output=True, text=True, timeout=300)
    return res, tmp_path / f"{name}.h5"


def test_halving_output_interval(tmp_path):
    r1, f1 = run_file(tmp_path, BASE.format(interval=0.02), "coarse")
    r2, f2 = run_file(tmp_path, BASE.format(interval=0.01), "fine")
    assert r1.returncode == 0 and r2.returncode == 0, r1.stderr + r2.stderr
    a, b = raildyn.Results(f1), raildyn.Results(f2)
    assert np.allclose(a.time, b.time[::2])
    for c in CHANNELS:
        ya, yb = a.get(c), b.get(c)[::2]
        # CVODE estimates its first step from the first output time, so the step sequences
        # differ: the runs agree to the global integration error (rtol = 1e-8 per step)
        assert np.max(np.abs(ya - yb)) < 1e-4 * scale(yb) + 1e-9, c


def test_records_cost_no_steps(tmp_path):
    """The scene interpolates its records (the integrator steps on to the advance target):
    with the first step given, halving the output interval leaves the step sequence as it
    is, so the steps and the records at the common times are the same bit for bit. (When
    the scene stopped the integrator at every record, the finer output took more steps.)"""
    deck = BASE.replace("atol = 1e-10 /", "atol = 1e-10, initial_step = 1e-4 /")
    assert deck != BASE
    r1, f1 = run_file(tmp_path, deck.format(interval=0.02), "coarse")
    r2, f2 = run_file(tmp_path, deck.format(interval=0.01), "fine")
    assert r1.returncode == 0 and r2.returncode == 0, r1.stderr + r2.stderr
    a, b = raildyn.Results(f1), raildyn.Results(f2)
    assert a.metadata["solver"]["n_steps"] == b.metadata["solver"]["n_steps"] > 100
    for c in CHANNELS:
        assert np.array_equal(a.get(c), b.get(c)[::2]), c


def test_chunks_cost_no_steps(tmp_path):
    """Nothing changes the inputs between advances, so neither `raildyn run` (which advances
    in chunks to show its progress) nor a C API caller's chunks stop the integrator: with
    the first step given, 800 C API chunks land bit for bit on the records of `raildyn run`
    at the same times. (When each advance stopped the integrator at its target, the chunks
    cut steps short and the runs differed at the tolerance.)"""
    deck = BASE.replace("atol = 1e-10 /", "atol = 1e-10, initial_step = 1e-4 /").format(interval=0.01)
    res, path = run_file(tmp_path, deck, "runner")
    assert res.returncode == 0, res.stderr
    records = raildyn.Results(path)
    times = np.asarray(records.time, float)
    many = raildyn.Model.from_string(deck, base_dir=str(INPUTS))
    many.initialize(write_output=False)
    checked = 0
    for k in range(1, times.size, 1):
        many.advance(float(times[k]))
        if k % 50 == 0 or k == times.size - 1:
            for c in CHANNELS:
                assert np.array_equal(many.output(c), records.get(c)[k]), (c, times[k])
            checked += 1
    assert checked >= 16 and abs(times[-1] - 8.0) < 1e-9
    many.close()


def test_split_segment_changes_nothing(tmp_path):
    """The designed track with its 200 m clothoid given as one segment, and the same track
    whose straight approach is cut into two halves; the clothoid cannot be split (a clothoid
    segment starts at the previous curvature), but the curve behind it can."""
    track = (INPUTS / "tracks" / "tgv_designed_track.nml").read_text()
    lines = [l for l in track.splitlines() if l.strip().startswith("&segment")]
    assert len(lines) >= 3
    straight = next(l for l in lines if "'straight'" in l)
    length = float(straight.split("length")[1].split("=")[1].split(",")[0].split("/")[0])
    half = straight.replace(f"{straight.split('length')[1].split('=')[1].split(',')[0].split('/')[0].strip()}",
                            repr(length / 2), 1)
    split_track = track.replace(straight, half + "\n" + half)
    (tmp_path / "tracks").mkdir()
    (tmp_path / "tracks" / "split.nml").write_text(split_track)
    (tmp_path / "tracks" / "whole.nml").write_text(track)
    vehicle = f"&include file = '{INPUTS / 'vehicles' / 'tgv001_bogie.nml'}' /\n"
    scene = (INPUTS / "tgv_bogie_curve.nml").read_text()
    scene = "\n".join(l for l in scene.splitlines()
                      if not l.startswith("&include") and not l.startswith("!"))
    (tmp_path / "scene.nml").write_text(vehicle + scene + "\n")
    results = []
    for name in ("whole", "split"):
        text = (f"&include file = 'tracks/{name}.nml' /\n&include file = 'scene.nml' /\n"
                "&simulation start_sigma = 960.0, t_end = 8.0 /\n&solver rtol = 1e-8, atol = 1e-10 /\n")
        res, path = run_file(tmp_path, text, name)
        assert res.returncode == 0, res.stderr
        results.append(raildyn.Results(path))
    for c in CHANNELS:
        a, b = results[0].get(c), results[1].get(c)
        assert np.max(np.abs(a - b)) < 1e-6 * scale(a) + 1e-9, c


def test_failing_integration_keeps_output(tmp_path):
    text = BASE.format(interval=0.01).replace("&solver rtol = 1e-8, atol = 1e-10 /",
                                              "&solver rtol = 1e-8, atol = 1e-10, max_num_steps = 5 /")
    res, path = run_file(tmp_path, text, "fails")
    assert res.returncode == 2, (res.returncode, res.stderr)
    lines = [l for l in res.stderr.splitlines() if l.strip()]
    assert len(lines) == 1 and "CV_TOO_MUCH_WORK" in lines[0] and "bdf" in lines[0], res.stderr
    r = raildyn.Results(path)
    assert r.metadata["status"].startswith("failed:")
    assert len(r.time) >= 1 and np.all(np.isfinite(r.get("bodies/ws1/position_track")))
    assert r.metadata["solver"]["n_steps"] > 0
