#!/usr/bin/env python3
"""What the age of BDF's Jacobian costs and changes (`&solver jacobian_max_age`, issue 14 item 4):
the profile-contact decks and a knife-edge vehicle deck, each at CVODE's default age (51 steps)
and at older ones, with nothing else changed.

CVODE evaluates the Jacobian of its Newton matrix when the matrix is set up (at least every 20
steps, or when the step size changed much) and the Jacobian is at least `jacobian_max_age`
steps old, or sooner when Newton converges slowly with it (docs/theory_solver.md "Jacobian
age"). On the Manchester decks the difference-quotient Jacobians (coloured: 42 right-hand sides
each) were 40 % of the right-hand-side calls, most of them evaluated because of the age alone.
An older Jacobian costs Newton iterations, and Newton's slower convergence enters the error
estimate, so the step sizes change too; the error test itself is unchanged.

Per run: steps, RHS calls (method + difference-quotient Jacobians), Jacobian evaluations, CPU s
(user + system of the runner, the smaller of two runs taken alternately), and the difference
to the same deck at the default age (bench/fidelity_map/run.py's measures): for the Manchester
decks the 32 window entries of the validation rule in % of their family scale S; for all, the
largest difference over the run of a wheelset's lateral shift and of a wheel force, in % of the
default run's range. The friction-0.6 Manchester deck (bench/manchester_friction/friction_06.nml)
runs to 10.5 s at each age: does wheelset 1 still reach the 135 Hz flange cycle that every run
at the deck's tolerances shows (bench/solver_tolerance/run.py)?

    python3 bench/jacobian_age/run.py [--build DIR] [--json FILE] [--from-json FILE] [--no-write]

One run at a time. Writes the table into docs/performance.md (section jacobian_age) unless
--no-write; --from-json rewrites it from an earlier run's JSON.
"""
import datetime
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "bench"))
from performance_section import bench_arguments, earlier_json, measurement_start, write_section  # noqa: E402


def _load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


# the fidelity map's runner and error measures, the tolerance bench's friction-0.6 probe
FM = _load("fidelity_map", REPO / "bench" / "fidelity_map" / "run.py")
TOL = _load("solver_tolerance", REPO / "bench" / "solver_tolerance" / "run.py")

#: (key, deck in inputs/, Manchester window entries)
DECKS = [("manchester strips", "manchester_v1_tc1.nml", True),
         ("manchester tables", "manchester_v1_tc1_tables.nml", True),
         ("tgv profile fastsim", "tgv_profile_fastsim.nml", False),
         ("tgv profile polach", "tgv_profile_polach.nml", False),
         ("tgv knife-edge curve", "tgv_vehicle_curve.nml", False)]
DEFAULT_AGE = 51
AGES = [DEFAULT_AGE, 200, 1000, 100000]
ROUNDS = 2


def level(age):
    return FM.Level(f"jacobian_max_age {age}", "", "", "", "bdf", "", f"jacobian_max_age = {age}",
                    reference=age == DEFAULT_AGE)


def measure_deck(exe, tmp, env, key, deck, manchester, ages=AGES, rounds=ROUNDS, t_end=None):
    """Rows of one deck at each age (the first is the reference), CPU over `rounds` runs taken
    alternately (t_end: a shortened run, for the tests)."""
    scene = FM.Scene(key.replace(" ", "_").replace("-", "_"), deck, key, [], 0.0, manchester=manchester)
    first, cpu, ref = {}, {age: [] for age in ages}, None
    for rnd in range(rounds):
        for age in ages:
            tag = f"age{age}_{rnd}"
            row, series = FM.measure(exe, tmp, scene, level(age), t_end, tag, env, 3600.0, ref, manchester,
                                     keep=True)
            out = tmp / f"{scene.key}__{tag}.h5"
            jac = ""
            if out.exists():
                with h5py.File(out, "r") as f:
                    jac = int(f["meta/solver"].attrs["n_jac"])
                out.unlink()
            if ref is None:
                ref = series
            cpu[age].append(row.cpu)
            if rnd == 0:
                first[age] = (row, jac)
            print(f"   {key}, age {age}, round {rnd + 1}: {row.outcome}, {row.steps} steps, "
                  f"{row.rhs} + {row.rhs_jac} RHS, {jac} Jacobians, {row.cpu:.2f} CPU s", flush=True)
    return [dict(deck=key, age=age, outcome=r.outcome, steps=r.steps, rhs=r.rhs, rhs_jac=r.rhs_jac, jac=jac,
                 cpu=cpu[age], err_entries=r.err_entries, err_y=r.err_y, err_force=r.err_force, rule=r.rule,
                 notes=list(r.notes)) for age, (r, jac) in first.items()]


