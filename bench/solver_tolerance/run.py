#!/usr/bin/env python3
"""What the integrator's tolerances cost and change on the Manchester decks (issue 12 item 3,
issue 14 item 4): the acceptance deck (online strips) and the tables deck, each at its
shipped tolerances and at looser ones, against the same deck at tight tolerances (the fidelity
map's reference solver: BDF rtol 1e-7, atol 1e-10 for coordinates and rates). Only the
&solver line changes, so every difference is the integration's.

Per run: steps, RHS calls (method + difference-quotient Jacobians), CPU s (user + system of the
runner), and its error against the tight run of the same deck (bench/fidelity_map/run.py's
measures): the 32 window entries of the validation rule in % of their family scale S (largest,
median), the largest difference over the run of a wheelset's lateral shift and of a wheel force
(Y or Q), in % of the tight run's range, the rule's own verdict and the run's notes (a wheel
without contact).

Each tolerance also runs the friction-0.6 variant (bench/manchester_friction/friction_06.nml)
to 10.5 s: at the clothoid's end wheelset 1 enters a 135 Hz cycle on its flange that the tight
run shows; a tolerance whose steps damp the kink's ringing before it grows misses the cycle
(--no-cycle skips these runs).

Where the force error sits: the curvature kinks (clothoid ends) excite the leading wheelsets'
undamped 131 Hz flange mode (docs/theory_flange_chatter.md section 11); the tight run follows
its ringing, BDF2 at looser tolerances damps it sooner. The output samples every 20 ms alias
that ringing, so the force error over the run is the ringing's sampled amplitude.

    python3 bench/solver_tolerance/run.py [--build DIR] [--decks tables strips] [--json FILE]
        [--from-json FILE] [--no-write] [--no-cycle]

Runs one at a time (2 shared cores). Writes the table into docs/performance.md (section
solver_tolerance) unless --no-write; --from-json rewrites it from an earlier run's JSON.
"""
import datetime
import importlib.util
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "bench"))
sys.path.insert(0, str(REPO / "python"))
from performance_section import bench_arguments, earlier_json, measurement_start, write_section  # noqa: E402
from raildyn.validation.runs import read_deck  # noqa: E402

# the fidelity map's runner and error measures (one definition of "error against a reference")
_spec = importlib.util.spec_from_file_location("fidelity_map", REPO / "bench" / "fidelity_map" / "run.py")
FM = importlib.util.module_from_spec(_spec)
sys.modules["fidelity_map"] = FM
_spec.loader.exec_module(FM)

DECKS = {"tables": "manchester_v1_tc1_tables.nml", "strips": "manchester_v1_tc1.nml"}
#: (label, &solver settings) over the acceptance deck's &solver line (method 'bdf', rtol 1e-5,
#: max_order 2, its atol and atol_velocity): the variants keep the method and the order (and
#: rtol, unless they name it); the row with the deck's own tolerances is marked in the table.
VARIANTS = [("atol 1e-8, atol_velocity 1e-5", "atol = 1e-8, atol_velocity = 1e-5"),
            ("atol 1e-7, atol_velocity 1e-5", "atol = 1e-7, atol_velocity = 1e-5"),
            ("atol 3e-7, atol_velocity 1e-5", "atol = 3e-7, atol_velocity = 1e-5"),
            ("atol 1e-6, atol_velocity 1e-5", "atol = 1e-6, atol_velocity = 1e-5"),
            ("atol 1e-7, atol_velocity 2e-5", "atol = 1e-7, atol_velocity = 2e-5"),
            ("atol 1e-8, atol_velocity 3e-5", "atol = 1e-8, atol_velocity = 3e-5"),
            ("atol 1e-8, atol_velocity 1e-4", "atol = 1e-8, atol_velocity = 1e-4"),
            ("atol 3e-8, atol_velocity 1e-4", "atol = 3e-8, atol_velocity = 1e-4"),
            ("atol 1e-7, atol_velocity 1e-4", "atol = 1e-7, atol_velocity = 1e-4"),
            ("atol 1e-7, atol_velocity 1e-3", "atol = 1e-7, atol_velocity = 1e-3"),
            ("atol 3e-7, atol_velocity 3e-4", "atol = 3e-7, atol_velocity = 3e-4"),
            ("atol 1e-6, atol_velocity 1e-3", "atol = 1e-6, atol_velocity = 1e-3"),
            ("rtol 1e-4, atol 1e-7, atol_velocity 1e-4", "rtol = 1e-4, atol = 1e-7, atol_velocity = 1e-4")]
