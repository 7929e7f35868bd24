#!/usr/bin/env python3
"""Before/after comparison of two builds in one session (the machine is shared and noisy:
only ratios measured back to back mean something). Runs the contact_geometry benchmark of
both builds alternately (best of the rounds per row) and, with --scenes, whole scenes with
both runners alternately (CPU seconds of the run: user + system, less exposed to the other
jobs than the wall time; best of the rounds). Checks that the scene outputs of the two
builds are identical (or prints the largest difference), prints a table and writes it into
the section `compare_builds` of docs/performance.md.

    python3 bench/compare_builds.py BEFORE_BUILD AFTER_BUILD [--rounds 2]
        [--scenes manchester_v1_tc1.nml tgv_profile_fastsim.nml] [--replay POSES.txt]
        [--label TEXT] [--no-write]

A build is a build directory (bench/bench_contact_geometry and bin/raildyn inside; build the
bench with `cmake --build DIR --target bench_contact_geometry raildyn_exe`). --replay also
times bench/bench_geometry_replay of both builds on the wheelset poses of POSES.txt
(bench/geometry_replay/poses.py) and compares their results bitwise.
"""
import argparse
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

REPO = Path(__file__).resolve().parents[1]


def bench_rows(exe):
    """{(spacing, pose): us per call} of the strip rows of one bench_contact_geometry run."""
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout
    rows = {}
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 7 and cells[0] in ("strip", "knife edge"):
            rows[(cells[0], cells[1], cells[3])] = float(cells[5])
    return rows


def replay_us(exe, poses, dump, passes=3):
    """us per wheel of one bench_geometry_replay run on poses (best of its passes); every
    result written bitwise to dump."""
    out = subprocess.run([str(exe), str(poses), str(passes), str(dump)], capture_output=True,
                         text=True, check=True).stdout
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and cells[0].isdigit():
            return float(cells[3]), int(cells[1])
    sys.exit(f"{exe}: no result row")


def scene_cpu(exe, deck, out):
    """CPU seconds (user + system) of one run of the runner exe on deck."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = subprocess.run([str(exe), "run", str(deck), "-o", str(out), "--quiet"],
                         capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if res.returncode != 0:
        sys.exit(f"{exe} failed on {deck}: {res.stderr.strip()[:200]}")
    return (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def h5_difference(a, b):
    """(number of datasets, number that differ, largest |difference| / largest |value|, name)."""
    fa, fb = h5py.File(a, "r"), h5py.File(b, "r")
    names = []
    fa.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
    ndiff, worst = 0, (0.0, "")
    for n in names:
        x = fa[n][()]
        y = fb[n][()] if n in fb else None
        if y is None or np.shape(x) != np.shape(y):
            ndiff += 1
            worst = max(worst, (np.inf, n))
            continue
        if np.asarray(x).dtype.kind in "fc":
            if not np.array_equal(x, y, equal_nan=True):
                ndiff += 1
                scale = np.nanmax(np.abs(x)) or 1.0
                worst = max(worst, (float(np.nanmax(np.abs(x - y)) / scale), n))
        elif not np.array_equal(x, y):
            ndiff += 1
    return len(names), ndiff, worst[0], worst[1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--scenes", nargs="*", default=[])
    ap.add_argument("--replay", default="")
    ap.add_argument("--label", default="")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    builds = [Path(args.before).resolve(), Path(args.after).resolve()]

    best = [{}, {}]
    for _ in range(args.rounds):
        for k, b in enumerate(builds):
            for key, t in bench_rows(b / "bench" / "bench_contact_geometry").items():
                best[k][key] = min(t, best[k].get(key, np.inf))
    lines = ["### Before/after comparison of two builds (bench/compare_builds.py)", ""]
    if args.label:
        lines += [args.label, ""]
    lines += [f"Best of {args.rounds} alternating runs of each build, measured in one session; "
              "speed-up = before / after.", "",
              "| model | spacing [mm] | pose | before us/call | after us/call | speed-up |",
              "|---|---:|---|---:|---:|---:|"]
    for key in best[0]:
        if key in best[1]:
            t0, t1 = best[0][key], best[1][key]
            lines.append(f"| {key[0]} | {key[1]} | {key[2]} | {t0:.2f} | {t1:.2f} | {t0 / t1:.2f} |")

    if args.replay:
        lines += ["", "Online strip geometry at the wheelset poses of a run of the acceptance deck "
                  "(bench/geometry_replay, both wheels per pose): us per wheel, best of the rounds "
                  "(3 passes each); every result of the two builds compared bitwise.", "",
                  "| poses | wheel evaluations | before us/wheel | after us/wheel | speed-up | results |",
                  "|---:|---:|---:|---:|---:|---|"]
        with tempfile.TemporaryDirectory() as d:
            tmp = Path(d)
            us = [np.inf, np.inf]
            for _ in range(args.rounds):
                for k, b in enumerate(builds):
                    t, nwheel = replay_us(b / "bench" / "bench_geometry_replay", args.replay, tmp / f"{k}.bin")
                    us[k] = min(us[k], t)
            same = (tmp / "0.bin").read_bytes() == (tmp / "1.bin").read_bytes()
            verdict = "identical" if same else "DIFFER"
            lines.append(f"| {nwheel // 2} | {nwheel} | {us[0]:.2f} | {us[1]:.2f} | {us[0] / us[1]:.2f} | {verdict} |")

    if args.scenes:
        lines += ["", "Whole scenes: CPU seconds (user + system) of the run, best of the rounds; "
                  "outputs compared dataset by dataset.", "",
                  "| scene | before CPU s | after CPU s | speed-up | outputs |", "|---|---:|---:|---:|---|"]
        with tempfile.TemporaryDirectory() as d:
            tmp = Path(d)
            for scene in args.scenes:
                cpu = [np.inf, np.inf]
                for _ in range(args.rounds):
                    for k, b in enumerate(builds):
                        cpu[k] = min(cpu[k], scene_cpu(b / "bin" / "raildyn", REPO / "inputs" / scene,
                                                       tmp / f"{k}.h5"))
                n, ndiff, worst, name = h5_difference(tmp / "0.h5", tmp / "1.h5")
                same = (f"identical ({n} datasets)" if ndiff == 0 else
                        f"{ndiff} of {n} datasets differ, largest {worst:.1e} of range ({name})")
                lines.append(f"| {scene} | {cpu[0]:.1f} | {cpu[1]:.1f} | {cpu[0] / cpu[1]:.2f} | {same} |")

    load = Path("/proc/loadavg").read_text().split()[:3]
    lines += ["", f"Host: load average {' '.join(load)} at the end of the run (shared machine)."]
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        sys.path.insert(0, str(REPO / "bench"))
        from performance_section import write_section
        write_section("compare_builds", text)


if __name__ == "__main__":
    main()
