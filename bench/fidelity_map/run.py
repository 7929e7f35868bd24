#!/usr/bin/env python3
"""The fidelity map (issue 14 item 3): for each scene, every modelling level that applies -
knife-edge contact, contact tables, online strips at two spacings, each with the linear,
Polach and FASTSIM (smooth clip) laws, elastic against quasi-static normal contact, and the
integrators on the scene's fastest level - run one after the other (the machine has 2 shared cores),
each measured by its CPU seconds (user + system of the runner process, less exposed to the
other jobs of a shared machine than the wall time), steps and right-hand-side calls, and its
error against the scene's reference level (the finest online model at tight tolerances).

Errors:
- Manchester acceptance scene: the 32 window entries of the validation rule (thesis tables
  5.9-5.11, window means over the quasi-static window), |level - reference| in % of the
  entry's family scale S (raildyn.validation: load_package_table, family_scales,
  manchester_window_times, manchester_window_values); the level's own verdict of the rule
  (raildyn.validation.manchester_acceptance) is shown next to it.
- Every scene (Manchester too): the largest difference over the run of the wheelsets' lateral
  shift, and of the wheel forces Y and Q, each relative to the reference's range of that
  quantity over all wheelsets / wheels.

A level that fails (solver failure, physics-limit stop, time-out) is a row with its outcome.
Writes a table into docs/performance.md (section fidelity_map), a Pareto plot (CPU seconds
against error) into docs/fidelity_map.png, the same tables into validation/fidelity_map.json
(the validation report's section "Fidelity map", raildyn.validation.fidelity_map), and every
measured row into a JSON file (--json, default <build>/fidelity_map/map.json; --from-json
rewrites the docs from it without running anything, e.g. after a run was cut short).

    python3 bench/fidelity_map/run.py [--build DIR] [--quick] [--scenes manchester tgv_profile tgv_knife_edge]
        [--timeout S] [--json FILE] [--from-json FILE] [--no-write]

The build is --build, else $RAILDYN_BUILD_DIR, else <repo>/build. Contact tables are cached
in <work dir>/cache ($RAILDYN_CACHE_DIR is set for the runs); each scene's table is built once
by a short warm-up run before its table levels (its cost is reported as its own row), so the
table levels are measured with the table cached, as a campaign would run them. --quick runs
shorter scenes (the Manchester window is then not reached: only the shift/force errors).
"""
import argparse
import json
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
#: the published map for the validation report (raildyn.validation.fidelity_map)
PUBLISHED = REPO / "validation" / "fidelity_map.json"
sys.path.insert(0, str(REPO / "python"))
import raildyn  # noqa: E402
from raildyn import validation as V  # noqa: E402
from raildyn.executable import EXIT_OUTCOMES, RESULTS_READABLE  # noqa: E402

#: FASTSIM with the smooth clip (docs/theory_contact_mechanics.md): the acceptance deck's law.
FASTSIM = "creep_law = 'fastsim', fastsim_saturation_width = 0.2"
#: Profile levels: the linear law with Shen-Hedrick-Elkins saturation (the decks set a friction
#: coefficient, which the unsaturated linear law does not read and raildyn refuses; unsaturated,
#: a flange patch's creep force would be unbounded). The knife-edge decks use the unsaturated law.
LAWS = {"linear+SHE": "creep_law = 'linear', creep_saturation = 'shen_hedrick_elkins'",
        "polach": "creep_law = 'polach'", "fastsim": FASTSIM}
KNIFE_LAWS = {"linear": "creep_law = 'linear'", "polach": "creep_law = 'polach'", "fastsim": FASTSIM}
#: Profile contact on the knife-edge TGV vehicle: S1002 on 60E1 at the track's 1:40, as the
#: TGV profile scene (inputs/tgv_profile_fastsim.nml) puts on the same vehicle.
PROFILE = "contact = 'profile', wheel_profile = 's1002', rail_profile = '60e1'"
STRIPS_FINE = "contact_geometry = 'strips', strip_spacing = 1.0e-4"
STRIPS = "contact_geometry = 'strips'"
TABLE = "contact_geometry = 'table'"
ELASTIC = "normal_contact = 'elastic', contact_damping = 2.0e5"
#: Reference integration: CVODE BDF, rtol 100 times tighter than the decks' 1e-5, and one atol of
#: 1e-10 for coordinates and rates (the Manchester deck gives its rates 1e-5 m/s).
REFERENCE_SOLVER = "method = 'bdf', rtol = 1e-7, atol = 1e-10, atol_velocity = 1e-10"
#: Integrators run on the scene's fastest level (Scene.integrator_base), at the deck's
#: tolerances; rk4 at the deck default step.
INTEGRATORS = [("adams", "method = 'adams', max_order = 0"), ("erk", "method = 'erk'"),
               ("rk4 1e-4 s", "method = 'rk4', fixed_step = 1e-4")]