TIGHT = ("tight: rtol 1e-7, atol 1e-10 (coordinates and rates)", FM.REFERENCE_SOLVER)


def deck_tolerances():
    """(rtol, atol, atol_velocity) of the acceptance deck's &solver, as the runner reads it."""
    solver = read_deck(REPO / "inputs" / DECKS["strips"])["groups"]["solver"][0]
    return solver["rtol"], solver["atol"], solver["atol_velocity"]


def is_deck(solver):
    """Whether the variant's settings give the deck's own tolerances."""
    rtol, atol, atol_v = deck_tolerances()
    given = dict(rtol=rtol, atol=atol, atol_velocity=atol_v)
    for k, v in re.findall(r"(\w+)\s*=\s*([0-9.eE+-]+)", solver):
        given[k] = float(v)
    return (given["rtol"], given["atol"], given["atol_velocity"]) == (rtol, atol, atol_v)


def measure(exe, tmp, env, deck_key, label, solver, ref, t_end=None):
    """(row, series, sampled maxima) of the deck with `solver` as its &solver line (t_end: a
    shortened run, for the tests)."""
    scene = FM.Scene(f"tol_{deck_key}", DECKS[deck_key], deck_key, [], 0.0, manchester=True)
    level = FM.Level(label, deck_key, "fastsim", "quasi-static", "bdf", "", solver)
    tag = "".join(c if c.isalnum() else "_" for c in label.split(":")[0])
    row, series = FM.measure(exe, tmp, scene, level, t_end, tag, env, 3600.0, ref, True, keep=True)
    out = tmp / f"{scene.key}__{tag}.h5"
    maxima = sampled_maxima(out) if series is not None else {}
    out.unlink(missing_ok=True)
    return row, series, maxima


#: The friction-0.6 variant of the acceptance deck (docs/theory_flange_chatter.md section 12):
#: wheelset 1 enters a 135 Hz cycle on its flange at the clothoid's end (8.9 s), which the deck
#: and a run at 100 times tighter tolerances both show. Each tolerance is also run on it to
#: 10.5 s (2 ms samples): does the run reach the cycle?
FRICTION_06 = REPO / "bench" / "manchester_friction" / "friction_06.nml"
CYCLE_WINDOW = (9.8, 10.5)


def cycle_probe(exe, tmp, env, tag, solver):
    """Wheelset 1 in CYCLE_WINDOW of the friction-0.6 deck with `solver`: steps, the lateral
    shift's and the height's peak to peak [mm], the left wheel's Y/Q range."""
    deck = tmp / f"cycle_{tag}.nml"
    deck.write_text(f"&include file = '{FRICTION_06}' /\n&simulation t_end = {CYCLE_WINDOW[1]} /\n"
                    f"&output interval = 0.002 /\n" + (f"&solver {solver} /\n" if solver else ""))
    out = tmp / f"cycle_{tag}.h5"
    rc, err, cpu, _ = FM.run_timed(exe, deck, out, env, 3600.0)
    if rc != 0:
        return dict(cycle=f"exit {rc}")
    with h5py.File(out, "r") as f:
        t = f["time"][...]
        m = (t > CYCLE_WINDOW[0]) & (t <= CYCLE_WINDOW[1] + 1e-9)
        pos = f["bodies/ws1/position_track"][...]
        wheel = f["wheelsets/w1/left/wheel"][...]
        steps = int(f["meta/solver"].attrs["n_steps"])
    out.unlink(missing_ok=True)
    return dict(cycle_steps=steps, cycle_cpu=cpu, cycle_y=1e3 * float(np.ptp(pos[m, 1])),
                cycle_z=1e3 * float(np.ptp(pos[m, 2])), cycle_yq=(float(wheel[m, 4].min()), float(wheel[m, 4].max())))