def run_all(exe, tmp, env):
    rows = []
    for key, deck, manchester in DECKS:
        if "tables" in deck:    # the table built once, outside the measured runs
            warm = tmp / "warm.nml"
            warm.write_text(f"&include file = '{REPO / 'inputs' / deck}' /\n&simulation t_end = 0.01 /\n")
            subprocess.run([str(exe), "run", str(warm), "-o", str(tmp / "warm.h5"), "--quiet"],
                           env=env, check=True, capture_output=True)
        rows += measure_deck(exe, tmp, env, key, deck, manchester)
    cycles = []
    for age in AGES:
        c = TOL.cycle_probe(exe, tmp, env, f"age{age}", f"jacobian_max_age = {age}")
        print(f"   friction 0.6, age {age}: {c}", flush=True)
        cycles.append(dict(age=age, **c))
    return rows, cycles


def render(data):
    rows, cycles = data["rows"], data["cycles"]
    lines = [f"Measured {data['when']}.", "",
             "Each row is the deck with only `&solver jacobian_max_age` set (51 = CVODE's default, the "
             "reference of its deck). RHS = the method's calls + the difference-quotient Jacobians' calls; "
             f"CPU s = user + system of the runner, the smaller of {ROUNDS} runs taken alternately with the "
             "other ages (both in brackets); entries = the 32 window entries of the validation rule, largest "
             "difference to the default age's run in % of the family scale S; y, F = largest difference over "
             "the run of a wheelset's lateral shift and of a wheel force (Y or Q), % of the default run's range.",
             "",
             "| deck | jacobian_max_age | outcome | steps | RHS | Jacobians | CPU s | entries [% S] | y [%] | F [%] "
             "| rule |",
             "|---|---:|---|---:|---:|---:|---|---:|---:|---:|---|"]
    for r in rows:
        cpus = ", ".join(f"{c:.2f}" for c in r["cpu"])
        lines.append(f"| {r['deck']} | {r['age']} | {r['outcome']} | {r['steps']} | {r['rhs']} + {r['rhs_jac']} | "
                     f"{r['jac']} | {min(r['cpu']):.2f} ({cpus}) | {FM.fmt(r['err_entries'], '.2g')} | "
                     f"{FM.fmt(r['err_y'], '.2g')} | {FM.fmt(r['err_force'], '.2g')} | {r['rule']} |")
    lines += ["", f"The friction-0.6 deck to {TOL.CYCLE_WINDOW[1]} s at each age: peak to peak of wheelset 1's "
              f"lateral shift y and height z and the left wheel's Y/Q range in {TOL.CYCLE_WINDOW[0]}-"
              f"{TOL.CYCLE_WINDOW[1]} s (the cycle: y about 0.05 mm; a quiet flange contact: 0.001 mm).", "",
              "| jacobian_max_age | steps | CPU s | y p-p [mm] | z p-p [mm] | Y/Q |",
              "|---:|---:|---:|---:|---:|---|"]
    for c in cycles:
        if "cycle_y" not in c:
            lines.append(f"| {c['age']} | | | | | {c.get('cycle', '')} |")
            continue
        lines.append(f"| {c['age']} | {c['cycle_steps']} | {c['cycle_cpu']:.1f} | {c['cycle_y']:.4f} | "
                     f"{c['cycle_z']:.4f} | {c['cycle_yq'][0]:.2f} .. {c['cycle_yq'][1]:.2f} |")
    return "\n".join(lines) + "\n"


def main():
    args = bench_arguments(__doc__).parse_args()
    data = earlier_json(args)
    if data is None:
        exe, rev, start = measurement_start(args)
        with tempfile.TemporaryDirectory(prefix="raildyn-age-") as tmpdir:
            tmp = Path(tmpdir)
            rows, cycles = run_all(exe, tmp, dict(os.environ, RAILDYN_CACHE_DIR=str(tmp / "cache")))
        end = datetime.datetime.now(datetime.timezone.utc)
        data = dict(rows=rows, cycles=cycles,
                    when=f"on commit {rev}, {start:%Y-%m-%d %H:%M}-{end:%H:%M} UTC, one run at a time "
                         f"(load average {os.getloadavg()[0]:.1f} at the end)")
        if args.json:
            Path(args.json).parent.mkdir(parents=True, exist_ok=True)
            Path(args.json).write_text(json.dumps(data, indent=1))
    text = render(data)
    print(text)
    if not args.no_write:
        write_section("jacobian_age", text, "### The Jacobian's age (bench/jacobian_age/run.py)")


if __name__ == "__main__":
    main()
