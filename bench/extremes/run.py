#!/usr/bin/env python3
"""Stability at the extremes (issue 14 item 5): full scenes at the edges of the operating range,
for every fidelity level of the map (bench/fidelity_map/run.py) that applies to each vehicle,
run as a campaign (raildyn.campaign: local processes or a Slurm job array) and classified.

The matrix is not the full factorial: one axis at a time around a base case (straight track,
8 m/s), each axis at its extremes, times the levels.

- speed: 0.5 m/s (walking pace), 8 m/s (base), 1.25 x the linear critical speed of the vehicle
  on straight track (`raildyn critical-speed DECK --method linear --speeds 5,120`, measured
  2026-11-28 on the scene decks: Manchester V1 80.2 m/s, TGV 001 knife edge 105.9 m/s, TGV 001
  S1002/60E1 104.7 m/s; so 100, 132 and 131 m/s), with a lateral pulse on wheelset 1 (15.7 kN,
  0.1 s, as inputs/tgv_vehicle_straight.nml) to start any hunting, on FLEXIBLE track (a rail
  body under each wheel on the pads and ballast of inputs/tracks/p2_flexible_track.nml): the
  hunting wheelsets hit their flanges, and on rigid track each hit is an impact against the
  Hertz contact alone, which lifts wheels in a way that depends on the modelling assumptions
  rather than on the vehicle (measured, bench/extremes/rigid_track.py: with quasi-static
  normal contact the wheelset tips over the flange contact at the closed-form limit
  Y/Q = y_c / r, Y ~ 160 kN; with elastic contact the flange impacts throw the wheels off as
  often as the assumed contact damping allows: TGV 14.6 % of the samples at 2e5 N s/m, none at
  2e6, Manchester 46 % and 19 %; on the flexible track no wheel of those runs leaves its rail
  and Y stays below ~150 kN). The other scenes' flange contacts are quasi-static and keep the
  rigid track;
- radius: R 80 m and R 150 m without cant at the base speed (cant deficiency
  h_d = V^2 s / (g R) with s = 1.5 m, g = 9.80665: 122 mm at R 80 m, 65 mm at R 150 m), and the
  straight base;
- friction: 0.05 and 0.6 in R 150 m at the base speed (the decks' own 0.4 / 0.45 is the R 150 m
  scene of the radius axis);
- cant: R 150 m with 100 mm cant at 15.66 m/s, cant deficiency 150 mm
  (V = sqrt(g R (h + h_d) / s) = sqrt(9.80665 x 150 x 0.25 / 1.5) = 15.66 m/s); R 150 m with
  150 mm cant at 0.5 m/s, cant excess 150 mm (V^2 s / (g R) = 0.25 mm);
- flange climb: R 80 m without cant, 2 m/s, friction 0.6, a lateral force of 120 kN on
  wheelset 1 towards the outer rail from 0.5 s (Nadal's limit at a 70 deg flange and mu 0.6 is
  Y/Q = 0.81: about 45 kN on a 55 kN wheel; the expected outcome is a physics stop: derailment,
  or the lift-off of the inner wheel, which the force's moment about the flange contact unloads);
- lift-off: straight, 2 m/s, a roll moment of 150 kN m on wheelset 1 from 0.5 s. It moves
  M / (2 b) of load from one wheel to the other (contact points at b = 0.75 m), so it unloads a
  wheel at 2 b Q: Manchester Q = 44 482 kg g / 8 = 54.5 kN, 82 kN m; TGV Q = 55 240 kg g / 8 =
  67.7 kN, 102 kN m (measured on Manchester, tables: 60 kN m leaves the wheel 14.7 kN, 54.5 - 60 /
  1.5 = 14.5 kN); the expected outcome is the lift-off stop.

The curves at 8 and 15.66 m/s are entered from straight track through a 20 m transition and
run until the trailing wheelset is 10 m into the curve (6.7 s at 8 m/s, 3.4 s at 15.66 m/s);
the slow curve scenes (cant excess, flange climb) start inside their curve (the static
equilibrium solve holds the wheelsets centred, docs/input_reference.md &simulation
equilibrium); the straight scenes last 3 s (1.5 m at walking pace, 300-400 m past the critical
speed).

Levels: every fidelity level of the map, read from bench/fidelity_map/run.py (deck overrides
of every wheelset or of &solver; map_levels): for the Manchester vehicle (profile contact,
quasi-static normal contact) and the TGV 001 with S1002/60E1 (elastic normal contact) the tables
and the online strips at 0.2 and 0.1 mm, each with linear+SHE, Polach and FASTSIM (smooth clip),
the other normal contact where the map has it (Manchester: elastic, on tables and on 0.2 mm
strips, with the TGV 001 decks' contact damping, 2e5 N s/m: inputs/vehicles/tgv001_bogie.nml's
ASSUMPTION; undamped, the wheels' ~180 Hz mode on the Hertz contact rang after every flange
contact and the wheels hopped: contact loss in R 80 m, R 150 m at friction 0.6 and at 150 mm
deficiency, measured 2026-11-30; TGV: quasi-static on tables), the map's reference (strips 0.1
mm, FASTSIM, BDF at rtol 1e-7, atol 1e-10) and the integrators Adams, erk and rk4 (1e-4 s) on
the map's fastest level (Manchester: tables with linear+SHE; TGV profile: tables with FASTSIM and
quasi-static contact); the TGV 001 with knife-edge contact: linear, Polach and FASTSIM and on
Polach the integrators (the map's knife-edge scene runs the TGV profile vehicle's levels too:
they are that vehicle's rows here). The study forms of the strip normal force (centroid,
potential) are not levels (docs/performance.md "Which fidelity level for what").

A level does not apply where the deck would be refused (the unsaturated linear law reads no
friction: the friction scenes), where the model has nothing to say (knife-edge contact has no
flange: flange climb) or where it leaves its range before anything else stops it (the
unsaturated linear law on knife-edge contact in the curves with cant deficiency: creep forces
beyond the wheel load, DEFICIENCY_SCENES).

Outcome of a run:
- completed: exit 0, results status 'completed', every value of every series finite, and no
  wheel without contact in any output sample (the run's notes) unless the scene is about
  losing contact or every such wheel's wheelset tipped over its other wheel's contact: that
  wheel's Y/Q at 0.85-1.0 of the closed-form tipping limit y_c / r at every such sample
  (bench/extremes/tipping.py; a physical outcome of the forces, the reason column says so);
- contact loss: exit 0 with finite results and a wheel off its rail that the tipping does not
  explain (not shown physical; not as expected);
- physics stop: exit 3 with a documented reason (derailment, wheel lift-off; the runner's
  message) reached by the run (an exit 3 of the static equilibrium solve before t = 0 is a
  FAILURE: the scene did not run);
- FAILURE: anything else - a solver failure (exit 2), another exit status, a non-finite value, an
  undocumented exit-3 reason, or a run still going at the wall-clock limit (--timeout: a
  hang).

CPU s = user + system seconds of the runner process (measured by a wrapper around the runner
that the campaign runs instead of it: os.wait4's resource usage of the runner alone), steps and
RHS calls from the results file's /meta/solver (RHS: the method's + the difference-quotient
Jacobian's).

    python3 bench/extremes/run.py [--build DIR] [--jobs N] [--backend local|slurm]
        [--slurm-option OPT] [--quick] [--only VEHICLE:SCENE:LEVEL ...] [--timeout S]
        [--work DIR] [--no-write] [--no-run] [--keep-published] [--when TEXT]

Writes bench/extremes/scenes/*.nml (the scene decks, tracked), runs the matrix under
<build>/extremes (one campaign per vehicle and scene; a rerun reuses completed runs whose
inputs and runner did not change), prints the table and writes it into docs/performance.md
(section extremes) unless --no-write or --quick or --only. --keep-published completes a partial
rerun (--only, or a work folder with rows not run) with the published rows it did not rerun,
marked '(earlier run)', and writes the whole table (with --only too).
"""
from __future__ import annotations

