"""The bench scripts' code paths on short runs, so that a change of the package they import
breaks a test instead of the next published measurement (bench/fidelity_map/run.py broke
unnoticed once when raildyn.validation renamed a helper). Nothing is timed.

- bench/fidelity_map/run.py: two levels of the TGV knife-edge scene, shortened to 0.5 s, through
  the script's own `measure` (deck writing, the timed run, reading the series) and `compare`: a
  level compared with a run of itself differs by exactly 0 (the runs are deterministic); Polach
  against FASTSIM differs (different creep laws give different wheel forces); `render` turns the
  rows into the published table naming both levels and the comparison.
- bench/manchester_friction: run.py's `measure` on a short acceptance-deck run (steps, no
  window yet), its entry differences on two entry sets built from the package table (a 1 kN
  change of one force entry is 1 kN and 100 kN / S % of its family's scale), and cycle.py's
  `report` on the same results file.
- bench/jacobian_age/run.py: `measure_deck` on a short knife-edge run at two ages, and `render`.
- bench/compare_builds.py --scenes-only: a build against itself on a short deck.
- bench/extremes/rigid_track.py: `run_case` on the Manchester vehicle past its critical speed on
  rigid track, shortened to 0.7 s (the first lifts at 0.46 and 0.54 s): some samples with a wheel
  off its rail, every one of them at a flange hit at 0.85-1.0 of the tipping limit (the
  closed form of bench/extremes/tipping.py), and the same on flexible track without any; `render`
  names both cases.
- bench/solver_tolerance/run.py: its `measure` on the tables deck shortened to 0.3 s, at the
  deck's tolerances against the tight run: the sampled maxima equal those read from the file
  by raildyn.Results, the tight run compared with itself differs by 0 and the deck's run does
  not; `render` names both rows.
"""
import os
import sys
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np
import pytest

from conftest import load_script

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def fidelity_map():
    return load_script("bench/fidelity_map/run.py", "bench_fidelity_map_run")


@pytest.fixture(scope="module")
def friction():
    return load_script("bench/manchester_friction/run.py", "bench_manchester_friction_run")


def test_fidelity_map_measures_compares_and_renders(fidelity_map, build_dir, tmp_path):
    fm = fidelity_map
    exe = build_dir / "bin" / "raildyn"
    env = dict(os.environ, RAILDYN_CACHE_DIR=str(tmp_path / "cache"))
    scene = next(s for s in fm.scene_list() if s.key == "tgv_knife_edge")
    polach = next(lv for lv in scene.levels if lv.name == "knife edge polach")
    fastsim = next(lv for lv in scene.levels if lv.name == "knife edge fastsim")
    ref_row, ref = fm.measure(exe, tmp_path, scene, replace(polach, reference=True), 0.5, "ref", env, 600.0,
                              None, False)
    assert ref_row.outcome == "completed" and ref is not None, ref_row.notes
    assert ref_row.steps > 0 and ref_row.rhs > 0 and ref.t[-1] == pytest.approx(0.5)
    same, _ = fm.measure(exe, tmp_path, scene, polach, 0.5, "same", env, 600.0, ref, False)
    assert (same.err_y, same.err_force) == (0.0, 0.0), "a deterministic run differs from itself"
    other, _ = fm.measure(exe, tmp_path, scene, fastsim, 0.5, "other", env, 600.0, ref, False)
    assert other.outcome == "completed" and np.isfinite(other.err_force) and other.err_force > 0, other
    data = {"meta": {"label": "test", "quick": True, "commit": "test", "host": "test", "when": "test"},
            "rows": [asdict(r) for r in (ref_row, same, other)]}
    text = fm.render(data, tmp_path / "map.png")
    assert "knife edge polach" in text and "knife edge fastsim" in text, text