@dataclass
class Level:
    name: str                 #: row label
    contact: str              #: knife edge / table / strips 0.2 mm / strips 0.1 mm
    law: str
    normal: str               #: elastic / quasi-static
    integrator: str
    wheelset: str = ""        #: &wheelset settings applied to every wheelset
    solver: str = ""          #: &solver settings
    reference: bool = False


@dataclass
class Row:
    scene: str
    level: Level
    outcome: str = ""
    cpu: float = float("nan")
    wall: float = float("nan")
    t_end: float = float("nan")
    steps: int = 0
    rhs: int = 0
    rhs_jac: int = 0
    err_y: float = float("nan")       #: % of the reference's range
    err_force: float = float("nan")   #: % of the reference's range (max of Y and Q)
    err_entries: float = float("nan")  #: largest entry difference, % of its family's S
    err_entry: str = ""
    err_entries_median: float = float("nan")
    rule: str = ""                    #: the level's own verdict of the Manchester rule
    err_base: float = float("nan")    #: integrator rows: largest error against the level under BDF
    notes: list = field(default_factory=list)


@dataclass
class Scene:
    key: str
    deck: str
    title: str
    levels: list
    quick_t_end: float
    manchester: bool = False
    #: normal contact of the deck (the levels' default)
    normal: str = "elastic"
    #: the level the integrators run on: the scene's fastest. Declared, not picked by the
    #: run's CPU seconds: the table levels (and the knife-edge laws) are within the shared
    #: machine's noise of each other (Manchester 0.6-0.7 CPU s, TGV profile 1.7-2.0, knife edge
    #: 2.2-3.3 on 62ab550), a pick by measurement changed from run to run, and the extremes
    #: matrix (bench/extremes/run.py) runs the integrators on the same level. A run in which
    #: another level is more than BASE_MARGIN faster notes it on the base's row.
    integrator_base: str = ""


def integrator_levels(scene: Scene, base_name: str | None = None) -> list[Level]:
    """The integrator levels of a scene: its integrator base (or the level `base_name`) under
    each of INTEGRATORS (the deck's tolerances stay; adams gets its own default order
    (max_order 0), erk and rk4 read no max_order)."""
    base = next(lv for lv in scene.levels if lv.name == (base_name or scene.integrator_base))
    return [Level(f"{base.name}, {label}", base.contact, base.law, base.normal, label, base.wheelset, solver)
            for label, solver in INTEGRATORS]


def scene_list():
    def grid(contacts, laws, normal):
        return [Level(f"{c} {law}", c, law, normal, "bdf", f"{w}, {LAWS[law]}") for c, w in contacts for law in laws]

    qs = "quasi-static"
    man = grid([("table", TABLE), ("strips 0.2 mm", STRIPS), ("strips 0.1 mm", STRIPS_FINE)],
               list(LAWS), qs)
    # elastic normal contact with the TGV 001 decks' contact damping (2e5 N s/m,
    # inputs/vehicles/tgv001_bogie.nml's ASSUMPTION; the extremes matrix's elastic level):
    # undamped, the wheels' ~180 Hz mode on the Hertz contact rings after every flange contact
    man += [Level("table fastsim elastic", "table", "fastsim", "elastic", "bdf",
                  f"{TABLE}, {FASTSIM}, {ELASTIC}", "max_order = 0"),
            Level("strips 0.2 mm fastsim elastic", "strips 0.2 mm", "fastsim", "elastic", "bdf",
                  f"{STRIPS}, {FASTSIM}, {ELASTIC}", "max_order = 0"),
            Level("reference", "strips 0.1 mm", "fastsim", qs, "bdf rtol 1e-7",
                  f"{STRIPS_FINE}, {FASTSIM}", REFERENCE_SOLVER, reference=True)]
    tgv = grid([("table", TABLE), ("strips 0.2 mm", STRIPS), ("strips 0.1 mm", STRIPS_FINE)],
               list(LAWS), "elastic")
    tgv += [Level("table fastsim quasi-static", "table", "fastsim", qs, "bdf",
                  f"{TABLE}, {FASTSIM}, normal_contact = 'quasi_static'"),
            Level("reference", "strips 0.1 mm", "fastsim", "elastic", "bdf rtol 1e-7",
                  f"{STRIPS_FINE}, {FASTSIM}", REFERENCE_SOLVER, reference=True)]
    knife = [Level(f"knife edge {law}", "knife edge", law, "elastic", "bdf", setting)
             for law, setting in KNIFE_LAWS.items()]
    knife += [Level("table fastsim", "table", "fastsim", "elastic", "bdf", f"{PROFILE}, {TABLE}, {FASTSIM}"),
              Level("strips 0.2 mm fastsim", "strips 0.2 mm", "fastsim", "elastic", "bdf",
                    f"{PROFILE}, {STRIPS}, {FASTSIM}"),
              Level("reference", "strips 0.1 mm", "fastsim", "elastic", "bdf rtol 1e-7",
                    f"{PROFILE}, {STRIPS_FINE}, {FASTSIM}", REFERENCE_SOLVER, reference=True)]
    return [Scene("manchester", "manchester_v1_tc1.nml", "Manchester V1 TC1 (acceptance deck), 22.5 s",
                  man, 4.0, manchester=True, normal=qs, integrator_base="table linear+SHE"),
            Scene("tgv_profile", "tgv_profile_fastsim.nml", "TGV 001 vehicle, S1002/UIC60, 25.6 m/s, 18 s",
                  tgv, 3.0, integrator_base="table fastsim quasi-static"),
            Scene("tgv_knife_edge", "tgv_vehicle_curve.nml", "TGV 001 vehicle, knife edge, into R 1000 m, 25 s",
                  knife, 5.0, integrator_base="knife edge polach")]