import argparse
import hashlib
import importlib.util
import json
import math
import os
import platform
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "bench"))
from raildyn import campaign as C  # noqa: E402
from raildyn.executable import EXIT_OUTCOMES  # noqa: E402
from raildyn.results import Results, open_results_file  # noqa: E402
sys.path.insert(0, str(HERE))
from tipping import TIPPING_SHARE, all_tipped, lift_ratios  # noqa: E402

#: The fidelity map (bench/fidelity_map/run.py): the matrix's levels are its levels, read from it
#: (a module of that name would clash with this one's, hence the spec).
_spec = importlib.util.spec_from_file_location("fidelity_map_run", REPO / "bench" / "fidelity_map" / "run.py")
fidelity_map = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fidelity_map)


@dataclass
class Level:
    name: str
    wheelset: dict = field(default_factory=dict)   #: applied to every wheelset
    solver: dict = field(default_factory=dict)
    #: scenes (keys) this level does not apply to, with the reason
    not_for: dict = field(default_factory=dict)


@dataclass
class Scene:
    key: str
    title: str
    track: str                 #: key of TRACKS
    speed: float
    friction: float | None = None
    extra: list = field(default_factory=list)   #: deck lines (forces)
    #: the scene is about a wheel losing contact: contact-loss notes are expected
    contact_loss_expected: bool = False
    #: what the physics should do: "completed", or the physics stops' reasons ("|"-separated)
    expect: str = "completed"
    t_end: float = 3.0
    #: on flexible track (inputs/tracks/p2_flexible_track.nml) instead of the rigid design track
    flexible_track: bool = False


@dataclass
class Vehicle:
    key: str
    title: str
    deck: str                  #: bench/extremes/<deck>: the vehicle with its base models
    wheelsets: list
    levels: list
    critical_speed: float      #: linear, straight track [m/s] (module docstring)
    friction_default: float | None


#: Track geometries: (description, vehicle start sigma [m], deck lines). The wheelsets are at most
#: 10.85 m from the vehicle reference. "in": a 20 m transition (raildyn refuses a curvature
#: jump), then the curve; the reference starts 12 m into the curve, so every wheelset starts
#: inside it (the scenes at walking pace and the flange climb: the static solve holds the
#: wheelsets centred, a start the slow scenes leave gently). "entry": 30 m of straight, a 20 m
#: transition (curvature and cant ramped together), then the curve; the leading wheelset starts
#: 1.2 m before the transition and the run lasts until the trailing one is 10 m into the curve
#: (ENTRY_DISTANCE): a start inside a tight curve at speed would throw the centred wheelsets
#: at the flanges, a load no vehicle meets.
CLOTHOID = "&segment type = 'clothoid', length = 20.0, radius = {r}, side = 'right', cant = {h} /"
CURVE = "&segment type = 'curve', length = 400.0, radius = {r}, side = 'right', cant = {h} /"
ENTRY_START = 18.0
#: from the start to the trailing wheelset (reference - 10.85 m) 10 m into the curve (at 60 m)
ENTRY_DISTANCE = 60.0 + 10.85 - ENTRY_START
GEOMETRIES = {"r80": ("R 80 m, no cant", 80.0, 0.0), "r150": ("R 150 m, no cant", 150.0, 0.0),
              "r150_c100": ("R 150 m, 100 mm cant", 150.0, 0.100),
              "r150_c150": ("R 150 m, 150 mm cant", 150.0, 0.150)}