def test_fidelity_map_flags_a_stale_integrator_base(fidelity_map):
    """The integrators run on a declared level (Scene.integrator_base); a run in which another
    level is more than BASE_MARGIN faster says so in the base's notes, within it nothing."""
    fm = fidelity_map
    scene = next(s for s in fm.scene_list() if s.key == "manchester")
    levels = {lv.name: lv for lv in scene.levels}

    def row(name, cpu, outcome="completed"):
        return fm.Row(scene.key, levels[name], outcome=outcome, cpu=cpu)
    base = scene.integrator_base
    assert fm.stale_base_note([row(base, 0.6), row("table fastsim", 0.55), row("reference", 0.1)], base) == ""
    note = fm.stale_base_note([row(base, 0.9), row("table polach", 0.6), row("table fastsim", 0.7)], base)
    assert note.startswith("not the fastest level of this run: table polach took 0.6 CPU s against 0.9"), note
    # a faster run that did not complete does not count, nor does a base that did not complete
    assert fm.stale_base_note([row(base, 0.9), row("table polach", 0.1, "FAILURE")], base) == ""
    assert fm.stale_base_note([row(base, 0.9, "FAILURE"), row("table polach", 0.1)], base) == ""


def test_manchester_friction_measures(friction, build_dir, tmp_path):
    mf = friction
    deck = tmp_path / "short.nml"
    deck.write_text(f"&include file = '{REPO / 'inputs' / 'manchester_v1_tc1.nml'}' /\n"
                    "&simulation t_end = 0.3 /\n&output interval = 0.002 /\n")
    out = tmp_path / "short.h5"
    rc, cpu, wall = mf.run(build_dir / "bin" / "raildyn", deck, out, 600.0)
    assert rc == 0 and cpu > 0 and wall > 0
    m = mf.measure(out)
    assert m["t_end"] == pytest.approx(0.3) and m["steps"] > 0 and m["rhs"] > 0
    assert m["entries"] is None and m["notes"] == []      # the window is at 106-128.5 m
    entries = mf.V.load_package_table()
    a = {e.key: 1.0 for e in entries}
    force = next(e for e in entries if e.unit == "kN")
    b = dict(a, **{force.key: 1.0 + 1000.0})             # entries are SI: +1 kN
    worst = mf.entry_differences(a, b)
    assert worst["kN"] == pytest.approx(1.0) and worst["mm"] == 0 and worst["mrad"] == 0
    percent, key = mf.scale_differences(a, b)
    assert key == force.key
    assert percent == pytest.approx(100.0 * 1000.0 / mf.V.family_scales(entries)[force.quantity])
    cycle = load_script("bench/manchester_friction/cycle.py", "bench_manchester_friction_cycle")
    cycle.report(out, "short")      # reads wheelset 1's channels by the writer's names