def write_deck(tmp: Path, scene: Scene, level: Level, t_end: float | None, tag: str) -> Path:
    """A deck that includes the scene's deck and overrides its wheelsets and solver."""
    deck = REPO / "inputs" / scene.deck
    lines = [f"! fidelity map: {scene.key} / {level.name}", f"&include file = '{deck}' /"]
    if t_end is not None:
        lines.append(f"&simulation t_end = {t_end} /")
    if level.wheelset:
        for w in V.deck_wheelsets(deck):
            lines.append(f"&wheelset name = '{w}', {level.wheelset} /")
    if level.solver:
        lines.append(f"&solver {level.solver} /")
    path = tmp / f"{scene.key}__{tag}.nml"
    path.write_text("\n".join(lines) + "\n")
    return path


def run_timed(exe: Path, deck: Path, out: Path, env: dict, timeout: float):
    """(exit status or None on time-out, stderr, CPU s, wall s) of one `raildyn run`."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    try:
        res = subprocess.run([str(exe), "run", str(deck), "-o", str(out), "--quiet"],
                             capture_output=True, text=True, env=env, timeout=timeout)
        rc, err = res.returncode, res.stderr
    except subprocess.TimeoutExpired as exc:
        rc, err = None, (exc.stderr or b"").decode(errors="replace") if isinstance(exc.stderr, bytes) else ""
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return rc, err, cpu, wall


class Series:
    """What the errors compare: the wheelsets' lateral shift and the wheel forces."""

    def __init__(self, path: Path, wheelsets: list, manchester: bool):
        r = raildyn.Results(path)
        try:
            def get(ch):
                return np.asarray(r.get(ch), float)
            self.t = np.asarray(r.time, float)
            n = len(wheelsets)
            self.y = np.array([get(f"bodies/ws{k}/position_track:y") for k in range(1, n + 1)])
            self.fy = np.array([get(f"wheelsets/{w}/{s}/wheel:force_lateral_Y") for w in wheelsets for s in ("left", "right")])
            self.fz = np.array([get(f"wheelsets/{w}/{s}/wheel:force_vertical_Q") for w in wheelsets for s in ("left", "right")])
            self.sigma = get("vehicle/distance:sigma")
            self.get = get
            self.entries = None
            self.solver = dict(r.metadata.get("solver", {}))
            self.notes = V.run_notes(r.metadata)
            if manchester:   # the window values, when the run reaches the window
                try:
                    w0, w1 = V.manchester_window_times(self.t, self.sigma)
                    self.entries = V.manchester_window_values(self.t, get, V.load_package_table(), w0, w1)
                except (V.CaseError, KeyError):
                    self.entries = None
        finally:
            r.close()


def rel_diff(a: np.ndarray, ref: np.ndarray) -> float:
    """Largest |a - ref| over wheels and time, % of ref's range (common output rows)."""
    n = min(a.shape[1], ref.shape[1])
    span = float(np.max(ref[:, :n]) - np.min(ref[:, :n]))
    return 100.0 * float(np.max(np.abs(a[:, :n] - ref[:, :n]))) / span if span > 0 else float("nan")