TRACKS = {
    "straight": ("straight", 20.0, ["&segment type = 'straight', length = 1000.0 /"]),
    **{f"{key}_in": (desc, 32.0, [CLOTHOID.format(r=r, h=h), CURVE.format(r=r, h=h)])
       for key, (desc, r, h) in GEOMETRIES.items()},
    **{f"{key}_entry": (desc + ", entered from straight track", ENTRY_START,
                        ["&segment type = 'straight', length = 30.0 /", CLOTHOID.format(r=r, h=h),
                         CURVE.format(r=r, h=h)])
       for key, (desc, r, h) in GEOMETRIES.items()},
}

#: the flexible track's rail bodies, pads and attachments, relative to scenes/ (the past-critical
#: scenes; module docstring)
FLEXIBLE_TRACK = "../../../inputs/tracks/p2_flexible_track.nml"

BASE_SPEED = 8.0
#: lateral pulse on wheelset 1 on straight track (inputs/tgv_vehicle_straight.nml's)
PULSE = "&external_force body = 'ws1', frame = 'track', force = 0.0, 15700.0, 0.0, t_start = 0.1, t_end = 0.2 /"
#: flange climb: towards the outer rail of a right-hand curve, the left one (+Y_T)
CLIMB = "&external_force body = 'ws1', frame = 'track', force = 0.0, 120.0e3, 0.0, t_start = 0.5 /"
#: lift-off: roll moment lifting the left wheel of wheelset 1 (1.5-1.8 times what unloads it)
LIFT = "&external_force body = 'ws1', frame = 'track', moment = 150.0e3, 0.0, 0.0, t_start = 0.5 /"


def scenes_for(v: Vehicle) -> list[Scene]:
    vc = round(1.25 * v.critical_speed)

    def entry(speed):
        return math.ceil(10 * ENTRY_DISTANCE / speed) / 10
    return [
        Scene("walk", "straight, 0.5 m/s", "straight", 0.5, extra=[PULSE]),
        Scene("base", f"straight, {BASE_SPEED:g} m/s (base)", "straight", BASE_SPEED, extra=[PULSE]),
        Scene("past_critical", f"straight, {vc} m/s (1.25 x linear critical {v.critical_speed:.1f} m/s), "
              "flexible track", "straight", float(vc), extra=[PULSE], flexible_track=True),
        Scene("r80", f"R 80 m, {BASE_SPEED:g} m/s (deficiency 122 mm)", "r80_entry", BASE_SPEED,
              t_end=entry(BASE_SPEED)),
        Scene("r150", f"R 150 m, {BASE_SPEED:g} m/s (deficiency 65 mm)", "r150_entry", BASE_SPEED,
              t_end=entry(BASE_SPEED)),
        Scene("mu005", f"R 150 m, {BASE_SPEED:g} m/s, friction 0.05", "r150_entry", BASE_SPEED, friction=0.05,
              t_end=entry(BASE_SPEED)),
        Scene("mu06", f"R 150 m, {BASE_SPEED:g} m/s, friction 0.6", "r150_entry", BASE_SPEED, friction=0.6,
              t_end=entry(BASE_SPEED)),
        Scene("deficiency150", "R 150 m, cant 100 mm, 15.66 m/s (deficiency 150 mm)", "r150_c100_entry", 15.66,
              t_end=entry(15.66)),
        Scene("excess150", "R 150 m, cant 150 mm, 0.5 m/s (excess 150 mm)", "r150_c150_in", 0.5),
        Scene("flange_climb", "R 80 m, 2 m/s, friction 0.6, 120 kN outwards on wheelset 1", "r80_in", 2.0,
              friction=0.6, extra=[CLIMB], contact_loss_expected=True, expect="derail|lift-off"),
        Scene("lift_off", "straight, 2 m/s, 150 kN m roll moment on wheelset 1", "straight", 2.0,
              extra=[LIFT], contact_loss_expected=True, expect="lift-off"),
    ]


FRICTION_SCENES = {"mu005": "the unsaturated linear law reads no friction",
                   "mu06": "the unsaturated linear law reads no friction",
                   "flange_climb": "knife-edge contact has no flange"}
#: The unsaturated linear law on knife-edge contact in a curve with cant deficiency: without a
#: flange nothing holds the wheelsets, they drift outwards (0.18 m in R 80 m at 8 m/s by 2.3 s)
#: and the longitudinal creepage conicity y / r0 grows with them (4 % there); creep forces
#: without a friction limit then exceed the wheel load (measured in R 80 m: |F| > Q from 1.1 s,
#: 18 Q on wheelset 1 at 2.28 s; R 150 m from 1.4 s; 150 mm deficiency from 0.7 s), a state no
#: wheel reaches. The run ends where a wheel unloads under percent creepages: the unsaturated
#: force G a b C xi ~ Q^(2/3) has an unbounded derivative Q^(-1/3) as Q -> 0, so the error test
#: fails or the lift-off stop is reached depending on the step sequence (R 80 m: CVODE error
#: test at 2.285 s with output every 0.01 s, lift-off at 2.364 s with output every 0.5 ms).
#: The saturating laws bound the force by mu Q and drift to the lift-off stop.
DEFICIENCY_SCENES = {k: "unsaturated linear law in a curve with cant deficiency: creep forces beyond the wheel "
                        "load (run.py DEFICIENCY_SCENES)" for k in ("r80", "r150", "deficiency150")}


def deck_settings(text: str) -> dict:
    """Deck settings "a = 'x', b = 0.2" (a fidelity-map level's) as campaign overrides
    {"a": "x", "b": 0.2}."""
    out = {}
    for key, val in re.findall(r"(\w+)\s*=\s*('[^']*'|[^,]+)", text):
        val = val.strip()
        out[key] = val[1:-1] if val.startswith("'") else (int(val) if re.fullmatch(r"[+-]?\d+", val) else float(val))
    return out