def test_solver_tolerance_measures_and_renders(build_dir, tmp_path):
    st = load_script("bench/solver_tolerance/run.py", "bench_solver_tolerance_run")
    exe = build_dir / "bin" / "raildyn"
    env = dict(os.environ, RAILDYN_CACHE_DIR=str(tmp_path / "cache"))
    ref_row, ref, ref_max = st.measure(exe, tmp_path, env, "tables", "tight", st.TIGHT[1], None, t_end=0.3)
    assert ref_row.outcome == "completed" and ref is not None, ref_row.notes
    same, _, same_max = st.measure(exe, tmp_path, env, "tables", "tight again", st.TIGHT[1], ref, t_end=0.3)
    assert (same.err_y, same.err_force) == (0.0, 0.0) and same_max == ref_max
    deck_row, _, deck_max = st.measure(exe, tmp_path, env, "tables", "deck", "", ref, t_end=0.3)
    assert deck_row.outcome == "completed" and deck_row.steps < same.steps and deck_row.err_force > 0
    # the maxima against an independent reading of a file of the same run
    out = tmp_path / "deck.h5"
    deck = tmp_path / "deck.nml"
    deck.write_text(f"&include file = '{REPO / 'inputs' / 'manchester_v1_tc1_tables.nml'}' /\n"
                    "&simulation t_end = 0.3 /\n")
    import subprocess
    subprocess.run([str(exe), "run", str(deck), "-o", str(out), "--quiet"], env=env, check=True)
    import raildyn
    r = raildyn.Results(out)
    sides = [(w, s) for w in ("w1", "w2", "w3", "w4") for s in ("left", "right")]
    assert deck_max["max_q"] == max(float(np.max(r.get(f"wheelsets/{w}/{s}/wheel:force_vertical_Q")))
                                    for w, s in sides)
    assert deck_max["max_yq"] == max(float(np.max(r.get(f"wheelsets/{w}/{s}/wheel:Y_over_Q"))) for w, s in sides)
    assert deck_max["max_sum_y"] == max(float(np.max(np.abs(r.get(f"wheelsets/{w}/left/wheel:force_lateral_Y")
                                                            + r.get(f"wheelsets/{w}/right/wheel:force_lateral_Y"))))
                                        for w in ("w1", "w2", "w3", "w4"))
    rows = [dict(deck="tables", label=label, **st.row_fields(row), **m)
            for label, row, m in (("tight", ref_row, ref_max), ("deck", deck_row, deck_max))]
    text = st.render(rows, "test")
    assert "| tables | tight |" in text and "| tables | deck |" in text, text


def test_friction_energy_work_per_cycle(tmp_path):
    """bench/manchester_friction/energy.py on a synthetic results file with a closed form: a
    lateral cycle at 140 Hz, a flange patch whose lateral creepage fluctuates, eta = e0 + e1 sin,
    with a viscous creep force Fy = -c eta (longitudinal and spin zero): the creep work per
    cycle is -v c (e0^2 + e1^2 / 2) T and its part on the fluctuation -v c e1^2 T / 2; a normal
    force N = k delta (conservative: no loop work) and a height z = z1 sin (rate amplitude z1 w)."""
    import h5py
    en = load_script("bench/manchester_friction/energy.py", "bench_manchester_friction_energy")
    f_hz, v, c, e0, e1, k, z1 = 140.0, 4.4, 2.0e6, 1.0e-3, 2.0e-4, 1.0e9, 5.0e-5
    w = 2 * np.pi * f_hz
    t = np.arange(0.0, 0.2, 1.0 / (f_hz * 400))
    s = np.sin(w * t)
    pos = np.zeros((t.size, 6))
    pos[:, 1] = 1.0e-5 * s
    pos[:, 2] = z1 * s
    vel = np.zeros((t.size, 6))
    vel[:, 1] = 1.0e-5 * w * np.cos(w * t)
    patch = np.zeros((t.size, 23))
    patch[:, 0] = 2
    patch[:, 1] = 8.0e-5 + 1.0e-5 * s            # penetration
    patch[:, 2] = k * patch[:, 1]                 # normal force, a function of the penetration
    patch[:, 4] = e0 + e1 * s                     # eta
    patch[:, 7] = -c * patch[:, 4]                # Fy
    patch[:, 22] = v
    path = tmp_path / "synthetic.h5"
    with h5py.File(path, "w") as h:
        h["time"] = t
        h["bodies/ws1/position_track"] = pos
        h["bodies/ws1/velocity_track"] = vel
        for side in ("left", "right"):
            for j in range(1, 5):
                h[f"wheelsets/w1/{side}/patch{j}"] = patch if (side, j) == ("left", 1) else np.zeros_like(patch)
    r = en.analyse(path, 0.0, 0.2)
    period = 1.0 / f_hz
    assert r["frequency"] == pytest.approx(f_hz, rel=1e-3)
    left = r["wheels"]["left"]
    assert left["creep"] == pytest.approx(-v * c * (e0 ** 2 + e1 ** 2 / 2) * period, rel=1e-3)
    assert sum(left["creep_on_fluctuation"]) == pytest.approx(-v * c * e1 ** 2 / 2 * period, rel=1e-3)
    assert abs(left["normal_loop"]) < 1e-6 * k * 1e-5 * 1e-5
    assert r["z_rate_amplitude"] == pytest.approx(z1 * w, rel=1e-3)
    assert r["energy_scale"] == pytest.approx(0.5 * en.WHEELSET_MASS * (1.0e-5 * w) ** 2, rel=1e-3)
    assert r["wheels"]["right"]["creep"] == 0.0