def compare(row: Row, s: Series, ref: Series | None, manchester: bool):
    if ref is None:
        return
    n = min(s.t.size, ref.t.size)
    if n < 2 or not np.allclose(s.t[:n], ref.t[:n], rtol=0, atol=1e-9):
        row.notes.append("output times differ from the reference's: not compared")
        return
    row.err_y = rel_diff(s.y, ref.y)
    row.err_force = max(rel_diff(s.fy, ref.fy), rel_diff(s.fz, ref.fz))
    if manchester and s.entries is not None and ref.entries is not None:
        entries = V.load_package_table()
        scales = V.family_scales(entries)
        d = {e.key: 100.0 * abs(s.entries[e.key] - ref.entries[e.key]) / scales[e.quantity] for e in entries}
        worst = max(d, key=d.get)
        row.err_entries, row.err_entry = d[worst], worst
        row.err_entries_median = float(np.median(list(d.values())))


def measure(exe, tmp, scene, level, t_end, tag, env, timeout, ref, manchester, keep=False):
    deck = write_deck(tmp, scene, level, t_end, tag)
    out = tmp / f"{scene.key}__{tag}.h5"
    rc, err, cpu, wall = run_timed(exe, deck, out, env, timeout)
    # messages name the generated decks and the repository's: keep the published text free of
    # machine paths
    err = err.replace(f"{tmp}/", "").replace(f"{REPO}/", "")
    row = Row(scene.key, level, cpu=cpu, wall=wall)
    if rc is None:
        row.outcome = f"time-out after {timeout:g} s wall"
        return row, None
    row.outcome = EXIT_OUTCOMES.get(rc, f"exit {rc}")
    if rc not in RESULTS_READABLE:
        msg = [ln for ln in err.strip().splitlines() if ln.strip()]
        row.notes.append(msg[-1][:160] if msg else "no message")
        return row, None
    if rc == 3:
        msg = [ln for ln in err.strip().splitlines() if ln.strip()]
        row.notes.append(msg[-1][:160] if msg else "")
    try:
        s = Series(out, V.deck_wheelsets(REPO / "inputs" / scene.deck), manchester)
    except (OSError, KeyError) as exc:
        row.outcome += " (results unreadable)"
        row.notes.append(str(exc)[:160])
        return row, None
    row.t_end = float(s.t[-1])
    row.steps = int(s.solver.get("n_steps", 0))
    row.rhs = int(s.solver.get("n_rhs", 0))
    row.rhs_jac = int(s.solver.get("n_rhs_jacobian", 0))
    row.notes += [n for n in s.notes if "without contact" in n][:2]
    if manchester and s.entries is not None:
        out_rule = V.manchester_acceptance(s.entries)
        row.rule = (f"{'pass' if out_rule.passed else 'FAIL'} {out_rule.n_inside}/{out_rule.n_entries}, "
                    f"worst {out_rule.max_off_percent:.1f} %")
    compare(row, s, ref, manchester)
    if not (level.reference or keep):
        out.unlink(missing_ok=True)
    return row, s


#: a declared integrator base (Scene.integrator_base) more than this factor slower than the
#: fastest completed level of the same run is flagged in the published table (the machine's
#: noise between runs of one level: ~10-20 % of CPU s)
BASE_MARGIN = 1.25


def stale_base_note(scene_rows: list, base_name: str) -> str:
    """'' when the scene's integrator base is within BASE_MARGIN of the fastest completed level
    of the same run, else a note naming the faster level: the declaration is out of date."""
    done = [r for r in scene_rows if r.outcome == "completed" and not r.level.reference
            and not r.level.name.startswith("table build")]
    base = next((r for r in done if r.level.name == base_name), None)
    if base is None:
        return ""
    fastest = min(done, key=lambda r: r.cpu)
    if base.cpu <= BASE_MARGIN * fastest.cpu:
        return ""
    return (f"not the fastest level of this run: {fastest.level.name} took {fastest.cpu:.1f} CPU s against "
            f"{base.cpu:.1f} (the integrators' base is declared: Scene.integrator_base)")