def sampled_maxima(path):
    """The sampled maxima an assessment starts from: largest Y/Q of a wheel, largest Q, and the
    largest |Y_left + Y_right| of a wheelset (raw samples, no sliding means or filters)."""
    with h5py.File(path, "r") as f:
        yq, q, sum_y = [], [], []
        for w in f["wheelsets"]:
            wheel = {side: f[f"wheelsets/{w}/{side}/wheel"][...] for side in ("left", "right")}
            for a in wheel.values():
                yq.append(float(np.max(a[:, 4])))
                q.append(float(np.max(a[:, 3])))
            sum_y.append(float(np.max(np.abs(wheel["left"][:, 2] + wheel["right"][:, 2]))))
    return dict(max_yq=max(yq), max_q=max(q), max_sum_y=max(sum_y))


def render(rows, when, cycles=()):
    lines = [f"Measured {when}.", "",
             "Each row is the deck with only its `&solver` line changed (method 'bdf' and max_order 2 "
             "kept, rtol 1e-5 unless named); errors against the same deck at the tight tolerances (the fidelity "
             "map's reference solver). entries = the 32 window entries of the validation rule, "
             "largest difference in % of the family scale S (median in brackets); y, F = largest "
             "difference over the run of a wheelset's lateral shift and of a wheel force (Y or Q), "
             "% of the tight run's range; rule = the run's own verdict of the acceptance rule; "
             "Y/Q, Q, sum Y = the largest sampled Y/Q of a wheel, Q of a wheel and |Y_left + Y_right| "
             "of a wheelset over the run (raw samples, before an assessment's sliding means).", "",
             "| deck | tolerances | outcome | steps | RHS (+ Jacobians) | CPU s | entries [% S] | y [%] | F [%] "
             "| Y/Q | Q [kN] | sum Y [kN] | rule | notes |",
             "|---|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---|---|"]
    for r in rows:
        entries = (f"{FM.fmt(r['err_entries'], '.2g')} ({FM.fmt(r['err_entries_median'], '.1g')})"
                   if np.isfinite(r["err_entries"]) else "")
        lines.append(f"| {r['deck']} | {r['label']} | {r['outcome']} | {r['steps']} | "
                     f"{r['rhs']} + {r['rhs_jac']} | {FM.fmt(r['cpu'], '.2f')} | {entries} | "
                     f"{FM.fmt(r['err_y'], '.2g')} | {FM.fmt(r['err_force'], '.2g')} | "
                     f"{FM.fmt(r.get('max_yq'), '.4f')} | {FM.fmt(r.get('max_q', float('nan')) / 1e3, '.2f')} | "
                     f"{FM.fmt(r.get('max_sum_y', float('nan')) / 1e3, '.2f')} | {r['rule']} | "
                     f"{'; '.join(r['notes'])} |")
    if cycles:
        lines += ["", f"The friction-0.6 deck (`bench/manchester_friction/friction_06.nml`) to {CYCLE_WINDOW[1]} s at "
                  "each tolerance: does wheelset 1 reach the 135 Hz cycle on its flange that the tight run shows "
                  "(docs/theory_flange_chatter.md section 12)? Peak to peak of its lateral shift y and height z, "
                  f"and the left wheel's Y/Q range, in {CYCLE_WINDOW[0]}-{CYCLE_WINDOW[1]} s.", "",
                  "| tolerances | steps | CPU s | y p-p [mm] | z p-p [mm] | Y/Q | the cycle |",
                  "|---|---:|---:|---:|---:|---|---|"]
        tight_y = next((c.get("cycle_y") for c in cycles if c["label"] == TIGHT[0]), None)
        for c in cycles:
            if "cycle_y" not in c:
                lines.append(f"| {c['label']} | | | | | | {c.get('cycle', '')} |")
                continue
            reached = tight_y is not None and c["cycle_y"] > 0.5 * tight_y
            lines.append(f"| {c['label']}{' (the deck)' if c['deck'] else ''} | {c['cycle_steps']} | "
                         f"{c['cycle_cpu']:.1f} | {c['cycle_y']:.4f} | {c['cycle_z']:.4f} | "
                         f"{c['cycle_yq'][0]:.2f} .. {c['cycle_yq'][1]:.2f} | "
                         f"{'reached' if reached else '**not reached**'} |")
    return "\n".join(lines) + "\n"


