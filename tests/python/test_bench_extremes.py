"""bench/extremes/run.py (issue 14 item 5, stability at the extremes): three of the matrix's
cheapest rows run through the bench's own code path (scene deck + level overrides as a
raildyn.campaign, the measuring runner wrapper, the classifier), shortened to 0.7 s (--quick),
and the classifier's verdict checked against what each run must give:

- the TGV knife-edge vehicle on straight track at 8 m/s completes (exit 0, finite results, no
  contact loss);
- the same vehicle with a 150 kN m roll moment on wheelset 1 from 0.5 s stops on the lift-off
  limit (exit 3, reason "wheel lift-off"): the moment moves M / (2 b) of load between the wheels
  (b = 0.75 m), so 2 b Q = 1.5 m x 67.7 kN = 102 kN m unloads a wheel (Q = 55 240 kg g / 8); the
  wheel must lift, and 0.2 s is ample for 5 mm;
- a Manchester run at walking pace with Adams on tables with a CPU-time limit of 1 s (~15 CPU s
  for the quick 0.7 s) is stopped by the wrapper and classified as a hang (FAILURE);
- the two knife-edge rows again through the Slurm backend (one job array per campaign) on a
  real single-node Slurm: the same outcomes.

The matrix's levels are the fidelity map's (bench/fidelity_map/run.py), each with its deck
settings, and no others.

And the classifier on results it did not write: a completed run whose results hold a NaN, a
solver failure (exit 2) and an exit 3 without a documented reason are FAILUREs; a wheel without
contact is "contact loss" (with the run's largest Y/Q) where no load asks for it and the other
wheel's Y/Q is far from the closed-form tipping limit y_c / r of its contact
(bench/extremes/tipping.py), completed where it is at 0.85-1.0 of it (the wheelset tipped over
its flange contact) and in the lift-off scene; a lift-off found by the static equilibrium solve before t = 0 (exit 3) is a
FAILURE, not the scene's physics stop. Not timed: no CPU-second figure is asserted.
"""
import json
from pathlib import Path

import numpy as np
import pytest

from conftest import load_script

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def bench():
    return load_script("bench/extremes/run.py", "bench_extremes_run")


def test_scene_decks_are_those_the_script_writes(bench):
    """The tracked decks in bench/extremes/scenes are run.py's (a changed scene must be
    regenerated and committed, not only described)."""
    tracked = sorted((REPO / "bench" / "extremes" / "scenes").glob("*.nml"))
    expected = {}
    for v in bench.vehicles():
        for s in bench.scenes_for(v):
            if all(s.key in lv.not_for for lv in v.levels):
                continue
            expected[f"{v.key}__{s.key}.nml"] = bench.scene_deck_text(v, s)
    assert sorted(p.name for p in tracked) == sorted(expected)
    for p in tracked:
        assert p.read_text() == expected[p.name], p.name


def test_matrix_levels_are_the_maps(bench):
    """Item 5 asks the matrix for every fidelity level of the map: each level of each map scene
    (bench/fidelity_map/run.py), the reference and the integrators on the scene's fastest level
    included, is a level of the matrix's vehicle of that model, with the same deck settings
    (read here token by token from the map's text), and the matrix has no level the map lacks.
    The map's knife-edge scene runs the TGV vehicle with S1002/60E1 too: those levels are the
    TGV profile vehicle's. The study forms of the strip normal force (centroid, potential) are
    not fidelity levels (docs/performance.md "Which fidelity level for what")."""
    fm = bench.fidelity_map
    matrix = {v.key: {lv.name: lv for lv in v.levels} for v in bench.vehicles()}
    seen = {key: set() for key in matrix}

    def same(settings: str, got: dict, drop=()):
        tokens = [t.split("=") for t in settings.split(",") if t.strip()]
        want = {k.strip(): v.strip() for k, v in tokens if k.strip() not in drop}
        assert set(got) == set(want), (settings, got)
        for k, v in want.items():
            if v.startswith("'"):
                assert got[k] == v.strip("'"), (k, got[k], v)
            else:
                assert isinstance(got[k], (int, float)) and got[k] == float(v), (k, got[k], v)

    for sc in fm.scene_list():
        for ml in sc.levels + fm.integrator_levels(sc):
            assert "strip_normal_force" not in ml.wheelset, ml.name
            profile = sc.key == "tgv_knife_edge" and "contact = 'profile'" in ml.wheelset
            key = "tgv_profile" if profile else sc.key
            assert ml.name in matrix[key], (sc.key, ml.name)
            lv = matrix[key][ml.name]
            same(ml.wheelset, lv.wheelset, ("contact", "wheel_profile", "rail_profile") if profile else ())
            same(ml.solver, lv.solver)
            seen[key].add(ml.name)
    assert {k: set(v) for k, v in matrix.items()} == seen
    assert any(n.endswith(", rk4 1e-4 s") for n in seen["tgv_profile"])