def run_scene(exe, tmp, scene, quick, env, timeout, rows, save, integrators_on=None):
    """The scene's reference, its levels, and the integrators on its fastest level.
    integrators_on = a level's name: that level and the integrators on it only (no reference)."""
    t_end = scene.quick_t_end if quick else None
    print(f"== {scene.title}", flush=True)
    ref = None
    if integrators_on is None:
        ref_level = next(lv for lv in scene.levels if lv.reference)
        ref_row, ref = measure(exe, tmp, scene, ref_level, t_end, "reference", env, timeout, None, scene.manchester)
        rows.append(ref_row)
        save()
        print(f"   {ref_level.name}: {ref_row.outcome}, {ref_row.cpu:.1f} CPU s", flush=True)
    table_built = False
    base = base_series = None
    scene_rows = []
    levels = [lv for lv in scene.levels if not lv.reference and integrators_on in (None, lv.name)]
    for i, level in enumerate(levels):
        if level.contact == "table" and not table_built:
            # warm-up: builds the scene's table into the cache (cost of the first build)
            warm = Level("table build (first run, 0.01 s simulated)", "table", level.law, level.normal,
                         "bdf", level.wheelset, level.solver)
            cache = Path(env["RAILDYN_CACHE_DIR"])
            before = set(cache.glob("contact-table-*")) if cache.is_dir() else set()
            row, _ = measure(exe, tmp, scene, warm, 0.01, "warm", env, timeout, None, False)
            built = set(cache.glob("contact-table-*")) - before if cache.is_dir() else set()
            row.notes.append("includes the table build; every later table level reads the cache" if built else
                             "the table was already in the cache (an earlier scene's: same profiles, gauge, "
                             "inclination and radius)")
            if integrators_on is None:
                rows.append(row)
            table_built = True
        row, series = measure(exe, tmp, scene, level, t_end, f"l{i}", env, timeout, ref, scene.manchester)
        scene_rows.append(row)
        if integrators_on is None:
            rows.append(row)
            save()
        print(f"   {level.name}: {row.outcome}, {row.cpu:.1f} CPU s, y {row.err_y:.2g} %, "
              f"F {row.err_force:.2g} %, entries {row.err_entries:.2g} %", flush=True)
        if level.name == (integrators_on or scene.integrator_base) and row.outcome == "completed":
            base, base_series = level, series
    note = "" if integrators_on else stale_base_note(scene_rows, scene.integrator_base)
    if note:
        next(r for r in scene_rows if r.level.name == scene.integrator_base).notes.append(note)
        save()
        print(f"   {scene.integrator_base}: {note}", flush=True)
    if base is None:
        return
    for j, level in enumerate(integrator_levels(scene, integrators_on)):
        row, series = measure(exe, tmp, scene, level, t_end, f"i{j}", env, timeout, ref, scene.manchester)
        if series is not None and base_series is not None:
            # the integrator's own error: against the same level under BDF at the deck's tolerances
            b = Row(scene.key, level)
            compare(b, series, base_series, scene.manchester)
            row.err_base = max(b.err_y, b.err_force, b.err_entries if np.isfinite(b.err_entries) else 0.0)
        rows.append(row)
        save()
        print(f"   {level.name}: {row.outcome}, {row.cpu:.1f} CPU s, y {row.err_y:.2g} %, "
              f"F {row.err_force:.2g} %", flush=True)


def shipped_tables_deck(exe, tmp, env, timeout, quick, rows):
    """inputs/manchester_v1_tc1_tables.nml against the acceptance deck as shipped (issue 14 item
    4): the acceptance run, the tables deck with an empty cache (its first build) and again
    with the table cached; the tables run's 32 entries against the acceptance run's, in % of
    their family's S."""
    sc = Scene("manchester_decks", "manchester_v1_tc1.nml", "Manchester V1 TC1: the shipped decks", [], 4.0,
               manchester=True)
    t_end = sc.quick_t_end if quick else None
    cold_env = dict(env, RAILDYN_CACHE_DIR=str(tmp / "cold_cache"))
    acc = Level("manchester_v1_tc1.nml (online strips)", "strips 0.2 mm", "fastsim", "quasi-static", "deck",
                reference=True)
    row, ref = measure(exe, tmp, sc, acc, t_end, "acc", env, timeout, None, True, keep=True)
    rows.append(row)
    print(f"   {acc.name}: {row.outcome}, {row.cpu:.1f} CPU s, {row.rule}", flush=True)
    for tag, name, e in (("cold", "manchester_v1_tc1_tables.nml, first run (table built)", cold_env),
                         ("warm", "manchester_v1_tc1_tables.nml, table cached", cold_env)):
        sc_t = Scene(sc.key, "manchester_v1_tc1_tables.nml", sc.title, [], 4.0, manchester=True)
        lv = Level(name, "table", "fastsim", "quasi-static", "deck")
        row, _ = measure(exe, tmp, sc_t, lv, t_end, tag, e, timeout, ref, True)
        rows.append(row)
        print(f"   {name}: {row.outcome}, {row.cpu:.1f} CPU s, entries {row.err_entries:.3g} % S, {row.rule}",
              flush=True)


# ------------------------------------------------------------------------------------------
# publishing


def fmt(x, spec=".2g"):
    return "" if x is None or (isinstance(x, float) and not np.isfinite(x)) else format(x, spec)


def pareto(points):
    """Indices of the points (cost, error) no other point beats in both."""
    keep = []
    for i, (c, e) in enumerate(points):
        if not any((c2 <= c and e2 <= e) and (c2 < c or e2 < e) for j, (c2, e2) in enumerate(points) if j != i):
            keep.append(i)
    return keep