def knife_edge_not_for(name: str) -> dict:
    """Scenes a knife-edge level does not apply to (module docstring): the unsaturated linear law
    reads no friction and leaves its range in the curves with cant deficiency; no knife-edge
    level has a flange to climb."""
    if name.startswith("knife edge linear"):
        return {**FRICTION_SCENES, **DEFICIENCY_SCENES}
    return {"flange_climb": FRICTION_SCENES["flange_climb"]}


def map_levels() -> dict[str, list[Level]]:
    """Every fidelity level of the map (its scenes' levels, the reference, the integrators on
    the fastest level) by matrix vehicle, in the map's order. A map scene's key is the key of
    the matrix's vehicle of the same model, but for the knife-edge scene's levels with
    S1002/60E1 contact (they set fidelity_map.PROFILE): those are the TGV profile vehicle's, and
    a level the map runs in two scenes is one level here."""
    out = {"manchester": [], "tgv_profile": [], "tgv_knife_edge": []}
    profile_keys = set(deck_settings(fidelity_map.PROFILE))
    for sc in fidelity_map.scene_list():
        for ml in sc.levels + fidelity_map.integrator_levels(sc):
            wheelset = deck_settings(ml.wheelset)
            vehicle = sc.key
            if vehicle == "tgv_knife_edge" and profile_keys <= set(wheelset):
                vehicle = "tgv_profile"
                wheelset = {k: v for k, v in wheelset.items() if k not in profile_keys}
            lv = Level(ml.name, wheelset, deck_settings(ml.solver),
                       knife_edge_not_for(ml.name) if vehicle == "tgv_knife_edge" else {})
            same = [o for o in out[vehicle] if o.name == lv.name]
            if same and (same[0].wheelset, same[0].solver) != (lv.wheelset, lv.solver):
                raise ValueError(f"fidelity map: two levels named {lv.name!r} for {vehicle} differ")
            if not same:
                out[vehicle].append(lv)
    return out


def vehicles() -> list[Vehicle]:
    ws4 = ["w1", "w2", "w3", "w4"]
    levels = map_levels()
    return [Vehicle("manchester", "Manchester V1, S1002/60E1, quasi-static normal contact", "manchester_vehicle.nml",
                    ws4, levels["manchester"], 80.169, 0.4),
            Vehicle("tgv_profile", "TGV 001, S1002/60E1, elastic normal contact", "tgv_profile_vehicle.nml",
                    ws4, levels["tgv_profile"], 104.727, 0.45),
            Vehicle("tgv_knife_edge", "TGV 001, knife edge", "tgv_knife_edge_vehicle.nml", ws4,
                    levels["tgv_knife_edge"], 105.924, None)]


def scene_deck_text(v: Vehicle, s: Scene) -> str:
    desc, start, segs = TRACKS[s.track]
    lines = [f"! bench/extremes: {v.title}; {s.title} (bench/extremes/run.py writes this file)",
             f"&include file = '../{v.deck}' /",
             f"&simulation title = 'extremes: {v.key} {s.key}', t_end = {s.t_end}, speed = {s.speed},",
             f"      start_sigma = {start}, equilibrium = 'preload' /",
             "&track gauge = 1.435, rail_inclination = 0.025 /", *segs, *s.extra]
    if s.flexible_track:
        lines.append(f"&include file = '{FLEXIBLE_TRACK}' /")
    if s.friction is not None:
        # the knife-edge vehicle's own law (unsaturated linear) reads no friction: Polach here,
        # the levels set their own law
        law = ", creep_law = 'polach'" if v.friction_default is None else ""
        lines += [f"&wheelset name = '{w}', friction = {s.friction}{law} /" for w in v.wheelsets]
    return "\n".join(lines) + "\n"


def write_scene_decks() -> dict:
    """bench/extremes/scenes/<vehicle>__<scene>.nml; returns {(vehicle, scene): path}."""
    out = {}
    d = HERE / "scenes"
    d.mkdir(exist_ok=True)
    for v in vehicles():
        for s in scenes_for(v):
            if all(s.key in lv.not_for for lv in v.levels):
                continue
            p = d / f"{v.key}__{s.key}.nml"
            text = scene_deck_text(v, s)
            if not p.exists() or p.read_text() != text:
                p.write_text(text)
            out[(v.key, s.key)] = p
    return out


def level_params(v: Vehicle, lv: Level) -> dict:
    """The campaign overrides of a level (raildyn.campaign keys)."""
    p = {f"wheelset[{w}].{k}": val for w in v.wheelsets for k, val in lv.wheelset.items()}
    p.update({f"solver.{k}": val for k, val in lv.solver.items()})
    return p


# ------------------------------------------------------------------------------------------
# the measured runner: the campaign runs this wrapper instead of raildyn

