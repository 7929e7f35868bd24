"""Stability of a deck (docs/theory_stability.md): the modes `raildyn eigen` reports, read
back from its JSON and CSV answers; the growth rate of a disturbed motion (shared with the
validation harness); and `raildyn critical-speed` (the runner hands it to ``main``):

    raildyn critical-speed DECK --method linear|bisection|ramp [--speeds LO,HI] [--json] ...

linear: bracketing the zero crossing of the least-damped mode's damping ratio on the root
locus (`raildyn eigen`); bisection: the sign of the growth rate of disturbed runs at
constant speed (probes run in parallel, ``--jobs``); ramp: the speed at which the hunting
stops while the speed is lowered (one run through the C API).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from .executable import ExecutableNotFound, find_raildyn_executable
from .model import RaildynError
from .results import Results

__all__ = ["Mode", "mode_from_json", "read_root_locus", "StabilityError", "half_cycle_peaks", "growth_rate",
           "GROWTH_FLOOR", "CriticalSpeed", "eigen_locus", "least_damped", "linear_critical_speed",
           "bisection_critical_speed", "ramp_critical_speed", "main"]


@dataclass
class Mode:
    """One mode of the linearised scene (an eigenvalue real + i imag, imag >= 0)."""
    frequency_hz: float
    damping_ratio: float
    real: float
    imag: float
    neutral: bool = False
    #: (body or element name, coordinate, share of the mode's kinetic energy), largest first
    dominant: list[tuple[str, str, float]] = field(default_factory=list)


def mode_from_json(obj: dict) -> Mode:
    """A mode of the ``"modes"`` list of ``raildyn eigen --json``."""
    return Mode(float(obj["frequency_hz"]), float(obj["damping_ratio"]), float(obj["real"]),
                float(obj["imag"]), bool(obj.get("neutral", False)),
                [(d["body"], d["dof"], float(d["share"])) for d in obj["dominant"]])


def read_root_locus(path: str | os.PathLike) -> dict[float, list[Mode]]:
    """The CSV of ``raildyn eigen --speeds ... --csv FILE``: the modes at each speed [m/s], in
    the file's order (least damped first)."""
    locus: dict[float, list[Mode]] = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            dominant = []
            for part in filter(None, (p.strip() for p in row["dominant"].split(";"))):
                name, share = part.rsplit(" ", 1)
                owner, _, dof = name.rpartition(".")
                dominant.append((owner, dof, float(share)))
            locus.setdefault(float(row["speed"]), []).append(
                Mode(float(row["frequency_hz"]), float(row["damping_ratio"]), float(row["real"]),
                     float(row["imag"]), row["neutral"] == "1", dominant))
    return locus


# ------------------------------------------------------------------------------------------
# growth of a disturbed motion (shared with the validation harness)


class StabilityError(RuntimeError):
    """A stability search that cannot answer: the message says why."""