def level_error(r: dict) -> float:
    """The plotted error of a row: Manchester's largest entry difference [% S] when measured,
    else the larger of the shift and force differences [% of range]."""
    if np.isfinite(r["err_entries"]):
        return r["err_entries"]
    vals = [v for v in (r["err_y"], r["err_force"]) if np.isfinite(v)]
    return max(vals) if vals else float("nan")


def strip_paths(text: str) -> str:
    """Messages without the directories of the files they name (no machine paths in docs/)."""
    return re.sub(r"(?:/[\w.\-]+)+/(?=[\w.\-]+)", "", text)


#: The explanation above the published tables (docs/performance.md and the validation report).
INTRO = ("Each level is the scene's deck with its wheelsets' contact and creep law, or its solver, "
         "replaced. CPU s = user + system seconds of the runner process (one run, levels run one after "
         "the other); CPU/sim = CPU s per simulated second (the issue's real-time factor: 0.044 = 1 CPU s "
         "for Manchester's 22.5 s); RHS = right-hand-side calls of the method + those of the difference-"
         "quotient Jacobians. Errors against the scene's reference (the finest online model: strips "
         "0.1 mm, FASTSIM with the smooth clip, BDF rtol 1e-7, atol 1e-10 for coordinates and rates): y = "
         "largest difference of a wheelset's lateral shift over the run, F = of a wheel's lateral or "
         "vertical force, each in % of the reference's range of that quantity; Manchester entries = "
         "largest difference of the 32 window entries of the validation rule in % of their family's scale "
         "S (docs/validation.md), median over the 32 in brackets; rule = the level's own verdict of the "
         "acceptance rule. Integrator rows run the scene's fastest level (declared: the table levels are "
         "within the shared machine's noise of each other) at the deck's tolerances (rk4: fixed step 1e-4 "
         "s); '(x % from bdf)' is their largest difference (shift, force, entry) from that level under "
         "BDF, the integrator's own share. FASTSIM = 10 x 10 with the smooth clip "
         "(fastsim_saturation_width = 0.2); linear = Kalker's coefficients without saturation (knife "
         "edge), linear+SHE = with Shen-Hedrick-Elkins saturation (profile levels: the decks' friction "
         "coefficient is refused by the unsaturated law); table = contact tables of the 0.2 mm strips "
         "(cached: the table-build row is the first run's cost).")
SHIPPED_NOTE = ("The decks as shipped, each run once: errors of the tables deck against the acceptance "
                "deck's run (marked ref); the first tables run starts with an empty cache and builds "
                "the table, the second reads it.")


def published_tables(data: dict) -> list[dict]:
    """The map's tables, one per scene, as published: {title, note, columns, rows (cells as
    text), footnote}; docs/performance.md (render) and the validation report
    (validation/fidelity_map.json, raildyn.validation.fidelity_map) show the same."""
    rows = data["rows"]
    for r in rows:
        r["notes"] = [strip_paths(n) for n in r["notes"]]
    scenes = {s.key: s for s in scene_list()}
    scenes["manchester_decks"] = Scene("manchester_decks", "manchester_v1_tc1.nml",
                                       "Manchester V1 TC1: the tables deck against the acceptance deck, as shipped",
                                       [], 0, manchester=True)
    tables = []
    for key in [k for k in scenes if any(r["scene"] == k for r in rows)]:
        sc = scenes[key]
        man = sc.manchester
        columns = ["level", "contact", "law", "normal", "integrator", "outcome", "CPU s", "CPU/sim", "steps", "RHS",
                   "y %", "F %"] + (["entries % S", "rule"] if man else [])
        cells = []
        for r in (r for r in rows if r["scene"] == key):
            lv = r["level"]
            sim = r["t_end"]
            rtf = (r["cpu"] / sim if np.isfinite(sim) and sim > 0 and not lv["name"].startswith("table build")
                   else float("nan"))
            outcome = r["outcome"] + (f" ({'; '.join(r['notes'])})" if r["notes"] and r["outcome"] != "completed"
                                      else "")
            rhs = f"{r['rhs']} + {r['rhs_jac']}" if r["steps"] else ""
            integ = lv["integrator"] + (f" ({fmt(r.get('err_base', float('nan')))} % from bdf)"
                                        if np.isfinite(r.get("err_base", float("nan"))) else "")
            row = [lv["name"], lv["contact"], lv["law"], lv["normal"], integ, outcome,
                   fmt(r["cpu"], ".1f"), fmt(rtf, ".3f"), str(r["steps"]) if r["steps"] else "", rhs,
                   "ref" if lv["reference"] else fmt(r["err_y"]), "ref" if lv["reference"] else fmt(r["err_force"])]
            if man:
                ent = "ref" if lv["reference"] else (
                    f"{fmt(r['err_entries'])} ({fmt(r['err_entries_median'])}; {r['err_entry']})"
                    if np.isfinite(r["err_entries"]) else "")
                row += [ent, r["rule"]]
            cells.append(row)
        notes = [f"{r['level']['name']}: {'; '.join(r['notes'])}" for r in rows
                 if r["scene"] == key and r["notes"] and r["outcome"] == "completed"]
        tables.append({"title": sc.title, "note": SHIPPED_NOTE if key == "manchester_decks" else "",
                       "columns": columns, "rows": cells,
                       "footnote": "Notes of completed runs: " + " / ".join(notes) if notes else ""})
    return tables


