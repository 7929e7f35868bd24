#!/usr/bin/env python3
"""Before/after comparison of two builds in one session (the machine is shared and noisy:
only ratios measured back to back mean something). Runs the contact_geometry benchmark of
both builds alternately (best of the rounds per row) and, with --scenes, whole scenes with
both runners alternately (CPU seconds of the run: user + system, less exposed to the other
jobs than the wall time; best of the rounds). Checks that the scene outputs of the two
builds are identical (or prints the largest difference), prints a table and writes it into
the section `compare_builds` of docs/performance.md (or --section).

    python3 bench/compare_builds.py BEFORE_BUILD AFTER_BUILD [--rounds 2]
        [--scenes manchester_v1_tc1.nml tgv_profile_fastsim.nml] [--scenes-only]
        [--before-env NAME=VALUE ...] [--after-env NAME=VALUE ...] [--replay POSES.txt]
        [--label TEXT] [--section NAME --title TEXT] [--no-write]

--before-env / --after-env set environment variables for one build's runs, e.g. the same
build against two BLAS libraries (LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/blas:...).
Scenes run with $RAILDYN_CACHE_DIR in a temporary directory, after one untimed run per build
(contact tables are then cached, as in a campaign). --scenes-only skips the geometry benchmark.

A build is a build directory (bench/bench_contact_geometry and bin/raildyn inside; build the
bench with `cmake --build DIR --target bench_contact_geometry raildyn_exe`). --replay also
times bench/bench_geometry_replay of both builds on the wheelset poses of POSES.txt
(bench/geometry_replay/poses.py) and compares their results bitwise.
"""
import argparse
import os
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


def scene_cpu(exe, deck, out, env=None):
    """CPU seconds (user + system) of one run of the runner exe on deck (environment env)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = subprocess.run([str(exe), "run", str(deck), "-o", str(out), "--quiet"],
                         capture_output=True, text=True, env=env)
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
    ap.add_argument("--section", default="compare_builds")
    ap.add_argument("--title", default="Before/after comparison of two builds (bench/compare_builds.py)")
    ap.add_argument("--scenes-only", action="store_true")
    ap.add_argument("--before-env", nargs="*", default=[])
    ap.add_argument("--after-env", nargs="*", default=[])
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    builds = [Path(args.before).resolve(), Path(args.after).resolve()]
    extra = [dict(e.split("=", 1) for e in args.before_env), dict(e.split("=", 1) for e in args.after_env)]

    lines = [f"### {args.title}", ""]
    if args.label:
        lines += [args.label, ""]
    for k, name in enumerate(("before", "after")):
        if extra[k]:
            lines += [f"Environment of the {name} runs: "
                      + ", ".join(f"`{n}={v}`" for n, v in extra[k].items()) + ".", ""]
    if not args.scenes_only:
        best = [{}, {}]
        for _ in range(args.rounds):
            for k, b in enumerate(builds):
                for key, t in bench_rows(b / "bench" / "bench_contact_geometry").items():
                    best[k][key] = min(t, best[k].get(key, np.inf))
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
        lines += ["", f"Whole scenes: CPU seconds (user + system) of the run, best and median of "
                  f"{args.rounds} alternating rounds; outputs compared dataset by dataset.", "",
                  "| scene | before CPU s best / median | after CPU s best / median | speed-up (best) "
                  "| outputs |", "|---|---:|---:|---:|---|"]
        with tempfile.TemporaryDirectory() as d:
            tmp = Path(d)
            env = []
            for k in range(2):
                env.append(dict(os.environ, RAILDYN_CACHE_DIR=str(tmp / "cache"), **extra[k]))
            for scene in args.scenes:
                cpu = [[], []]
                for k, b in enumerate(builds):     # untimed: builds a contact table once
                    scene_cpu(b / "bin" / "raildyn", REPO / "inputs" / scene, tmp / f"{k}.h5", env[k])
                for _ in range(args.rounds):
                    for k, b in enumerate(builds):
                        cpu[k].append(scene_cpu(b / "bin" / "raildyn", REPO / "inputs" / scene,
                                                tmp / f"{k}.h5", env[k]))
                n, ndiff, worst, name = h5_difference(tmp / "0.h5", tmp / "1.h5")
                same = (f"identical ({n} datasets)" if ndiff == 0 else
                        f"{ndiff} of {n} datasets differ, largest {worst:.1e} of range ({name})")
                best = [min(c) for c in cpu]
                med = [float(np.median(c)) for c in cpu]
                lines.append(f"| {scene} | {best[0]:.2f} / {med[0]:.2f} | {best[1]:.2f} / {med[1]:.2f} "
                             f"| {best[0] / best[1]:.2f} | {same} |")

    load = Path("/proc/loadavg").read_text().split()[:3]
    lines += ["", f"Host: load average {' '.join(load)} at the end of the run (shared machine)."]
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        sys.path.insert(0, str(REPO / "bench"))
        from performance_section import write_section
        write_section(args.section, text)


if __name__ == "__main__":
    main()