#: the two knife-edge rows the runs below make (quick: 0.7 s)
KNIFE_EDGE_ROWS = ["tgv_knife_edge:base:knife edge polach", "tgv_knife_edge:lift_off:knife edge polach"]


def check_knife_edge_rows(rows, lines):
    """On straight track at 8 m/s: completed; with the 150 kN m roll moment from 0.5 s: the
    lift-off stop before 0.7 s."""
    by_scene = {r.scene: r for r in rows}
    assert set(by_scene) == {"base", "lift_off"}, lines
    ok, stop = by_scene["base"], by_scene["lift_off"]
    assert (ok.outcome, ok.reason, ok.expected) == ("completed", "", True), lines
    assert ok.steps > 0 and ok.rhs > 0 and ok.cpu > 0 and ok.t_reached == pytest.approx(0.7)
    assert stop.outcome == "physics stop" and stop.expected, lines
    assert "wheel lift-off" in stop.reason and 0.5 < stop.t_reached < 0.7, stop.reason


def test_matrix_rows_classified(bench, build_dir, tmp_path, monkeypatch):
    monkeypatch.setenv("RAILDYN_CACHE_DIR", str(tmp_path / "cache"))
    lines = []
    rows = bench.run_matrix(build_dir, tmp_path / "w", 1, "local", [], True,
                            KNIFE_EDGE_ROWS, 600.0, 300, progress=lines.append)
    check_knife_edge_rows(rows, lines)
    # the hang: a CPU-time limit the run cannot meet. A scene near 1 CPU s would make this test
    # depend on the machine's speed: R 80 m on 0.1 mm strips, chosen first, took 0.98 CPU s for
    # the quick 0.7 s once the contact got cheaper (2026-11-29). Walking pace with Adams on
    # tables took 65.8 CPU s for 3 s in the published matrix (docs/performance.md; table
    # fastsim then, the integrators' base), ~15 for 0.7 s
    rows = bench.run_matrix(build_dir, tmp_path / "h", 1, "local", [], True,
                            ["manchester:walk:table linear+SHE, adams"], 600.0, 1, progress=lines.append)
    assert len(rows) == 1 and rows[0].outcome == "FAILURE", lines
    assert rows[0].reason.startswith("hang: still running at the CPU-time limit of 1 s"), rows[0].reason
    assert not rows[0].expected