def test_friction_energy_balance_per_coordinate(tmp_path):
    """bench/manchester_friction/energy.py's `balance` on a synthetic results file with closed
    forms: wheelset 1 oscillates laterally, y = A sin wt, its quasi-static height z = B sin(wt +
    p); the left wheel has one flange patch at a fixed contact angle g with the normal force N =
    N0 + N1 cos wt and a constant longitudinal creep force (x does not move: no work); the left
    primary element damps the lateral rate, F_y = -c dy/dt. Per cycle the normal force gives
    pi N1 A sin g to y and pi N1 B cos g cos p to z, the damper takes pi c A^2 w; the steady
    creep force and gravity (constant forces on periodic coordinates) give nothing; the wheel
    forces rebuilt from the patch equal the wheel series."""
    import h5py
    en = load_script("bench/manchester_friction/energy.py", "bench_manchester_friction_energy")
    f_hz, amp_y, amp_z, lag, n0, n1, gamma, damping = 140.0, 2.0e-5, 5.0e-5, 0.7, 6.0e4, 2.0e4, -1.0, 2.0e3
    w = 2 * np.pi * f_hz
    t = np.arange(0.0, 0.2, 1.0 / (f_hz * 400))
    pos = np.zeros((t.size, 6))
    pos[:, 1] = amp_y * np.sin(w * t)
    pos[:, 2] = 0.46 + amp_z * np.sin(w * t + lag)
    vel = np.zeros((t.size, 6))
    vel[:, 1] = amp_y * w * np.cos(w * t)
    patch = np.zeros((t.size, 23))
    patch[:, 0] = 2
    patch[:, 2] = n0 + n1 * np.cos(w * t)
    patch[:, 6] = 5.0e3
    patch[:, 11:14] = [0.0, 0.75, -0.46]
    patch[:, 17] = gamma
    wheel = np.zeros((t.size, 6))
    wheel[:, 2] = patch[:, 2] * np.sin(gamma)
    wheel[:, 3] = patch[:, 2] * np.cos(gamma)
    damper = np.zeros((t.size, 3))
    damper[:, 1] = -damping * vel[:, 1]
    path = tmp_path / "synthetic.h5"
    with h5py.File(path, "w") as h:
        h["time"] = t
        h["bodies/ws1/position_track"] = pos
        h["bodies/ws1/velocity_track"] = vel
        h["bodies/ws1/angles_fixed"] = np.zeros((t.size, 3))
        for side in ("left", "right"):
            h[f"wheelsets/w1/{side}/wheel"] = wheel if side == "left" else np.zeros_like(wheel)
            for j in range(1, 5):
                h[f"wheelsets/w1/{side}/patch{j}"] = patch if (side, j) == ("left", 1) else np.zeros_like(patch)
        h["elements/prim1l/force_fixed"] = damper
        h["elements/prim1r/force_fixed"] = np.zeros_like(damper)
    b = en.balance(path, 0.0, 0.2)
    normal, creep, susp = b["groups"]["left normal"], b["groups"]["left creep"], b["groups"]["suspension"]
    assert normal["y"] == pytest.approx(np.pi * n1 * amp_y * np.sin(gamma), rel=1e-3)
    assert normal["z"] == pytest.approx(np.pi * n1 * amp_z * np.cos(gamma) * np.cos(lag), rel=1e-3)
    assert susp["y"] == pytest.approx(-np.pi * damping * amp_y ** 2 * w, rel=1e-3)
    assert abs(creep["x"]) + abs(b["groups"]["gravity"]["z"]) < 1e-6 * abs(normal["y"])
    assert abs(b["kinetic"]["y"]) < 1e-3 * abs(normal["y"])
    assert b["residual"]["y"] == pytest.approx(normal["y"] + susp["y"], rel=1e-3)
    assert max(b["rebuild_error"].values()) < 1e-6
    assert "left normal" in en.render_balance(b)