WRAPPER = '''#!{python}
# bench/extremes: runs {exe} (sha256 {sha}) and, for `run`, records its CPU time (user +
# system of that process alone, os.wait4) and stops it at a CPU-time limit of {cpu_limit} s
# (RLIMIT_CPU: SIGXCPU) or a wall-clock limit of {limit} s (exit 124; measure.json says which)
# - the campaign records the exit status as usual. The CPU limit tells a hang from a slow run
# on a loaded machine; the wall limit catches a run that waits without computing.
import json, os, resource, signal, subprocess, sys, threading, time
exe = {exe!r}
args = sys.argv[1:]
if not args or args[0] != "run":
    os.execv(exe, [exe] + args)
def limit_cpu():
    resource.setrlimit(resource.RLIMIT_CPU, ({cpu_limit}, {cpu_limit} + 10))
proc = subprocess.Popen([exe] + args, preexec_fn=limit_cpu)
timed_out = threading.Event()
def stop():
    timed_out.set()
    proc.terminate()
    try:
        proc.wait(10)
    except subprocess.TimeoutExpired:
        proc.kill()
signal.signal(signal.SIGINT, lambda *a: proc.send_signal(signal.SIGINT))
timer = threading.Timer({limit}, stop)
timer.start()
t0 = time.perf_counter()
while True:
    try:
        _, status, usage = os.wait4(proc.pid, 0)
        break
    except InterruptedError:
        continue
wall = time.perf_counter() - t0
timer.cancel()
code = os.waitstatus_to_exitcode(status)
cpu = usage.ru_utime + usage.ru_stime
over = "wall" if timed_out.is_set() else ("cpu" if code in (-signal.SIGXCPU, -signal.SIGKILL) and cpu >= {cpu_limit} else "")
with open("measure.json", "w") as f:
    json.dump({{"cpu": cpu, "wall": wall, "timed_out": over, "limit": {limit}, "cpu_limit": {cpu_limit},
               "exit": code}}, f)
if over:
    sys.exit(124)
if code < 0:
    signal.signal(-code, signal.SIG_DFL)
    os.kill(os.getpid(), -code)
sys.exit(code)
'''


def write_wrapper(work: Path, exe: Path, limit: float, cpu_limit: int) -> Path:
    sha = hashlib.sha256(exe.read_bytes()).hexdigest()
    path = work / "raildyn-measured"
    text = WRAPPER.format(python=sys.executable, exe=str(exe), sha=sha, limit=float(limit), cpu_limit=int(cpu_limit))
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
        path.chmod(0o755)
    return path


# ------------------------------------------------------------------------------------------
# classification

DOCUMENTED_STOPS = ("derail", "lift-off", "flange climb")


@dataclass
class Row:
    vehicle: str
    scene: str
    level: str
    outcome: str = ""          #: completed / physics stop / FAILURE / n/a
    reason: str = ""
    steps: int = 0
    rhs: int = 0
    rhs_jac: int = 0
    cpu: float = float("nan")
    wall: float = float("nan")
    t_reached: float = float("nan")
    expected: bool = True      #: the outcome is what the scene's physics asks for
    #: taken from the published table (--keep-published), not classified from a run folder
    kept: bool = False


def _nonfinite(path: Path) -> str:
    """'' when every value of every series (rows up to the last written time) is finite, else
    the first series with a non-finite value and its time."""
    with open_results_file(path) as f:
        t = np.asarray(f["time"][...], float)
        n = int(np.flatnonzero(np.isfinite(t))[-1]) + 1 if np.isfinite(t).any() else 0
        if n < t.size and np.isfinite(t[n:]).any():
            return "time: non-finite value inside the written rows"
        found = []

        def visit(name, obj):
            if found or name.startswith("meta") or not hasattr(obj, "dtype") or obj.dtype.kind != "f":
                return
            if obj.ndim == 0 or obj.shape[0] != t.size:
                return
            data = np.asarray(obj[:n], float)
            bad = ~np.isfinite(data)
            if bad.any():
                row = int(np.flatnonzero(bad.reshape(n, -1).any(axis=1))[0])
                found.append(f"{name}: non-finite value at t = {t[row]:.4g} s")
        f.visititems(visit)
        return found[0] if found else ""


def _max_yq(path: Path) -> float:
    """The largest derailment quotient Y/Q of any wheelset over the run (unfiltered samples)."""
    with Results(path) as r:
        vals = [np.nanmax(r.get(c + ":derailment_quotient")) for c in r.channels()
                if c.startswith("wheelsets/") and c.endswith("/summary")]
    return float(max(vals)) if vals else float("nan")


def _lift_ratios(path: Path) -> np.ndarray:
    """Per sample and wheel without contact, the other wheel's Y/Q over its tipping limit
    (bench/extremes/tipping.py)."""
    with open_results_file(path) as f:
        return lift_ratios(f)


def _meta(path: Path) -> dict:
    with open_results_file(path) as f:
        m = f["meta"]
        attrs = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in m.attrs.items()}
        if "solver" in m:
            attrs["solver"] = {k: (v.item() if hasattr(v, "item") else v) for k, v in m["solver"].attrs.items()}
        return attrs


def _last_message(run: Path) -> str:
    lines = [ln.strip() for ln in (run / "log.txt").read_text(errors="replace").splitlines() if ln.strip()]
    msg = next((ln for ln in reversed(lines) if "error" in ln.lower()), lines[-1] if lines else "")
    return msg.removeprefix("raildyn: error: ")


def summarise(msg: str, physics: bool = False) -> str:
    """The runner's error line shortened to what a table can hold: the integrator, its flag
    and the time reached, then the root cause (the right-hand side's error, after 'rhs at t =
    ... s: '), without the module prefix."""
    root = msg
    if "rhs at t = " in msg:
        root = msg.rsplit("rhs at t = ", 1)[1].split(" s: ", 1)[-1]
    root = root.removeprefix("multibody%rhs: ").strip()
    if physics:   # the stop's own message says what and when
        return root
    integ = re.search(r"integrator '(\w+)'", msg)
    flag = re.search(r"(\w+) \(flag -?\d+\)", msg)
    reached = re.search(r"time reached ([-+0-9.Ee]+) s", msg)
    if integ and flag and reached:
        head = f"{integ.group(1)} {flag.group(1)} at t = {float(reached.group(1)):.4g} s"
        return head if root == msg else f"{head}: {root}"
    return root


def strip_paths(text: str) -> str:
    return re.sub(r"(?:/[\w.\-]+)+/(?=[\w.\-]+)", "", text)


