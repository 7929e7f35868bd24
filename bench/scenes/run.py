#!/usr/bin/env python3
"""Scene benchmark: wall time, real-time factor, peak memory and solver work of whole
scenes, and the speed/accuracy trade of the integrators on one scene (error against a
tight-tolerance reference run of the same scene, measured in one session so the ratios are
comparable on a shared machine). Prints a table and rewrites its section of
docs/performance.md (between <!-- BEGIN scenes --> and <!-- END scenes -->).

    python3 bench/scenes/run.py [--build build] [--no-write]
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))
import raildyn  # noqa: E402

SCENES = ["tgv_wheelset.nml", "tgv_bogie_straight_20.nml", "tgv_bogie_curve.nml",
          "tgv_vehicle_straight.nml", "tgv_vehicle_curve.nml"]
TRADE_SCENE = "tgv_bogie_curve.nml"
TRADE = [("bdf", "rtol = 1e-4, atol = 1e-7"), ("bdf", "rtol = 1e-6, atol = 1e-9"),
         ("adams", "rtol = 1e-6, atol = 1e-9"), ("erk", "rtol = 1e-6, atol = 1e-9"),
         ("rk4", "fixed_step = 2e-4"), ("rk4", "fixed_step = 5e-4")]
REFERENCE = ("bdf", "rtol = 1e-10, atol = 1e-13")
#: Profile-contact scenes run with the coloured and the dense (CVODE) difference-quotient
#: Jacobian (&solver jacobian); Manchester only with --long (about 3 min per run).
JACOBIAN_SCENES = ["tgv_profile_fastsim.nml"]
JACOBIAN_LONG = ["manchester_v1_tc1.nml"]


def run(exe, deck, out):
    res, wall, rss, _ = run_timed(exe, deck, out)
    return res, wall, rss


def run_timed(exe, deck, out):
    """(process result, wall s, peak MiB of the children so far, CPU s of this run)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    res = subprocess.run([str(exe), "run", str(deck), "-o", str(out), "--quiet"],
                         capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return res, wall, after.ru_maxrss / 1024.0, cpu  # ru_maxrss: KiB on Linux


def variant(tmp, scene, method, settings):
    deck = tmp / f"{Path(scene).stem}_{method}_{abs(hash(settings)) % 10**6}.nml"
    deck.write_text(f"&include file = '{REPO / 'inputs' / scene}' /\n"
                    f"&solver method = '{method}', {settings} /\n")
    return deck


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--long", action="store_true", help="also the Manchester scene in the Jacobian table")
    args = ap.parse_args()
    exe = Path(args.build).resolve() / "bin" / "raildyn"
    lines = ["### Whole scenes (bench/scenes/run.py)", "",
             "Knife-edge contact, Kalker linear creep, CVODE BDF as in the decks. Real-time factor = "
             "simulated time / wall time (> 1: faster than real time). Peak memory is the largest "
             "resident set of the runs so far (the runner process).", "",
             "| scene | bodies | states | simulated s | wall s | x real time | steps | RHS | RHS for Jacobians | peak MiB |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for scene in SCENES:
            res, wall, rss = run(exe, REPO / "inputs" / scene, tmp / f"{scene}.h5")
            if res.returncode != 0:
                lines.append(f"| {scene} | failed: {res.stderr.strip()[:80]} |")
                continue
            r = raildyn.Results(tmp / f"{scene}.h5")
            st = r.metadata["solver"]
            nb = len({c.split('/')[1] for c in r.channels() if c.startswith('bodies/')})
            m = raildyn.Model.from_file(REPO / "inputs" / scene)
            m.initialize(write_output=False)
            n = len(m.state())
            m.close()
            t_end = float(r.time[-1])
            lines.append(f"| {scene} | {nb} | {n} | {t_end:g} | {wall:.2f} | {t_end / wall:.1f} | "
                         f"{st['n_steps']} | {st['n_rhs']} | {st['n_rhs_jacobian']} | {rss:.0f} |")
        lines += ["", f"Integrators on `{TRADE_SCENE}` (speed/accuracy trade): error = largest "
                  "difference of the wheelsets' lateral displacement from a BDF run at rtol 1e-10, "
                  "relative to its largest value.", "",
                  "| method | settings | wall s | steps | RHS | relative error |", "|---|---|---|---|---|---|"]
        ref_deck = variant(tmp, TRADE_SCENE, *REFERENCE)
        res, _, _ = run(exe, ref_deck, tmp / "ref.h5")
        ref = raildyn.Results(tmp / "ref.h5")
        chans = [c for c in ref.channels() if c.startswith("bodies/ws") and c.endswith("position_track")]
        yref = np.concatenate([ref.get(c)[:, 1] for c in chans])
        for method, settings in TRADE:
            deck = variant(tmp, TRADE_SCENE, method, settings)
            res, wall, _ = run(exe, deck, tmp / f"{deck.stem}.h5")
            if res.returncode != 0:
                lines.append(f"| {method} | {settings} | failed: {res.stderr.strip()[:60]} | | | |")
                continue
            v = raildyn.Results(tmp / f"{deck.stem}.h5")
            y = np.concatenate([v.get(c)[:, 1] for c in chans])
            err = np.max(np.abs(y - yref)) / np.max(np.abs(yref))
            st = v.metadata["solver"]
            lines.append(f"| {method} | {settings} | {wall:.2f} | {st['n_steps']} | "
                         f"{st['n_rhs'] + st['n_rhs_jacobian']} | {err:.1e} |")
        lines += ["", "Profile contact (strip geometry, FASTSIM), coloured against dense difference-quotient "
                  "Jacobian (`&solver jacobian`): CPU seconds of the run (user + system, less exposed to "
                  "the other jobs of a shared machine than the wall time), RHS calls of the method and "
                  "of the Jacobians, and the largest difference of the wheelsets' lateral displacement "
                  "between the two runs (both at the deck's rtol).", "",
                  "| scene | Jacobian | CPU s | wall s | steps | RHS | RHS for Jacobians | Jacobians | max diff y [m] |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for scene in JACOBIAN_SCENES + (JACOBIAN_LONG if args.long else []):
            ys = {}
            for mode in ("coloured", "dense"):
                deck = tmp / f"{Path(scene).stem}_{mode}.nml"
                deck.write_text(f"&include file = '{REPO / 'inputs' / scene}' /\n"
                                f"&solver jacobian = '{mode}' /\n")
                res, wall, _, cpu = run_timed(exe, deck, tmp / f"{deck.stem}.h5")
                if res.returncode != 0:
                    lines.append(f"| {scene} | {mode} | failed: {res.stderr.strip()[:60]} | | | | | | |")
                    continue
                v = raildyn.Results(tmp / f"{deck.stem}.h5")
                chans = sorted(c for c in v.channels() if c.startswith("bodies/ws") and c.endswith("position_track"))
                ys[mode] = np.concatenate([v.get(c)[:, 1] for c in chans])
                st = v.metadata["solver"]
                diff = f"{np.max(np.abs(ys['coloured'] - ys['dense'])):.1e}" if len(ys) == 2 else ""
                lines.append(f"| {scene} | {mode} | {cpu:.1f} | {wall:.1f} | {st['n_steps']} | {st['n_rhs']} | "
                             f"{st['n_rhs_jacobian']} | {st['n_jac']} | {diff} |")
    text = "\n".join(lines)
    print(text)
    if not args.no_write:
        sys.path.insert(0, str(REPO / "bench"))
        from performance_section import write_section
        write_section("scenes", text)

if __name__ == "__main__":
    main()
