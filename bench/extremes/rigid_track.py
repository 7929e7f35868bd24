#!/usr/bin/env python3
"""Past the critical speed on rigid and on flexible track: why the extremes matrix runs its
past-critical scenes on flexible track (bench/extremes/run.py, issue 14 item 5).

The past-critical scene of the matrix (straight track, 1.25 times the vehicle's linear critical
speed, a lateral pulse on wheelset 1) run with the tables level (FASTSIM with the smooth clip)
of the Manchester V1 vehicle and of the TGV 001 vehicle with S1002/60E1 profiles, on the rigid
design track and on the flexible track of inputs/tracks/p2_flexible_track.nml (a rail body under
each wheel on pads and ballast), with quasi-static and with elastic normal contact, the elastic
one at three contact dampings (the TGV 001 decks' 2e5 N s/m and 3 and 10 times it). Per run:
the share of output samples in which some wheel has no contact, the largest sampled lateral
force Y and wheel load Q, and for every sample with a wheel off its rail the other wheel's
Y/Q against the closed-form tipping limit of its loaded contact, Y/Q = y_c / r
(|wheel_point_y| / |wheel_point_z|: the moment balance about that contact of the forces at the
wheelset centre, tests/python/test_quasi_static_tipping.py): the share of those samples at a
flange hit (ratio >= 0.85) and the ratio's range.

    python3 bench/extremes/rigid_track.py [--build DIR] [--work DIR] [--jobs N] [--no-write]
        [--json FILE] [--from-json FILE]

Writes the section `rigid_track_past_critical` of docs/performance.md unless --no-write.
"""
from __future__ import annotations

import concurrent.futures
import json
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "bench"))
from performance_section import bench_arguments, earlier_json, measurement_start, write_section  # noqa: E402
sys.path.insert(0, str(HERE))
import run as matrix  # noqa: E402  (the extremes matrix: its vehicles, pulse and flexible track)
from tipping import lift_ratios  # noqa: E402

FLEXIBLE = (HERE / "scenes" / matrix.FLEXIBLE_TRACK).resolve()
_MATRIX_VEHICLES = {v.key: v for v in matrix.vehicles()}
#: (vehicle title, vehicle deck, speed [m/s]: the matrix's past-critical speed, 1.25 x the linear
#: critical speed)
VEHICLES = {key: (title, HERE / _MATRIX_VEHICLES[mkey].deck, float(round(1.25 * _MATRIX_VEHICLES[mkey].critical_speed)))
            for key, mkey, title in (("manchester", "manchester", "Manchester V1"),
                                     ("tgv", "tgv_profile", "TGV 001 S1002/60E1"))}
#: (vehicle, normal contact, contact damping [N s/m] or None, flexible track)
CASES = [("manchester", "quasi_static", None, False), ("manchester", "quasi_static", None, True),
         ("manchester", "elastic", 2.0e5, False), ("manchester", "elastic", 6.0e5, False),
         ("manchester", "elastic", 2.0e6, False), ("manchester", "elastic", 2.0e5, True),
         ("tgv", "quasi_static", None, False), ("tgv", "quasi_static", None, True),
         ("tgv", "elastic", 2.0e5, False), ("tgv", "elastic", 6.0e5, False),
         ("tgv", "elastic", 2.0e6, False), ("tgv", "elastic", 2.0e5, True)]


def case_name(case) -> str:
    veh, normal, damping, flexible = case
    d = f", damping {damping:.0e} N s/m" if damping is not None else ""
    return f"{VEHICLES[veh][0]}, {normal.replace('_', '-')}{d}, {'flexible' if flexible else 'rigid'} track"


def deck_text(case, t_end: float = 3.0, wheelset: str | None = None) -> str:
    """The case's deck; `wheelset` replaces its wheelset overrides (the contact level)."""
    veh, normal, damping, flexible = case
    _, vehicle, speed = VEHICLES[veh]
    over = f"contact_geometry = 'table', creep_law = 'fastsim', fastsim_saturation_width = 0.2, normal_contact = '{normal}'"
    if damping is not None:
        over += f", contact_damping = {damping:.1f}"
    if wheelset is not None:
        over = wheelset
    lines = [f"&include file = {str(vehicle)!r} /",
             f"&simulation title = 'rigid_track {case_name(case)}', t_end = {t_end}, speed = {speed},",
             "      start_sigma = 20.0, equilibrium = 'preload' /",
             "&track gauge = 1.435, rail_inclination = 0.025 /",
             "&segment type = 'straight', length = 1000.0 /", matrix.PULSE]
    if flexible:
        lines.append(f"&include file = {str(FLEXIBLE)!r} /")
    lines += [f"&wheelset name = 'w{k}', {over} /" for k in range(1, 5)]
    return "\n".join(lines) + "\n"