def half_cycle_peaks(t: np.ndarray, y: np.ndarray, floor: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Peaks of |y| in each half cycle: the largest |y| between consecutive sign changes of y
    (the first and last, incomplete half cycles are dropped). Peaks below ``floor`` are
    dropped (numerical noise once the motion has died out)."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    s = np.sign(y)
    nz = np.flatnonzero(s != 0)
    if nz.size < 2:
        return np.empty(0), np.empty(0)
    change = nz[1:][s[nz[1:]] != s[nz[:-1]]]        # first index of each new sign run
    tp, ap = [], []
    for a, b in zip(change[:-1], change[1:]):
        k = a + int(np.argmax(np.abs(y[a:b])))
        if abs(y[k]) > floor:
            tp.append(t[k])
            ap.append(abs(y[k]))
    return np.array(tp), np.array(ap)


#: Peaks below this [m] are not used for growth rates: 10 x the decks' absolute solver
#: tolerance (atol = 1e-8 in state units), below which the integrator's error dominates.
GROWTH_FLOOR = 1e-7


def growth_rate(t: np.ndarray, y: np.ndarray, floor: float = GROWTH_FLOOR) -> tuple[float, int]:
    """Exponential growth rate of the motion [1/s] (negative: decay). With at least 3 half-cycle
    peaks above ``floor``: slope of the least-squares line through ln(peak) against the peak
    times (the logarithmic decrement per half cycle over the half period). Otherwise (an
    over-damped, non-oscillating motion): slope of ln|y| against t over the samples above the
    floor. Returns (rate, number of peaks used; 0 for the second form). A motion that never
    rises above the floor in the window is an error (no disturbance, or it died out before)."""
    tp, ap = half_cycle_peaks(t, y, floor)
    if tp.size >= 3:
        slope = np.polyfit(tp, np.log(ap), 1)[0]
        return float(slope), int(tp.size)
    t = np.asarray(t, float)
    a = np.abs(np.asarray(y, float))
    m = a > floor
    if m.sum() < 5:
        raise StabilityError(f"the motion stays below {floor:g} in the window: nothing to measure a "
                             "growth rate on (no disturbance, or it died out before the window)")
    return float(np.polyfit(t[m], np.log(a[m]), 1)[0]), 0


# ------------------------------------------------------------------------------------------
# critical speed: linear (root locus), bisection (disturbed runs), ramp (hunting dies out)


@dataclass
class CriticalSpeed:
    """The answer of one method: ``critical_speed`` [m/s] (None when the bracket holds no
    change: then ``note`` says which way), ``resolution`` [m/s] (the critical speed lies
    within +- resolution of the value), the final ``bracket`` and the probes."""
    method: str
    critical_speed: float | None
    resolution: float | None
    bracket: tuple[float, float]
    mode: dict | None = None
    probes: list[dict] = field(default_factory=list)
    note: str = ""

    def as_json(self) -> dict:
        return {"method": self.method, "critical_speed": self.critical_speed, "resolution": self.resolution,
                "bracket": list(self.bracket), "mode": self.mode, "probes": self.probes, "note": self.note}


def _runner(exe) -> Path:
    return find_raildyn_executable(exe)


def eigen_locus(deck: str | os.PathLike, speeds: Sequence[float], exe=None,
                dofs: str | None = None) -> list[tuple[float, list[dict]]]:
    """``raildyn eigen DECK --speeds ... --json``: (speed, modes) per speed."""
    args = [os.fspath(_runner(exe)), "eigen", os.fspath(deck), "--json",
            "--speeds", ",".join(f"{v:.17g}" for v in speeds)]
    if dofs:
        args += ["--dofs", dofs]
    proc = subprocess.run(args, capture_output=True, text=True)
    if proc.returncode != 0:
        raise StabilityError(f"raildyn eigen {deck}: {proc.stderr.strip().splitlines()[-1] if proc.stderr else proc.returncode}")
    out = json.loads(proc.stdout)
    points = out["root_locus"] if "root_locus" in out else [{"speed": out["speed"], "modes": out["modes"]}]
    return [(float(p["speed"]), p["modes"]) for p in points]


def least_damped(modes: Sequence[dict]) -> dict:
    """The least-damped mode that is not neutral (neutral modes never cross zero damping)."""
    live = [m for m in modes if not m.get("neutral", False)]
    if not live:
        raise StabilityError("every mode is neutral: nothing can become unstable")
    return min(live, key=lambda m: m["damping_ratio"])


def linear_critical_speed(deck, lo: float, hi: float, resolution: float, exe=None, dofs: str | None = None,
                          grid: int = 25) -> CriticalSpeed:
    """The lowest speed in [lo, hi] at which the least-damped mode's damping ratio crosses
    zero: a grid of ``grid`` speeds (one eigen call), then bisection of the first bracket
    until it is at most 2 x ``resolution`` wide. ``mode``: that mode at the bracket's top."""
    probes = []

    def zeta(locus):
        out = []
        for v, modes in locus:
            m = least_damped(modes)
            probes.append({"speed": v, "damping_ratio": m["damping_ratio"], "frequency_hz": m["frequency_hz"]})
            out.append((v, m))
        return out

    points = zeta(eigen_locus(deck, np.linspace(lo, hi, grid), exe, dofs))
    if points[0][1]["damping_ratio"] < 0:
        return CriticalSpeed("linear", None, None, (lo, lo), _mode_json(points[0][1]), probes,
                             f"unstable already at {lo:g} m/s: lower the bracket")
    first = next((i for i, (_, m) in enumerate(points) if m["damping_ratio"] < 0), None)
    if first is None:
        return CriticalSpeed("linear", None, None, (hi, hi), _mode_json(points[-1][1]), probes,
                             f"stable up to {hi:g} m/s: raise the bracket")
    (a, _), (b, top) = points[first - 1], points[first]
    while b - a > 2 * resolution:
        ((mid, m),) = zeta(eigen_locus(deck, [0.5 * (a + b)], exe, dofs))
        if m["damping_ratio"] < 0:
            b, top = mid, m
        else:
            a = mid
    return CriticalSpeed("linear", 0.5 * (a + b), 0.5 * (b - a), (a, b), _mode_json(top), probes)


def _mode_json(mode: dict) -> dict:
    return {k: mode[k] for k in ("frequency_hz", "damping_ratio", "real", "imag", "dominant")}


def hunting_channel(deck, speed: float, exe=None) -> str:
    """Default channel for the nonlinear methods: the lateral coordinate of the body with the
    largest lateral share of the least-damped linear mode at ``speed``."""
    ((_, modes),) = eigen_locus(deck, [speed], exe)
    lateral = [d for d in least_damped(modes)["dominant"] if d["dof"] == "y"]
    if not lateral:
        raise StabilityError(f"the least-damped mode at {speed:g} m/s has no lateral coordinate among its "
                             "dominant ones; give --channel")
    return f"bodies/{lateral[0]['body']}/position_track:y"


def _probe_run(deck: Path, speed: float, t_end: float, work: Path, exe) -> Path:
    """A run of ``deck`` at constant ``speed`` to ``t_end`` (an including deck with the
    overrides, docs/input_reference.md "Includes and overrides")."""
    tag = f"v{speed:.6f}".replace(".", "_")
    probe = work / f"{tag}.nml"
    probe.write_text(f"! raildyn critical-speed probe\n&include file = '{deck.resolve()}' /\n"
                     f"&simulation speed = {speed:.17g}, t_end = {t_end:.17g} /\n")
    results = work / f"{tag}.h5"
    proc = subprocess.run([os.fspath(_runner(exe)), "run", os.fspath(probe), "-o", os.fspath(results), "--quiet"],
                          capture_output=True, text=True)
    if proc.returncode not in (0, 3):      # 3: a physics limit (lift-off): the rows written still count
        raise StabilityError(f"probe at {speed:g} m/s: raildyn run exited with {proc.returncode}: "
                             f"{proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ''}")
    return results


def probe_growth(deck, speed: float, channel: str, t_from: float, t_end: float, work: Path, exe=None) -> dict:
    """Growth rate [1/s] of ``channel`` over [t_from, t_end] in a run at ``speed``."""
    path = _probe_run(Path(deck), speed, t_end, work, exe)
    with Results(path) as r:
        t, y = r.time, r.get(channel)
    m = (t >= t_from - 1e-12) & (t <= t_end + 1e-12)
    try:
        rate, peaks = growth_rate(t[m], y[m])
    except StabilityError as exc:
        raise StabilityError(f"probe at {speed:g} m/s, {channel}: {exc}") from None
    return {"speed": speed, "growth_rate": rate, "peaks": peaks,
            "frequency_hz": oscillation_frequency(*half_cycle_peaks(t[m], y[m], GROWTH_FLOOR)[:1])}


def oscillation_frequency(peak_times: np.ndarray) -> float | None:
    """Frequency [Hz] from half-cycle peak times (two per period); None below 3 peaks."""
    if len(peak_times) < 3:
        return None
    return float(1.0 / (2.0 * np.median(np.diff(peak_times))))


def mode_near(deck, speed: float, frequency_hz: float | None, exe=None) -> dict:
    """The linear mode at ``speed`` whose frequency is nearest the measured oscillation (the
    least-damped one when none was measured): the mode shape at a nonlinear crossing."""
    ((_, modes),) = eigen_locus(deck, [speed], exe)
    live = [m for m in modes if not m.get("neutral", False)]
    if frequency_hz is None:
        return _mode_json(least_damped(modes))
    mode = _mode_json(min(live, key=lambda m: abs(m["frequency_hz"] - frequency_hz)))
    mode["measured_frequency_hz"] = frequency_hz
    return mode


def bisection_critical_speed(deck, lo: float, hi: float, resolution: float, channel: str, t_from: float,
                             t_end: float, work: Path, exe=None, jobs: int = 1,
                             probe: Callable[[float], dict] | None = None) -> CriticalSpeed:
    """The speed where the growth rate of a disturbed run changes sign (the deck disturbs the
    vehicle itself, e.g. a lateral force pulse): probes at lo and hi, then the bracket cut
    into jobs + 1 parts by ``jobs`` probes run in parallel, until it is at most 2 x
    ``resolution`` wide. ``probe(speed)`` -> {"speed", "growth_rate", "peaks", ...} replaces
    ``probe_growth`` (the validation harness runs its probes as its own cases' variants)."""
    probes: list[dict] = []
    probe = probe or (lambda v: probe_growth(deck, v, channel, t_from, t_end, work, exe))

    def rates(speeds):
        with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            got = list(pool.map(probe, speeds))
        probes.extend(got)
        return [p["growth_rate"] for p in got]

    r_lo, r_hi = rates([lo, hi])
    if r_lo > 0:
        return CriticalSpeed("bisection", None, None, (lo, lo), None, probes,
                             f"the motion grows already at {lo:g} m/s: lower the bracket")
    if r_hi <= 0:
        return CriticalSpeed("bisection", None, None, (hi, hi), None, probes,
                             f"the motion decays up to {hi:g} m/s: raise the bracket")
    a, b = lo, hi
    while b - a > 2 * resolution:
        inner = list(np.linspace(a, b, max(1, jobs) + 2)[1:-1])
        growing = [v for v, rate in zip(inner, rates(inner)) if rate > 0]
        below = [v for v in inner if v < (growing[0] if growing else b)]
        a, b = (below[-1] if below else a), (growing[0] if growing else b)
    return CriticalSpeed("bisection", 0.5 * (a + b), 0.5 * (b - a), (a, b), None, probes)


def ramp_critical_speed(deck, v_start: float, v_end: float, hold: float, duration: float, channel: str,
                        work: Path, exe=None, step: float = 0.01, threshold: float = 0.5) -> CriticalSpeed:
    """Speed ramp-down from hunting: hold ``v_start`` for ``hold`` seconds (the deck's own
    disturbance starts the hunting), then lower the speed linearly to ``v_end`` over
    ``duration`` seconds (through the C API, set_input "speed" every ``step`` seconds). The
    critical speed is the speed at the last half-cycle peak of ``channel`` above ``threshold``
    x the hunting amplitude at the end of the hold; resolution: the speed lost over one
    hunting period there (peaks are that far apart). Once below the critical speed the
    hunting takes time to die out, so a ramp reads low by its lag, the more the faster it
    is: compare two durations (docs/theory_stability.md section 5)."""
    from .model import Model
    deck = Path(deck)
    ramp_deck = work / "ramp.nml"
    results = (work / "ramp.h5").resolve()
    ramp_deck.write_text(f"! raildyn critical-speed ramp\n&include file = '{deck.resolve()}' /\n"
                         f"&simulation speed = {v_start:.17g}, t_end = {hold + duration:.17g} /\n"
                         f"&output file = '{results}' /\n")
    with Model.from_file(ramp_deck) as model:
        model.initialize(write_output=True)
        model.advance(hold)
        t = hold
        while t < hold + duration - 1e-12:
            t = min(t + step, hold + duration)
            model.set_input("speed", v_start + (v_end - v_start) * (t - hold) / duration)
            model.advance(t)
        model.finalize()
    with Results(results) as r:
        time, y, v = r.time, r.get(channel), r.get("vehicle/speed")[:, 0]
    tp, ap = half_cycle_peaks(time, y, GROWTH_FLOOR)
    held = ap[tp <= hold]
    if held.size < 2:
        raise StabilityError(f"no hunting at {v_start:g} m/s by the end of the hold ({hold:g} s): "
                             "start the ramp higher or hold longer")
    amplitude = float(held[-1])
    after = (tp > hold)
    alive = tp[after][ap[after] > threshold * amplitude]
    speed_at = lambda tt: float(np.interp(tt, time, v))
    probes = [{"time": float(a), "speed": speed_at(a), "peak": float(b)} for a, b in zip(tp, ap)]
    if alive.size == 0:
        return CriticalSpeed("ramp", None, None, (v_start, v_start), None, probes,
                             f"the hunting died during the first ramp period: start the ramp higher")
    t_last = float(alive[-1])
    if t_last >= tp[-1] and ap[-1] > threshold * amplitude:
        return CriticalSpeed("ramp", None, None, (v_end, v_end), None, probes,
                             f"still hunting at {v_end:g} m/s: ramp further down")
    near = np.abs(tp - t_last) <= 2.0 * float(np.median(np.diff(tp)))   # the last periods of hunting
    period = 2 * float(np.median(np.diff(tp[near]))) if near.sum() > 2 else 2 * float(np.median(np.diff(tp)))
    vc = speed_at(t_last)
    res = abs(v_start - v_end) / duration * period
    return CriticalSpeed("ramp", vc, res, (vc - res, vc + res), mode_near(deck, vc, 1.0 / period, exe), probes,
                         f"hunting amplitude {amplitude:.3g} at {v_start:g} m/s; last peak above "
                         f"{threshold:g} of it at t = {t_last:.3f} s")


class _Parser(argparse.ArgumentParser):
    """Usage errors exit 1 with the usage line, as the runner's commands do (argparse: 2)."""

    def error(self, message: str):
        self.print_usage(sys.stderr)
        print(f"raildyn: {message}", file=sys.stderr)
        raise SystemExit(1)


def main(argv: list[str] | None = None) -> int:
    """``raildyn critical-speed DECK --method linear|bisection|ramp [options] [--json]``."""
    parser = _Parser(
        prog="raildyn critical-speed",
        description="Critical speed of a deck (docs/theory_stability.md): linear (root locus), "
                    "bisection (growth of disturbed runs) or ramp (speed ramp-down from hunting).")
    parser.add_argument("deck")
    parser.add_argument("--method", choices=["linear", "bisection", "ramp"], required=True)
    parser.add_argument("--speeds", default="10,100", help="bracket LO,HI [m/s] (ramp: from HI down to LO)")
    parser.add_argument("--resolution", type=float, default=0.5, help="half-width of the final bracket [m/s]")
    parser.add_argument("--dofs", help="linear: coordinates kept (raildyn eigen --dofs)")
    parser.add_argument("--channel", help="bisection, ramp: the series 'path:component' whose growth "
                                          "decides (default: lateral y of the body dominating the "
                                          "least-damped linear mode at HI)")
    parser.add_argument("--t-end", type=float, default=8.0, help="bisection: length of each probe run [s]")
    parser.add_argument("--t-from", type=float, default=0.5, help="bisection: growth measured from [s]")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="bisection: probes run at once")
    parser.add_argument("--hold", type=float, default=4.0, help="ramp: time at HI before the ramp [s]")
    parser.add_argument("--duration", type=float, default=20.0, help="ramp: ramp time from HI to LO [s]")
    parser.add_argument("--work", help="folder for probe decks and results (default: a temporary one)")
    parser.add_argument("--exe", help="the raildyn runner (default: raildyn.executable lookup)")
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")
    args = parser.parse_args(argv)
    try:
        lo, hi = (float(v) for v in args.speeds.split(","))
    except ValueError:
        parser.error(f"--speeds expects LO,HI in m/s, got {args.speeds!r}")
    if not 0 <= lo < hi:
        parser.error(f"--speeds expects 0 <= LO < HI, got {args.speeds!r}")
    if not args.resolution > 0:
        parser.error("--resolution expects a speed > 0 in m/s")
    if not Path(args.deck).is_file():
        print(f"raildyn: error: {args.deck}: no such deck file", file=sys.stderr)
        return 1
    try:
        with tempfile.TemporaryDirectory(prefix="raildyn_critical_speed_") as scratch:
            work = Path(args.work) if args.work else Path(scratch)
            work.mkdir(parents=True, exist_ok=True)
            if args.method == "linear":
                answer = linear_critical_speed(args.deck, lo, hi, args.resolution, args.exe, args.dofs)
            else:
                channel = args.channel or hunting_channel(args.deck, hi, args.exe)
                if args.method == "bisection":
                    answer = bisection_critical_speed(args.deck, lo, hi, args.resolution, channel, args.t_from,
                                                      args.t_end, work, args.exe, args.jobs)
                    if answer.critical_speed is not None:
                        # the mode shape at the crossing: the linear mode of the growing motion's frequency
                        above = min((p for p in answer.probes if p["speed"] >= answer.bracket[1]),
                                    key=lambda p: p["speed"])
                        answer.mode = mode_near(args.deck, answer.critical_speed, above["frequency_hz"], args.exe)
                else:
                    answer = ramp_critical_speed(args.deck, hi, lo, args.hold, args.duration, channel, work,
                                                 args.exe)
                answer.note = (answer.note + "; " if answer.note else "") + f"channel {channel}"
    except RaildynError as exc:           # the ramp's run through the C API
        print(f"raildyn: error: {exc.message}", file=sys.stderr)
        return exc.status
    except (StabilityError, ExecutableNotFound, OSError) as exc:
        print(f"raildyn: error: {exc}", file=sys.stderr)
        return 2 if isinstance(exc, StabilityError) else 4
    if args.json:
        print(json.dumps(answer.as_json()))
    elif answer.critical_speed is None:
        print(f"raildyn: {args.method} critical speed of {args.deck}: not found ({answer.note})")
    else:
        shape = ", ".join(f"{d['body']}.{d['dof']} {d['share']:.2f}" for d in (answer.mode or {}).get("dominant", []))
        print(f"raildyn: {args.method} critical speed of {args.deck}: {answer.critical_speed:.3f} m/s "
              f"+- {answer.resolution:.3f} m/s" + (f"; mode {answer.mode['frequency_hz']:.3f} Hz ({shape})"
                                                    if answer.mode else "") + (f"; {answer.note}" if answer.note else ""))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