def test_matrix_rows_on_slurm(bench, build_dir, tmp_path, monkeypatch, slurm):
    """The matrix's Slurm backend (`run.py --backend slurm`: one job array per campaign) on a real
    single-node Slurm (the `slurm` fixture): the two knife-edge rows of the local test above
    end as they do locally - completed, and the lift-off stop - measured by the same wrapper."""
    monkeypatch.setenv("RAILDYN_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("SLURM_CONF", slurm["SLURM_CONF"])
    lines = []
    rows = bench.run_matrix(build_dir, tmp_path / "w", 2, "slurm", [], True,
                            KNIFE_EDGE_ROWS, 600.0, 300, progress=lines.append)
    check_knife_edge_rows(rows, lines)
    # the runs went through Slurm: each campaign's job array and its task's log
    for scene in ("base", "lift_off"):
        camp = tmp_path / "w" / "quick" / "tgv_knife_edge" / scene / "knife_edge_polach"
        assert (camp / "campaign.sbatch").is_file() and list(camp.glob("slurm-*_0.out")), sorted(camp.iterdir())


def _run_folder(path: Path, exit_code: int, log: str = "") -> Path:
    path.mkdir(parents=True)
    (path / "status.json").write_text(json.dumps({"exit_code": exit_code}))
    (path / "measure.json").write_text(json.dumps({"cpu": 1.0, "wall": 1.0, "timed_out": "", "limit": 60,
                                                   "cpu_limit": 60, "exit": exit_code}))
    (path / "log.txt").write_text(log)
    return path


def test_classifier_on_hand_made_runs(bench, tmp_path):
    from conftest import write_layout_file
    scene = bench.Scene("base", "straight", "straight", 8.0)
    t = np.linspace(0.0, 1.0, 11)
    y = np.zeros((11, 1))
    series = {"bodies/ws1/position_track": (y, "m", "y", "lateral shift")}
    meta = {"status": "completed", "end_time": 1.0}
    solver = {"n_steps": np.int64(10), "n_rhs": np.int64(20), "n_rhs_jacobian": np.int64(5)}

    good = _run_folder(tmp_path / "good", 0)
    write_layout_file(good / "results.h5", t, series, meta_attrs=meta, solver=solver)
    row = bench.classify(good, scene)
    assert (row.outcome, row.steps, row.rhs, row.rhs_jac) == ("completed", 10, 20, 5)

    bad = _run_folder(tmp_path / "nan", 0)
    y_nan = y.copy()
    y_nan[6, 0] = np.nan
    write_layout_file(bad / "results.h5", t, {"bodies/ws1/position_track": (y_nan, "m", "y", "lateral shift")},
                      meta_attrs=meta, solver=solver)
    row = bench.classify(bad, scene)
    assert row.outcome == "FAILURE" and "non-finite value at t = 0.6 s" in row.reason, row.reason

    # the left wheel of w1 off its rail at t = 0.3 s with the right one on its flange face
    # (contact point 0.711 m from the centre, 0.473 m below it: tipping limit Y/Q = 1.503) at
    # Y/Q 0.2 (a lift the tipping does not explain) and at 1.45 (0.965 of the limit: tipped)
    def lost_run(name, right_yq):
        folder = _run_folder(tmp_path / name, 0)
        yq = np.zeros((11, 2))
        yq[3, 0] = right_yq
        wheel_comp = "n_patches force_longitudinal force_lateral_Y force_vertical_Q Y_over_Q max_penetration"
        patch_comp = ("kind penetration normal_force xi eta spin creep_force_x creep_force_y spin_moment s_wheel "
                      "u_rail wheel_point_x wheel_point_y wheel_point_z rail_point_x rail_point_y rail_point_z "
                      "contact_angle rolling_radius semi_axis_a semi_axis_b hertz_warning reference_speed")
        wheels = {}
        for side, sign in (("left", 1.0), ("right", -1.0)):
            w = np.tile([1.0, 0.0, 0.0, 55.0e3, 0.0, 1.0e-4], (11, 1))
            pa = np.zeros((11, 23))
            pa[:, 0], pa[:, 2], pa[:, 12], pa[:, 13] = 1.0, 55.0e3, sign * 0.75, -0.46
            if side == "left":
                w[3] = 0.0
                pa[3] = 0.0
            else:
                w[3] = [1.0, 0.0, right_yq * 100.0e3, 100.0e3, right_yq, 2.0e-4]
                pa[3, 2], pa[3, 12], pa[3, 13] = 100.0e3, -0.711, -0.473
            wheels[f"wheelsets/w1/{side}/wheel"] = (w, "1 N N N 1 m", wheel_comp, "")
            wheels[f"wheelsets/w1/{side}/patch1"] = (pa, "", patch_comp, "")
            for j in (2, 3, 4):
                wheels[f"wheelsets/w1/{side}/patch{j}"] = (np.zeros((11, 23)), "", patch_comp, "")
        write_layout_file(folder / "results.h5", t,
                          {**series, **wheels,
                           "wheelsets/w1/summary": (yq, "1 N", "derailment_quotient guiding_force_sum", "")},
                          solver=solver, meta_attrs={**meta, "notes": "wheelset w1 left wheel without contact in "
                                                                      "9.1 % of 11 output samples"})
        return folder

    lost = lost_run("lost", 0.2)
    row = bench.classify(lost, scene)
    assert (row.outcome, row.expected) == ("contact loss", False)
    assert row.reason.startswith("largest Y/Q 0.20; 1 of 1 wheel-samples off the rail not at the tipping limit; "
                                 "wheelset w1 left wheel without contact"), row.reason
    tipped = bench.classify(lost_run("tipped", 1.45), scene)
    assert (tipped.outcome, tipped.expected) == ("completed", True)
    assert "tipping over the flange contact in 1 wheel-samples, the other wheel at 0.96-0.96" in tipped.reason, \
        tipped.reason
    lift = bench.Scene("lift_off", "lift", "straight", 2.0, contact_loss_expected=True, expect="lift-off")
    assert bench.classify(lost, lift).outcome == "completed"
    assert not bench.classify(lost, lift).expected   # completed where a lift-off stop was due

    solver_failure = _run_folder(tmp_path / "solver", 2, "raildyn: error: scene: integrator 'bdf' (CVODE BDF) "
                                 "failed advancing to 1.0E-01 s (time reached 9.0E-02 s, last step h = 1.0E-12 s): "
                                 "CV_CONV_FAILURE (flag -4): CVODE: ...; rhs at t = 9.0E-02 s: quasi-static normal "
                                 "contact did not converge\n")
    row = bench.classify(solver_failure, scene)
    assert row.outcome == "FAILURE" and row.reason.startswith("solver failure (exit 2): bdf CV_CONV_FAILURE at t = 0.09 s")
    stop = _run_folder(tmp_path / "stop", 3, "raildyn: error: scene: ...; rhs at t = 5.1E-01 s: multibody%rhs: "
                       "wheelset contact 1, left wheel, t = 5.1E-01 s: derailment: contact point beyond the flange tip\n")
    row = bench.classify(stop, bench.Scene("flange_climb", "climb", "r80_in", 2.0, expect="derail|lift-off"))
    assert (row.outcome, row.expected) == ("physics stop", True) and row.reason.startswith("wheelset contact 1")
    # a lift-off found by the static equilibrium solve at rest: the scene never ran
    static = _run_folder(tmp_path / "static", 3, "raildyn: error: scenes/s.nml:4: &simulation 'equilibrium': "
                         "static positions: multibody%rhs: wheelset contact 1, left wheel, t = 0.00000E+00 s: "
                         "wheel lift-off: gap 5.00000E-03 m exceeds the limit 5.00000E-03 m\n")
    row = bench.classify(static, bench.Scene("flange_climb", "climb", "r80_in", 2.0, expect="derail|lift-off"))
    assert (row.outcome, row.expected) == ("FAILURE", False)
    assert row.reason.startswith("static equilibrium (exit 3 before the run): static positions: "), row.reason
    odd = _run_folder(tmp_path / "odd", 3, "raildyn: error: something else\n")
    assert bench.classify(odd, scene).outcome == "FAILURE"


def test_keep_published_round_trip(bench):
    """--keep-published: a published table read back gives its rows (outcome, counts, CPU, t,
    reason, 'as expected'); a partial rerun keeps the published rows it did not rerun, marked,
    and its own rows replace the published ones."""
    v = bench.vehicles()[0]
    s = bench.scenes_for(v)
    rows = [bench.Row(v.key, s[0].key, v.levels[0].name, "completed", "", 10, 20, 5, 1.5, 2.0, 3.0, True),
            bench.Row(v.key, s[3].key, v.levels[1].name, "FAILURE", "solver failure (exit 2): a / b", 7, 8, 9, 0.4,
                      0.5, 2.28, False)]
    text = bench.render(rows, {"when": "when", "source": "source"})
    got = bench.published_rows(text)
    assert set(got) == {(r.vehicle, r.scene, r.level) for r in rows}
    for r in rows:
        g = got[(r.vehicle, r.scene, r.level)]
        assert (g.outcome, g.steps, g.rhs, g.rhs_jac, g.cpu, g.t_reached, g.expected, g.kept) == \
            (r.outcome, r.steps, r.rhs, r.rhs_jac, r.cpu, r.t_reached, r.expected, True)
        assert g.reason == r.reason
    rerun = [bench.Row(v.key, s[3].key, v.levels[1].name, "completed", "", 70, 80, 90, 2.0, 2.0, 6.7, True),
             bench.Row(v.key, s[0].key, v.levels[1].name, "not run", "no status.json in the run folder")]
    full = bench.keep_published(rerun, got)
    by = {(r.vehicle, r.scene, r.level): r for r in full}
    assert len(full) == sum(len(bench.scenes_for(w)) * len(w.levels) for w in bench.vehicles())
    assert by[(v.key, s[3].key, v.levels[1].name)].outcome == "completed"
    assert not by[(v.key, s[3].key, v.levels[1].name)].kept
    assert by[(v.key, s[0].key, v.levels[0].name)].kept
    assert by[(v.key, s[0].key, v.levels[1].name)].outcome == "not run"
    again = bench.published_rows(bench.render(full, {"when": "when", "source": "source"}))
    assert (v.key, s[0].key, v.levels[0].name) in again and again[(v.key, s[0].key, v.levels[0].name)].kept
    assert "(earlier run)" in bench.render(full, {"when": "when", "source": "source"})