def measure(out: Path) -> dict:
    m = {"lost_share": 0.0, "max_y": 0.0, "max_q": 0.0, "lost": 0, "at_hit": 0, "ratio_min": None,
         "ratio_max": None}
    with h5py.File(out, "r") as f:
        n = len(f["time"][()])
        any_lost = np.zeros(n, bool)
        for ws in f["wheelsets"]:
            for side in ("left", "right"):
                wheel = f[f"wheelsets/{ws}/{side}/wheel"][()]
                m["max_y"] = max(m["max_y"], float(np.abs(wheel[:, 2]).max()))
                m["max_q"] = max(m["max_q"], float(wheel[:, 3].max()))
                any_lost |= wheel[:, 0] == 0
        m["lost_share"] = float(any_lost.mean())
        r = lift_ratios(f)
        m["lost"] = int(r.size)
        if r.size:
            m["at_hit"] = int((r >= 0.85).sum())
            m["ratio_min"], m["ratio_max"] = float(r.min()), float(r.max())
    return m


def run_case(exe: Path, work: Path, i: int, case, t_end: float = 3.0) -> dict:
    deck = work / f"case{i:02d}.nml"
    deck.write_text(deck_text(case, t_end))
    out = work / f"case{i:02d}.h5"
    proc = subprocess.Popen([str(exe), "run", str(deck), "-o", str(out), "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    err = proc.stderr.read()
    _, status, usage = os.wait4(proc.pid, 0)       # this runner's own CPU time
    proc.returncode = os.waitstatus_to_exitcode(status)
    rec = {"name": case_name(case), "exit": proc.returncode, "cpu": usage.ru_utime + usage.ru_stime,
           "error": err.strip().splitlines()[-1:] if err.strip() else []}
    if proc.returncode == 0:
        rec.update(measure(out))
    return rec


def render(rows: list, meta: dict) -> str:
    out = [f"Measured {meta['when']} on commit {meta['rev']} (bench/extremes/rigid_track.py): the past-critical "
           "scene of the extremes matrix (straight track at 1.25 x the linear critical speed, the lateral pulse on "
           "wheelset 1; 3 s, output every 0.01 s), tables with FASTSIM (smooth clip). lost = share of the samples "
           "with some wheel without contact; at a flange hit = of the samples with a wheel off its rail, those in "
           "which the other wheel's Y/Q is at least 0.85 of its contact's tipping limit y_c / r; ratio = that "
           "Y/Q over the limit, range.", "",
           "| case | exit | CPU s | lost [% of samples] | largest Y [kN] | largest Q [kN] | wheels off the rail at a flange hit | ratio |",
           "|---|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        if r["exit"] != 0:
            out.append(f"| {r['name']} | {r['exit']} | {r['cpu']:.1f} | - | - | - | - | {' '.join(r['error'])[:120]} |")
            continue
        hit = f"{r['at_hit']} of {r['lost']}" if r["lost"] else "-"
        ratio = f"{r['ratio_min']:.2f}-{r['ratio_max']:.2f}" if r["lost"] else "-"
        out.append(f"| {r['name']} | 0 | {r['cpu']:.1f} | {100 * r['lost_share']:.1f} | {r['max_y'] / 1e3:.1f} | "
                   f"{r['max_q'] / 1e3:.1f} | {hit} | {ratio} |")
    return "\n".join(out) + "\n"


def main(argv=None) -> int:
    ap = bench_arguments(__doc__)
    ap.add_argument("--work", default=None, help="run folder (default <build>/rigid_track)")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args(argv)
    data = earlier_json(args)
    if data is None:
        exe, rev, start = measurement_start(args)
        work = Path(args.work or Path(args.build) / "rigid_track").resolve()
        work.mkdir(parents=True, exist_ok=True)
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(lambda ic: run_case(exe, work, *ic), enumerate(CASES)))
        data = {"meta": {"when": start.strftime("%Y-%m-%d %H:%M UTC"), "rev": rev}, "rows": rows}
        if args.json:
            Path(args.json).write_text(json.dumps(data, indent=1))
    text = render(data["rows"], data["meta"])
    print(text)
    if not args.no_write:
        write_section("rigid_track_past_critical", text, "### Past the critical speed on rigid and on flexible track")
    return 0


if __name__ == "__main__":
    sys.exit(main())