def classify(run: Path, scene: Scene) -> Row:
    """The outcome of one run folder (status.json, measure.json, log.txt, results.h5)."""
    row = Row("", scene.key, "")
    status = json.loads((run / "status.json").read_text()) if (run / "status.json").exists() else {}
    meas = json.loads((run / "measure.json").read_text()) if (run / "measure.json").exists() else {}
    row.cpu, row.wall = meas.get("cpu", float("nan")), meas.get("wall", float("nan"))
    code = status.get("exit_code")
    res = run / "results.h5"
    meta = {}
    if res.exists():
        try:
            meta = _meta(res)
        except (OSError, KeyError, ValueError):
            meta = {}
    solver = meta.get("solver", {})
    row.steps, row.rhs, row.rhs_jac = (int(solver.get("n_steps", 0)), int(solver.get("n_rhs", 0)),
                                       int(solver.get("n_rhs_jacobian", 0)))
    if "end_time" in meta:
        row.t_reached = float(meta["end_time"])
    if meas.get("timed_out") == "cpu":
        row.outcome, row.reason = "FAILURE", f"hang: still running at the CPU-time limit of {meas['cpu_limit']:g} s"
    elif meas.get("timed_out"):
        row.outcome, row.reason = "FAILURE", f"hang: still running at the wall-clock limit of {meas['limit']:g} s"
    elif code is None:   # an interrupted or unfinished matrix: nothing to judge
        row.outcome, row.reason = "not run", "no status.json in the run folder"
    elif code == 0:
        problems = []
        if meta.get("status") != "completed":
            problems.append(f"results status {meta.get('status')!r}")
        else:
            bad = _nonfinite(res)
            if bad:
                problems.append(bad)
        notes = [n.strip() for n in str(meta.get("notes") or "").splitlines() if n.strip()]
        lost = [n for n in notes if "without contact" in n]
        lost_text = "; ".join(lost[:2]) + (f" (and {len(lost) - 2} more wheels)" if len(lost) > 2 else "")
        if problems:
            row.outcome, row.reason = "FAILURE", "; ".join(problems)
        elif lost and not scene.contact_loss_expected:
            # A wheel off its rail in a scene without a lifting load is physical where the
            # wheelset tipped over its other wheel's contact: at every such sample that wheel's
            # Y/Q is at the closed-form tipping limit y_c / r (bench/extremes/tipping.py; a hunting
            # wheelset's flange hits past the critical speed). Any other lift (a wheel thrown
            # off by its own vertical dynamics, e.g. the chatter of a non-conservative strip force)
            # is not shown physical: "contact loss", not as expected.
            ratios = _lift_ratios(res)
            if all_tipped(ratios):
                row.outcome = "completed"
                row.reason = (f"wheels lifted by tipping over the flange contact in {ratios.size} wheel-samples, the "
                              f"other wheel at {ratios.min():.2f}-{ratios.max():.2f} of its tipping limit y_c / r; "
                              f"{lost_text}")
            else:
                out = ratios[(ratios < TIPPING_SHARE[0]) | (ratios > TIPPING_SHARE[1])]
                row.outcome = "contact loss"
                row.reason = (f"largest Y/Q {_max_yq(res):.2f}; {out.size} of {ratios.size} wheel-samples off the rail "
                              f"not at the tipping limit; {lost_text}")
        else:
            row.outcome, row.reason = "completed", lost_text
    elif code == 3 and "&simulation 'equilibrium'" in _last_message(run):
        # the static equilibrium solve before t = 0 hit the limit: the scene never ran, its
        # physics did not stop it (a lift-off found by the solve at rest is no outcome of the run)
        row.outcome = "FAILURE"
        row.reason = "static equilibrium (exit 3 before the run): " + _last_message(run).split("'equilibrium': ", 1)[-1]
    elif code == 3:
        msg = _last_message(run)
        documented = any(k in msg.lower() for k in DOCUMENTED_STOPS)
        row.outcome = "physics stop" if documented else "FAILURE"
        row.reason = summarise(msg, physics=True) if documented else f"exit 3 without a documented reason: {summarise(msg)}"
    else:
        kind = EXIT_OUTCOMES.get(code, f"exit {code}")
        row.outcome, row.reason = "FAILURE", f"{kind} (exit {code}): {summarise(_last_message(run))}"
    row.reason = strip_paths(row.reason)[:300]
    if row.outcome == "not run":
        row.expected = True
    elif scene.expect == "completed":
        row.expected = row.outcome == "completed"
    else:
        row.expected = row.outcome == "physics stop" and any(k in row.reason.lower() for k in scene.expect.split("|"))
    return row


# ------------------------------------------------------------------------------------------
# running