def source_line(meta: dict) -> str:
    return f"Source: commit {meta.get('commit', '?')}. Host: {meta['host']}; {meta['when']}."


def render(data: dict, png: Path) -> str:
    """docs/performance.md's section fidelity_map."""
    lines = ["### Fidelity map: cost against accuracy (bench/fidelity_map/run.py)", "",
             f"{data['meta']['label']}", "", INTRO, ""]
    for t in published_tables(data):
        lines += [f"#### {t['title']}", ""]
        if t["note"]:
            lines += [t["note"], ""]
        right = {"CPU s", "CPU/sim", "steps", "RHS", "y %", "F %", "entries % S"}
        lines += ["| " + " | ".join(t["columns"]) + " |",
                  "|" + "|".join("---:" if c in right else "---" for c in t["columns"]) + "|"]
        lines += ["| " + " | ".join(row) + " |" for row in t["rows"]]
        if t["footnote"]:
            lines += ["", t["footnote"]]
        lines.append("")
    lines += [f"![Fidelity map: CPU seconds against error]({png.name})", "", source_line(data["meta"])]
    return "\n".join(lines) + "\n"


def published_json(data: dict) -> dict:
    """validation/fidelity_map.json: what the validation report's fidelity-map section shows."""
    return {"about": "written by bench/fidelity_map/run.py with docs/performance.md's section fidelity_map "
                     "and docs/fidelity_map.png (the Pareto plot); read by raildyn.validation.fidelity_map",
            "label": data["meta"]["label"], "intro": INTRO, "tables": published_tables(data),
            "source": source_line(data["meta"]), "quick": bool(data["meta"].get("quick"))}


