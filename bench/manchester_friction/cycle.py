#!/usr/bin/env python3
"""The leading wheelset's flange cycle at friction 0.6 (docs/theory_flange_chatter.md section 12).

Runs friction_06.nml of this folder to t = 9.6 s with plain samples every 2 ms (no interval
means), at the deck's tolerances and at rtol 1e-7, atol 1e-10, atol_velocity 1e-7 (integration
error ruled out when both agree), and prints per 0.1 s the ranges of wheelset 1's left contact
angle, Y/Q and height, and over 9.2-9.6 s the dominant frequency and peak-to-peak amplitude of its
lateral shift and height. Extra deck lines (e.g. a frozen coordinate) with --extra; existing
results files are reused with --results.

    python3 bench/manchester_friction/cycle.py [--build DIR] [--work DIR] [--extra TEXT]
        [--results FILE ...]
"""
import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "python"))
import raildyn  # noqa: E402

RUNS = {"deck tolerances": "", "rtol 1e-7, atol 1e-10, atol_velocity 1e-7":
        "&solver rtol = 1e-7, atol = 1e-10, atol_velocity = 1e-7 /\n"}


def report(path: Path, label: str):
    r = raildyn.Results(path)
    try:
        t = np.asarray(r.time, float)

        def get(ch):
            return np.asarray(r.get(ch), float)
        solver = dict(r.metadata.get("solver", {}))
        gamma = np.degrees(get("wheelsets/w1/left/patch1:contact_angle"))
        yq = -get("wheelsets/w1/left/wheel:force_lateral_Y") / get("wheelsets/w1/left/wheel:force_vertical_Q")
        pos = get("bodies/ws1/position_track")
    finally:
        r.close()
    print(f"{label}: {path.name}, t_end {t[-1]:g} s, {solver.get('n_steps')} steps, last step "
          f"{solver.get('h_last', float('nan')):.2g} s")
    print("| t [s] | contact angle, ws1 left [deg] | Y/Q, ws1 left | z, ws1 [mm] |")
    print("|---|---|---|---|")
    for a in np.arange(8.6, 9.6 - 1e-9, 0.1):
        m = (t >= a - 1e-9) & (t < a + 0.1 - 1e-9)
        if m.any():
            print(f"| {a:.1f}-{a + 0.1:.1f} | {gamma[m].min():.1f} .. {gamma[m].max():.1f} | "
                  f"{yq[m].min():.3f} .. {yq[m].max():.3f} | {pos[m, 2].min() * 1e3:.4f} .. {pos[m, 2].max() * 1e3:.4f} |")
    m = (t >= 9.2) & (t < 9.6)
    if m.sum() > 16:
        dt = float(t[1] - t[0])
        for name, s in (("lateral shift y", pos[m, 1]), ("height z", pos[m, 2])):
            x = s - s.mean()
            spec = np.abs(np.fft.rfft(x * np.hanning(x.size)))
            f = np.fft.rfftfreq(x.size, dt)
            k = int(np.argmax(spec[1:])) + 1
            print(f"  {name}, 9.2-9.6 s: peak-to-peak {np.ptp(s) * 1e3:.3f} mm, dominant frequency {f[k]:.1f} Hz "
                  f"(samples every {dt * 1e3:g} ms)")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", type=Path, default=Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")))
    ap.add_argument("--work", type=Path, default=None)
    ap.add_argument("--extra", default="", help="deck lines added to both runs")
    ap.add_argument("--results", type=Path, nargs="*", help="report these results files instead of running")
    args = ap.parse_args()
    if args.results:
        for p in args.results:
            report(p, "results")
        return
    work = args.work or Path(tempfile.mkdtemp(prefix="manchester_cycle_"))
    work.mkdir(parents=True, exist_ok=True)
    for k, (label, solver) in enumerate(RUNS.items()):
        deck = work / f"cycle_{k}.nml"
        deck.write_text(f"&include file = '{HERE / 'friction_06.nml'}' /\n&simulation t_end = 9.6 /\n"
                        f"&output interval = 0.002, mean_samples = 0 /\n{solver}{args.extra}\n")
        out = work / f"cycle_{k}.h5"
        res = subprocess.run([str(args.build / "bin" / "raildyn"), "run", str(deck), "-o", str(out), "--quiet"],
                             capture_output=True, text=True)
        if res.returncode != 0:
            print(f"{label}: exit {res.returncode}: {res.stderr.strip().splitlines()[-1:]}")
            continue
        report(out, label)


if __name__ == "__main__":
    main()