def test_jacobian_age_measures_and_renders(build_dir, tmp_path):
    """bench/jacobian_age/run.py: `measure_deck` on the TGV knife-edge curve deck shortened to
    0.3 s at the default age and an old one: the default is the reference (no difference to
    itself: NaN), the old age evaluates fewer Jacobians and is compared with it (a finite
    difference; its size is test_solver_jacobian_age's, over 1 s); `render` lists both."""
    bench = load_script("bench/jacobian_age/run.py", "bench_jacobian_age")
    env = dict(os.environ, RAILDYN_CACHE_DIR=str(tmp_path / "cache"))
    rows = bench.measure_deck(build_dir / "bin" / "raildyn", tmp_path, env, "tgv knife-edge curve",
                              "tgv_vehicle_curve.nml", False, ages=[51, 1000], rounds=1, t_end=0.3)
    ref, old = rows
    assert (ref["age"], old["age"]) == (51, 1000)
    assert ref["outcome"] == old["outcome"] == "completed"
    assert not np.isfinite(ref["err_y"])
    assert 0 < old["jac"] < ref["jac"], (old, ref)
    assert np.isfinite(old["err_y"]) and np.isfinite(old["err_force"])
    text = bench.render(dict(rows=rows, cycles=[dict(age=51, cycle="skipped")], when="in a test"))
    assert "| tgv knife-edge curve | 51 |" in text and "| tgv knife-edge curve | 1000 |" in text


def test_compare_builds_scenes_only(build_dir):
    """bench/compare_builds.py --scenes-only: the same build on both sides, one round of a
    short deck, an environment variable for the after runs; the outputs must be reported
    identical (a build compared with itself) and nothing written (--no-write)."""
    import subprocess
    res = subprocess.run([sys.executable, str(REPO / "bench" / "compare_builds.py"), str(build_dir),
                          str(build_dir), "--scenes", "tgv_wheelset.nml", "--scenes-only", "--rounds", "1",
                          "--after-env", "RAILDYN_BENCH_PROBE=1", "--no-write"],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    row = [line for line in res.stdout.splitlines() if line.startswith("| tgv_wheelset.nml")]
    assert len(row) == 1 and "identical" in row[0], res.stdout
    assert "`RAILDYN_BENCH_PROBE=1`" in res.stdout


def test_rigid_track_study_measures_and_renders(build_dir, tmp_path):
    """bench/extremes/rigid_track.py: the rigid and the flexible quasi-static Manchester cases,
    0.7 s each."""
    bench = load_script("bench/extremes/rigid_track.py", "bench_rigid_track")
    exe = build_dir / "bin" / "raildyn"
    rigid, flexible = (bench.run_case(exe, tmp_path, i, case, t_end=0.7)
                       for i, case in enumerate([("manchester", "quasi_static", None, False),
                                                 ("manchester", "quasi_static", None, True)]))
    assert rigid["exit"] == flexible["exit"] == 0, (rigid, flexible)
    assert rigid["lost"] >= 2 and rigid["at_hit"] == rigid["lost"], rigid
    assert 0.85 <= rigid["ratio_min"] <= rigid["ratio_max"] <= 1.0, rigid
    assert flexible["lost"] == 0 and flexible["lost_share"] == 0.0, flexible
    text = bench.render([rigid, flexible], {"when": "in a test", "rev": "test"})
    assert "| Manchester V1, quasi-static, rigid track | 0 |" in text
    assert "| Manchester V1, quasi-static, flexible track | 0 |" in text