def main():
    ap = bench_arguments(__doc__)
    ap.add_argument("--decks", nargs="+", choices=list(DECKS), default=list(DECKS))
    ap.add_argument("--no-cycle", dest="cycle", action="store_false",
                    help="without the friction-0.6 runs (bench/manchester_friction/friction_06.nml to 10.5 s)")
    args = ap.parse_args()
    data = earlier_json(args)
    if data is None:
        exe, rev, start = measurement_start(args)
        rows, cycles = [], []
        with tempfile.TemporaryDirectory(prefix="raildyn-tol-") as tmpdir:
            tmp = Path(tmpdir)
            env = dict(os.environ, RAILDYN_CACHE_DIR=str(tmp / "cache"))
            if args.cycle:
                for label, solver in [TIGHT] + VARIANTS:
                    c = cycle_probe(exe, tmp, env, "".join(ch if ch.isalnum() else "_" for ch in label[:40]), solver)
                    print(f"   friction 0.6, {label}: {c}", flush=True)
                    cycles.append(dict(label=label, deck=is_deck(solver) if solver != TIGHT[1] else False, **c))
            for key in args.decks:
                if key == "tables":   # build the table once, outside the measured runs
                    warm = tmp / "warm.nml"
                    warm.write_text(f"&include file = '{REPO / 'inputs' / DECKS[key]}' /\n"
                                    "&simulation t_end = 0.01 /\n")
                    subprocess.run([str(exe), "run", str(warm), "-o", str(tmp / "warm.h5"), "--quiet"],
                                   env=env, check=True, capture_output=True)
                ref_row, ref, ref_max = measure(exe, tmp, env, key, TIGHT[0], TIGHT[1], None)
                print(f"== {key}: tight run {ref_row.outcome}, {ref_row.steps} steps, {ref_row.cpu:.1f} CPU s",
                      flush=True)
                rows.append(dict(deck=key, label=TIGHT[0], **row_fields(ref_row), **ref_max))
                for label, solver in VARIANTS:
                    label = f"{label} (the deck)" if is_deck(solver) else label
                    row, _, maxima = measure(exe, tmp, env, key, label, solver, ref)
                    print(f"   {label}: {row.outcome}, {row.steps} steps, {row.cpu:.2f} CPU s, entries "
                          f"{row.err_entries:.2g} % S, y {row.err_y:.2g} %, F {row.err_force:.2g} %, "
                          f"max Y/Q {maxima.get('max_yq', float('nan')):.4f}", flush=True)
                    rows.append(dict(deck=key, label=label, **row_fields(row), **maxima))
        end = datetime.datetime.now(datetime.timezone.utc)
        load = os.getloadavg()[0]
        data = dict(rows=rows, cycles=cycles, when=f"on commit {rev}, {start:%Y-%m-%d %H:%M}-{end:%H:%M} UTC, one run at a "
                                    f"time (load average {load:.1f} at the end)")
        if args.json:
            Path(args.json).parent.mkdir(parents=True, exist_ok=True)
            Path(args.json).write_text(json.dumps(data, indent=1))
    text = render(data["rows"], data["when"], data.get("cycles", []))
    print(text)
    if not args.no_write:
        write_section("solver_tolerance", text,
                      "### Solver tolerances on the Manchester decks (bench/solver_tolerance/run.py)")


def row_fields(row):
    return dict(outcome=row.outcome, steps=row.steps, rhs=row.rhs, rhs_jac=row.rhs_jac, cpu=row.cpu,
                err_entries=row.err_entries, err_entries_median=row.err_entries_median,
                err_y=row.err_y, err_force=row.err_force, rule=row.rule, notes=list(row.notes))


if __name__ == "__main__":
    main()