def slug(name: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")


def build_campaigns(work: Path, wrapper: Path, only: list | None, quick: bool):
    """One campaign per vehicle, scene and level (its one variant: the level's overrides), in
    <work>/runs/<vehicle>/<scene>/<level>/run0000, so that a run's folder does not depend on
    which other levels a selection (--only) runs; returns [(vehicle, scene, level, campaign or
    None, n/a row or None)]."""
    decks = write_scene_decks()
    out = []
    for v in vehicles():
        for s in scenes_for(v):
            for lv in v.levels:
                if only and not any(_match(o, v.key, s.key, lv.name) for o in only):
                    continue
                if s.key in lv.not_for:
                    out.append((v, s, lv, None, Row(v.key, s.key, lv.name, "n/a", lv.not_for[s.key])))
                    continue
                deck = decks[(v.key, s.key)]
                if quick:
                    # a shorter scene: the same deck with t_end overridden (development only)
                    qd = work / "quick" / deck.name
                    qd.parent.mkdir(parents=True, exist_ok=True)
                    qd.write_text(f"&include file = '{deck}' /\n&simulation t_end = 0.7 /\n")
                    deck = qd
                camp = C.Campaign(path=HERE / "run.py", name=f"extremes_{v.key}_{s.key}_{slug(lv.name)}", deck=deck,
                                  output=work / ("quick" if quick else "runs") / v.key / s.key / slug(lv.name),
                                  exe=wrapper, variants=[level_params(v, lv)])
                out.append((v, s, lv, camp, None))
    return out


def _match(pattern: str, vehicle: str, scene: str, level: str) -> bool:
    parts = (pattern.split(":") + ["", "", ""])[:3]
    return all(p in ("", "*") or p == x for p, x in zip(parts, (vehicle, scene, level)))


def run_matrix(build: Path, work: Path, jobs: int, backend: str, slurm_options: list, quick: bool,
               only: list | None, timeout: float, cpu_limit: int, progress=print, run: bool = True) -> list[Row]:
    """Run the matrix (run=False: classify the run folders of an earlier run only) and classify
    every run. `jobs` campaigns run at once (local: one process each; slurm: one job array
    each). Contact tables are cached in $RAILDYN_CACHE_DIR (default <work>/cache): the first
    table run of a vehicle with an empty cache includes the table's build (2.6-3.2 CPU s in the
    fidelity map), every later one reads it."""
    exe = (build / "bin" / "raildyn").resolve()
    if not exe.exists():
        raise SystemExit(f"bench/extremes: no runner {exe} (build first)")
    work.mkdir(parents=True, exist_ok=True)
    os.environ.setdefault("RAILDYN_CACHE_DIR", str(work / "cache"))
    wrapper = write_wrapper(work, exe, timeout, cpu_limit)
    plan = build_campaigns(work, wrapper, only, quick)

    def one(camp):
        if backend == "slurm":
            # the wrapper's limits hold on a node as well; --time backs them up
            camp.slurm_options = list(slurm_options) + [f"--time={max(1, int(timeout // 60) + 2)}"]
        try:
            C.run_campaign(camp, jobs=1, executor=backend, submit=True, progress=lambda *_: None)
        except C.CampaignError as exc:   # the summary's metrics: the matrix has none
            progress(f"bench/extremes: {camp.name}: {exc}")

    if run:
        with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            list(pool.map(one, [camp for *_, camp, na in plan if camp is not None]))
    rows: list[Row] = []
    for v, s, lv, camp, na in plan:
        if na is not None:
            rows.append(na)
            continue
        row = classify(C.run_dir(camp, 0), s)
        row.vehicle, row.level = v.key, lv.name
        rows.append(row)
        progress(f"{v.key:15s} {s.key:14s} {lv.name:28s} {row.outcome:13s} {row.cpu:7.1f} CPU s "
                 f"{row.steps:7d} steps  {row.reason[:90]}")
    return rows


# ------------------------------------------------------------------------------------------
# publishing


def fmt(x, spec):
    return "" if x is None or (isinstance(x, float) and not np.isfinite(x)) else format(x, spec)


#: marks a kept row's outcome in the published table
KEPT_MARK = " (earlier run)"


def published_rows(text: str) -> dict:
    """The rows of a published table (render's output, e.g. the extremes section of
    docs/performance.md): {(vehicle key, scene key, level): Row} with kept = True, for
    --keep-published. Rows not run or n/a are left out (they are nothing to keep)."""
    titles = {v.title: v for v in vehicles()}
    out, v, scenes = {}, None, {}
    for line in text.splitlines():
        if line.startswith("#### "):
            v = titles.get(line[5:].strip())
            scenes = {s.title: s for s in scenes_for(v)} if v else {}
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if v is None or len(cells) != 9 or cells[0] not in scenes:
            continue
        outcome = cells[2].replace(KEPT_MARK, "")
        if outcome in ("not run", "n/a"):
            continue
        rhs = [int(x) for x in cells[5].split("+")] if cells[5] else [0, 0]
        row = Row(v.key, scenes[cells[0]].key, cells[1], outcome=outcome, reason=cells[8],
                  steps=int(cells[4]) if cells[4] else 0, rhs=rhs[0], rhs_jac=rhs[1],
                  cpu=float(cells[6]) if cells[6] else float("nan"),
                  t_reached=float(cells[7]) if cells[7] else float("nan"), expected=cells[3] == "yes", kept=True)
        out[(row.vehicle, row.scene, row.level)] = row
    return out


def keep_published(rows: list, published: dict) -> list:
    """The whole matrix: every row of `rows` (this invocation's plan) that was classified from
    a run folder, and for every other row of the matrix (not selected by --only, or not run
    in the work folder) the published one when there is one."""
    have = {(r.vehicle, r.scene, r.level): r for r in rows if r.outcome != "not run"}
    full = []
    for v in vehicles():
        for s in scenes_for(v):
            for lv in v.levels:
                key = (v.key, s.key, lv.name)
                if key in have:
                    full.append(have[key])
                elif s.key in lv.not_for:
                    full.append(Row(v.key, s.key, lv.name, "n/a", lv.not_for[s.key]))
                elif key in published:
                    full.append(published[key])
                else:
                    full.append(Row(v.key, s.key, lv.name, "not run", "no status.json in the run folder"))
    return full


def render(rows: list[Row], meta: dict) -> str:
    vs = {v.key: v for v in vehicles()}
    out = ["### Stability at the extremes (bench/extremes/run.py)", "",
           meta["when"], "",
           "Each row is one run of a scene deck (`bench/extremes/scenes/`) with the level's overrides, "
           "run as a campaign (`raildyn.campaign`, local processes). outcome: completed = exit 0, every "
           "value finite, no wheel without contact unless the scene is about losing it or the wheelset "
           "tipped over its other wheel's contact (that wheel's Y/Q at 0.85-1.0 of the closed-form tipping "
           "limit y_c / r at every sample with a wheel off: bench/extremes/tipping.py; the reason column "
           "says so); physics stop = "
           "exit 3 with its documented reason, reached by the run; FAILURE = anything else (solver failure, "
           "other exit, an exit 3 of the static equilibrium solve before t = 0, non-finite value, "
           "still running at the wall-clock limit); n/a = the "
           "level does not apply. CPU s = user + system seconds of the runner process; RHS = method + "
           "difference-quotient Jacobian calls; t = simulated time reached [s]. 'as expected' compares "
           "the outcome with the scene's physics (flange climb: derailment or inner-wheel lift-off stop; lift-off: lift-off stop; "
           "every other scene: completed). contact loss = exit 0 with finite results, but some wheel had no "
           "contact in some output samples in a scene without a lift-off or climb load (the run's notes) "
           "and the tipping does not explain it (not shown physical); "
           "the largest Y/Q of the run goes with it."
           + (f" '{KEPT_MARK.strip()}' after an outcome: the row is kept from the table published before "
              "(--keep-published), not rerun; the text above says which rows ran where." if any(r.kept for r in rows) else ""),
           ""]
    for vkey, v in vs.items():
        vrows = [r for r in rows if r.vehicle == vkey]
        if not vrows:
            continue
        scenes = {s.key: s for s in scenes_for(v)}
        out += [f"#### {v.title}", "",
                "| scene | level | outcome | as expected | steps | RHS | CPU s | t [s] | reason |",
                "|---|---|---|---|---:|---:|---:|---:|---|"]
        for r in vrows:
            rhs = f"{r.rhs} + {r.rhs_jac}" if r.rhs else ""
            exp = "" if r.outcome in ("n/a", "not run") else ("yes" if r.expected else "**no**")
            reason = r.reason.replace("|", "/")
            outcome = r.outcome + (KEPT_MARK if r.kept else "")
            out.append(f"| {scenes[r.scene].title} | {r.level} | {outcome} | {exp} | {r.steps or ''} | {rhs} | "
                       f"{fmt(r.cpu, '.1f')} | {fmt(r.t_reached, '.3g')} | {reason} |")
        out.append("")
    ran = [r for r in rows if r.outcome not in ("n/a", "not run")]
    not_run = sum(r.outcome == "not run" for r in rows)
    counts = {k: sum(r.outcome == k for r in ran) for k in ("completed", "physics stop", "contact loss", "FAILURE")}
    cpu = sum(r.cpu for r in ran if np.isfinite(r.cpu))
    out += [f"Totals: {len(ran)} runs: {counts['completed']} completed, {counts['physics stop']} physics stops, "
            f"{counts['contact loss']} with contact loss, {counts['FAILURE']} FAILURES; {sum(not r.expected for r in ran)} not as expected; "
            f"{cpu:.0f} CPU s in all ({cpu / 60:.1f} CPU min)."
            + (f" {not_run} rows not run (the matrix was stopped before them)." if not_run else "")
            + (f" {sum(r.kept for r in ran)} of the runs are rows kept from the earlier table." if any(r.kept for r in ran) else ""),
            "", meta["source"]]
    return "\n".join(out) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", type=Path, default=Path(os.environ.get("RAILDYN_BUILD_DIR", REPO / "build")))
    ap.add_argument("--work", type=Path, help="run folders (default <build>/extremes)")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--backend", choices=("local", "slurm"), default="local")
    ap.add_argument("--slurm-option", action="append", default=[])
    ap.add_argument("--quick", action="store_true", help="0.7 s scenes, docs untouched")
    ap.add_argument("--only", nargs="+", help="VEHICLE:SCENE:LEVEL patterns ('' or * = any)")
    ap.add_argument("--timeout", type=float, default=3600.0, help="wall-clock limit of one run [s]")
    ap.add_argument("--cpu-limit", type=int, default=600, help="CPU-time limit of one run [s]")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--no-run", action="store_true", help="classify the run folders of an earlier run only")
    ap.add_argument("--when", help="the published run's description (with --no-run: when and how it ran)")
    ap.add_argument("--json", type=Path, help="rows as JSON (default <work>/extremes.json)")
    ap.add_argument("--keep-published", action="store_true",
                    help="rows this invocation does not classify (not selected by --only, not run in the work folder) "
                         "keep their row of the published table, marked; the whole table is written (with --only too)")
    args = ap.parse_args(argv)
    work = (args.work or args.build / "extremes").resolve()
    t0 = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    rows = run_matrix(args.build, work, args.jobs, args.backend, args.slurm_option, args.quick, args.only,
                      args.timeout, args.cpu_limit, run=not args.no_run)
    t1 = time.strftime("%H:%M UTC", time.gmtime())
    commit = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=REPO, capture_output=True,
                            text=True).stdout.strip()
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    meta = {"when": f"Run {t0} - {t1}, backend {args.backend}, {args.jobs} run(s) at a time, limits per run "
                    f"{args.cpu_limit} CPU s and {args.timeout:g} s wall; {os.cpu_count()} CPUs shared with other work (load average "
                    f"{load} at the end).",
            "source": f"Source: commit {commit}; host {platform.machine()}, {os.cpu_count()} CPUs."}
    if args.no_run:
        meta["when"] = args.when or f"Classified {t0} from the run folders of earlier runs (their times are not recorded here)."
    if args.keep_published:
        from performance_section import DOC
        doc = DOC.read_text()
        section = doc.split("<!-- BEGIN extremes -->", 1)[-1].split("<!-- END extremes -->", 1)[0]
        rows = keep_published(rows, published_rows(section))
    text = render(rows, meta)
    print(text)
    (args.json or work / "extremes.json").write_text(json.dumps([r.__dict__ for r in rows], indent=1))
    if not (args.no_write or args.quick or (args.only and not args.keep_published)):
        from performance_section import write_section
        write_section("extremes", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