def plot(data: dict, png: Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = data["rows"]
    scenes = [s for s in scene_list() if any(r["scene"] == s.key for r in rows)]
    fig, axes = plt.subplots(1, len(scenes), figsize=(6.2 * len(scenes), 5.2), squeeze=False)
    marker = {"knife edge": "s", "table": "o", "strips 0.2 mm": "^", "strips 0.1 mm": "v"}
    colour = {"linear": "tab:blue", "linear+SHE": "tab:purple", "polach": "tab:orange", "fastsim": "tab:green"}
    for ax, sc in zip(axes[0], scenes):
        pts, labels = [], []
        for r in rows:
            if r["scene"] != sc.key or r["level"]["reference"] or r["outcome"] != "completed":
                continue
            e = level_error(r)
            if not np.isfinite(e) or r["level"]["name"].startswith("table build"):
                continue
            lv = r["level"]
            x, y = r["cpu"], max(e, 1e-5)
            filled = lv["integrator"] == "bdf" and lv["normal"] == ("quasi-static" if sc.manchester else "elastic")
            ax.scatter([x], [y], marker=marker.get(lv["contact"], "o"), s=55,
                       facecolors=colour.get(lv["law"], "k") if filled else "none",
                       edgecolors=colour.get(lv["law"], "k"))
            pts.append((x, y))
            labels.append(lv["name"])
        for i in pareto(pts):
            ax.annotate(labels[i], pts[i], fontsize=7, xytext=(4, 3), textcoords="offset points")
        front = sorted(pts[i] for i in pareto(pts))
        if front:
            ax.plot(*zip(*front), color="0.6", lw=0.8, zorder=0)
        ref = next((r for r in rows if r["scene"] == sc.key and r["level"]["reference"]), None)
        if ref is not None and np.isfinite(ref["cpu"]):
            ax.axvline(ref["cpu"], color="0.3", ls=":", lw=0.8)
            ax.text(ref["cpu"], ax.get_ylim()[1] if pts else 1, " reference", fontsize=7, va="top", rotation=90)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU s of the run")
        ax.set_ylabel("largest entry difference [% of S]" if sc.manchester else
                      "largest shift / force difference [% of range]")
        ax.set_title(sc.title, fontsize=9)
        ax.grid(True, which="both", lw=0.3)
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], ls="", marker=m, color="k", mfc="none", label=c) for c, m in marker.items()]
    handles += [Line2D([], [], ls="", marker="o", color=c, label=law) for law, c in colour.items()]
    handles += [Line2D([], [], ls="", marker="o", color="k", mfc="none",
                       label="hollow: other normal contact or integrator")]
    fig.legend(handles=handles, loc="lower center", ncol=5, fontsize=7, frameon=False)
    fig.suptitle("Fidelity map (bench/fidelity_map/run.py): CPU s against the error from each scene's reference; "
                 "the Pareto front labelled" + (" - QUICK run, not for publishing" if data["meta"].get("quick") else ""),
                 fontsize=9)
    fig.tight_layout(rect=(0, 0.09, 1, 0.95))
    fig.savefig(png, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.environ.get("RAILDYN_BUILD_DIR", str(REPO / "build")))
    ap.add_argument("--quick", action="store_true", help="shorter runs (development; not for publishing)")
    ap.add_argument("--scenes", nargs="*", default=None, help="scene keys (default: all)")
    ap.add_argument("--timeout", type=float, default=1800.0, help="wall-clock limit per run [s]")
    ap.add_argument("--json", default=None, help="where the rows go (default <build>/fidelity_map/map.json)")
    ap.add_argument("--from-json", nargs="+", default=None,
                    help="rewrite the docs from these files (their rows in order); run nothing")
    ap.add_argument("--label", default="", help="first line of the published section")
    ap.add_argument("--integrators-on", default=None,
                    help="run only this level and the integrators on it (errors against it)")
    ap.add_argument("--no-write", action="store_true", help="do not touch docs/")
    args = ap.parse_args()
    build = Path(args.build).resolve()
    png = REPO / "docs" / "fidelity_map.png"
    if args.from_json:
        parts = [json.loads(Path(f).read_text()) for f in args.from_json]
        merged = {}
        for part in parts:
            for r in part["rows"]:
                old = merged.setdefault((r["scene"], r["level"]["name"]), r)
                # a later file's row of the same scene and level only fills in what the earlier
                # one lacks (e.g. the 'from bdf' errors of an --integrators-on rerun); the
                # measured costs stay those of the first run
                for k, v in r.items():
                    if isinstance(old.get(k), float) and not np.isfinite(old[k]) and isinstance(v, float):
                        old[k] = v
                    elif k not in old:
                        old[k] = v
        data = {"meta": dict(parts[0]["meta"]), "rows": list(merged.values())}
        for key in ("host", "when", "commit"):
            data["meta"][key] = "; ".join(dict.fromkeys(str(p["meta"].get(key, "")) for p in parts))
        if args.label:
            data["meta"]["label"] = args.label
    else:
        exe = build / "bin" / "raildyn"
        if not exe.exists():
            sys.exit(f"no runner {exe}: build it or give --build / RAILDYN_BUILD_DIR")
        work = build / "fidelity_map"
        work.mkdir(parents=True, exist_ok=True)
        json_path = Path(args.json) if args.json else work / "map.json"
        env = dict(os.environ, RAILDYN_CACHE_DIR=str(work / "cache"))
        label = args.label or ("QUICK run (shortened scenes; development only)" if args.quick else "Full run")
        commit = subprocess.run(["git", "-C", str(REPO), "describe", "--always", "--dirty"],
                                capture_output=True, text=True).stdout.strip()
        data = {"meta": {"label": label, "quick": args.quick, "commit": commit}, "rows": []}
        rows = []

        def save():
            data["rows"] = [asdict(r) for r in rows]
            data["meta"]["host"] = (f"{os.cpu_count()} CPUs, load average "
                                    f"{' '.join(Path('/proc/loadavg').read_text().split()[:3])} at the last row")
            data["meta"]["when"] = time.strftime("measured %Y-%m-%d %H:%M UTC", time.gmtime())
            json_path.parent.mkdir(parents=True, exist_ok=True)
            json_path.write_text(json.dumps(data, indent=1))

        keys = args.scenes or [s.key for s in scene_list()] + ["manchester_decks"]
        with tempfile.TemporaryDirectory(dir=work) as d:
            for sc in scene_list():
                if sc.key in keys:
                    run_scene(exe, Path(d), sc, args.quick, env, args.timeout, rows, save, args.integrators_on)
            if "manchester_decks" in keys:
                print("== Manchester: the shipped decks", flush=True)
                shipped_tables_deck(exe, Path(d), env, args.timeout, args.quick, rows)
        save()
        print(f"rows in {json_path}")
    text = render(data, png)
    print(text)
    if not args.no_write:
        plot(data, png)
        PUBLISHED.write_text(json.dumps(published_json(data), indent=1) + "\n")
        sys.path.insert(0, str(REPO / "bench"))
        from performance_section import write_section
        write_section("fidelity_map", text)


if __name__ == "__main__":
    main()
