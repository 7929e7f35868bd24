"""Stability of a deck (docs/theory_stability.md): the modes `raildyn eigen` reports, read
back from its JSON and CSV answers; the growth rate of a disturbed motion (shared with the
validation harness); and `raildyn critical-speed` (the runner hands it to ``main``):

    raildyn critical-speed DECK --method linear|bisection|ramp [--speeds LO,HI] [--json] ...

linear: bracketing the zero crossing of the least-damped mode's damping ratio on the root
locus (`raildyn eigen`); bisection: the sign of the growth rate of disturbed runs at
constant speed; ramp: the speed at which the hunting stops while the speed is lowered, at
two or more ramp rates extrapolated to a zero rate. The probe runs of both nonlinear methods
are campaigns of raildyn.campaign (``run_probes``): ``--jobs`` at once in a local process
pool, or a Slurm job array per round (``--backend slurm``).
"""

from __future__ import annotations

import csv
import json
import math
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from .executable import RESULTS_READABLE, CommandParser, ExecutableNotFound, find_raildyn_executable
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
# growth of a disturbed motion (shared with the validation harness and the campaigns)


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


def eigen_locus(deck: str | os.PathLike, speeds: Sequence[float], exe=None,
                dofs: str | None = None) -> list[tuple[float, list[dict]]]:
    """``raildyn eigen DECK --speeds ... --json``: (speed, modes) per speed."""
    args = [os.fspath(find_raildyn_executable(exe)), "eigen", os.fspath(deck), "--json",
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


#: Where the probe runs of the nonlinear methods run (raildyn.campaign's executors).
BACKENDS = ("local", "slurm")


def run_probes(deck, variants: Sequence[dict], work: Path, exe=None, backend: str = "local", jobs: int = 1,
               slurm_options: Sequence[str] = (), tag: str = "probes") -> list[Path]:
    """Runs of ``deck`` with the ``&simulation`` overrides of each variant ({"simulation.speed":
    40.0, ...}), as one campaign of raildyn.campaign: an including deck per run (docs/
    input_reference.md "Includes and overrides") under ``work/tag/runNNNN``, run by a local
    pool of ``jobs`` processes or as one Slurm job array (sbatch --wait; ``slurm_options`` are
    its #SBATCH lines). Returns each variant's results file, in order. A run that failed
    (other than a physics limit, exit 3, whose rows written still count) or that Slurm did
    not run is a StabilityError naming it."""
    from . import campaign as cp
    if backend not in BACKENDS:
        raise StabilityError(f"backend must be one of {BACKENDS}, got {backend!r}")
    deck = Path(deck).resolve()
    messages: list[str] = []
    try:
        exe_path = find_raildyn_executable(exe).resolve()
        camp = cp.Campaign(path=deck, name=f"raildyn_critical_speed_{tag}", deck=deck,
                           output=(Path(work) / tag).resolve(), executor=backend, jobs=max(1, jobs),
                           slurm_options=list(slurm_options), exe=exe_path, variants=list(variants))
        cp.run_campaign(camp, jobs=max(1, jobs), executor=backend, submit=True, progress=messages.append)
    except cp.CampaignError as exc:
        raise StabilityError(f"probe runs: {exc}") from None
    paths = []
    for i, params in enumerate(camp.runs()):
        run = cp.run_dir(camp, i)
        status = cp._read_status(run)
        what = ", ".join(f"{k.split('.', 1)[1]} = {v}" for k, v in params.items())
        if "exit_code" not in status:
            raise StabilityError(f"probe run {run} ({what}) has no status: it did not run"
                                 + (f" ({'; '.join(m for m in messages if m)})" if any(messages) else ""))
        if status["exit_code"] not in RESULTS_READABLE:
            raise StabilityError(f"probe run {run} ({what}): raildyn run exited with {status['exit_code']}: "
                                 f"{status.get('error', '')}")
        paths.append(run / "results.h5")
    return paths


def _series(path: Path, channel: str) -> tuple[np.ndarray, np.ndarray]:
    """Time and the first component of ``channel`` in the results ``path``."""
    with Results(path) as r:
        try:
            y = r.get(channel)
        except KeyError:
            raise StabilityError(f"{path}: no series {channel!r} (give --channel)") from None
        return r.time, (y[:, 0] if y.ndim > 1 else y)


def growth_of(path: Path, speed: float, channel: str, t_from: float, t_end: float) -> dict:
    """Growth rate [1/s] of ``channel`` over [t_from, t_end] in the results ``path`` of a run
    at ``speed``, its half-cycle peaks and frequency."""
    t, y = _series(path, channel)
    m = (t >= t_from - 1e-12) & (t <= t_end + 1e-12)
    try:
        rate, peaks = growth_rate(t[m], y[m])
    except StabilityError as exc:
        raise StabilityError(f"probe at {speed:g} m/s, {channel}: {exc}") from None
    return {"speed": speed, "growth_rate": rate, "peaks": peaks,
            "frequency_hz": oscillation_frequency(*half_cycle_peaks(t[m], y[m], GROWTH_FLOOR)[:1])}


def peaks_after_speed_change(deck, speed: float, hold_speed: float, hold: float, after: float,
                             channel: str = "bodies/ws/position_track", component: int = 1,
                             sample: float = 0.005) -> tuple[np.ndarray, np.ndarray]:
    """Half-cycle peaks (times from the change, amplitudes) of one output over ``after``
    seconds at ``speed``, starting from the motion reached after ``hold`` seconds at
    ``hold_speed`` (e.g. a hunting cycle): where a hunting cycle lives or dies at constant
    speed, the reference of the ramp method (docs/theory_stability.md 5a). Steps the deck
    through the C API (input "speed"), sampling every ``sample`` seconds."""
    from .model import Model
    with Model.from_file(deck) as model:
        model.initialize(write_output=False)
        model.set_input("speed", hold_speed)
        model.advance(hold)
        model.set_input("speed", speed)
        t = np.arange(1, int(round(after / sample)) + 1) * sample
        y = []
        for tk in t:
            model.advance(hold + tk)
            y.append(model.output(channel)[component])
    return half_cycle_peaks(t, np.array(y), GROWTH_FLOOR)


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
                             probe: Callable[[float], dict] | None = None, backend: str = "local",
                             slurm_options: Sequence[str] = ()) -> CriticalSpeed:
    """The speed where the growth rate of a disturbed run changes sign (the deck disturbs the
    vehicle itself, e.g. a lateral force pulse): probes at lo and hi, then the bracket cut
    into jobs + 1 parts by ``jobs`` probes run at once, until it is at most 2 x
    ``resolution`` wide. Each round of probes is one campaign (run_probes: a local pool of
    ``jobs`` processes, or a Slurm job array with ``backend = "slurm"``). ``probe(speed)`` ->
    {"speed", "growth_rate", "peaks", ...} replaces those runs (the validation harness runs
    its probes as its own cases' variants; ``jobs`` of them at once in threads)."""
    probes: list[dict] = []
    rounds = [0]

    def rates(speeds):
        if probe is not None:
            with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
                got = list(pool.map(probe, speeds))
        else:
            rounds[0] += 1
            paths = run_probes(deck, [{"simulation.speed": float(v), "simulation.t_end": float(t_end)}
                                      for v in speeds], work, exe, backend, jobs, slurm_options,
                               tag=f"bisection{rounds[0]:02d}")
            got = [growth_of(path, v, channel, t_from, t_end) for path, v in zip(paths, speeds)]
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


def ramp_reading(time: np.ndarray, y: np.ndarray, speed: np.ndarray, hold: float,
                 threshold: float = 0.5) -> dict:
    """What one ramp-down run reads: the speed at the last half-cycle peak of ``y`` after the
    hold that is above ``threshold`` x the hunting amplitude at the end of the hold (the
    last held peak), and the hunting period there. Raises StabilityError when there was no
    hunting at the end of the hold; ``speed`` is None (with ``note``) when the hunting died
    in the first ramp period or did not die by the end of the ramp."""
    tp, ap = half_cycle_peaks(time, y, GROWTH_FLOOR)
    held = ap[tp <= hold]
    if held.size < 2:
        raise StabilityError(f"no hunting by the end of the hold ({hold:g} s): start the ramp higher or "
                             "hold longer")
    amplitude = float(held[-1])
    speed_at = lambda tt: float(np.interp(tt, time, speed))
    peaks = [{"time": float(a), "speed": speed_at(a), "peak": float(b)} for a, b in zip(tp, ap)]
    out = {"amplitude": amplitude, "peaks": peaks, "speed": None, "period": None, "note": ""}
    after = tp > hold
    alive = tp[after][ap[after] > threshold * amplitude]
    if alive.size == 0:
        out["note"] = "the hunting died during the first ramp period: start the ramp higher"
        return out
    t_last = float(alive[-1])
    if t_last >= tp[-1] and ap[-1] > threshold * amplitude:
        out["note"] = f"still hunting at {speed_at(time[-1]):g} m/s: ramp further down"
        return out
    near = np.abs(tp - t_last) <= 2.0 * float(np.median(np.diff(tp)))   # the last periods of hunting
    out["period"] = 2 * float(np.median(np.diff(tp[near]))) if near.sum() > 2 else 2 * float(np.median(np.diff(tp)))
    out["speed"] = speed_at(t_last)
    out["time"] = t_last
    return out


#: Smallest exponent p of the ramp's lag ~ rate^p the ramp's extrapolation allows for
#: (ramp_critical_speed): below the 0.39-0.56 measured on the tests' knife-edge wheelset and
#: theory's 1/2 and 2/3 (docs/theory_stability.md section 5a).
RAMP_LAG_P_MIN = 1.0 / 3.0


def ramp_critical_speed(deck, v_start: float, v_end: float, hold: float, durations: Sequence[float],
                        channel: str, work: Path, exe=None, threshold: float = 0.5, backend: str = "local",
                        jobs: int = 1, slurm_options: Sequence[str] = ()) -> CriticalSpeed:
    """Speed ramp-down from hunting at several ramp rates, extrapolated to a zero rate
    (docs/theory_stability.md section 5a). Each ramp is a run of the deck with the speed law
    (``&simulation speed_times, speed_values``) ``v_start`` for ``hold`` seconds (the deck's
    own disturbance starts the hunting), then linearly down to ``v_end`` over one of
    ``durations`` [s]; the ramps run at once as one campaign (run_probes: local pool or Slurm
    job array). Each reads the speed at which its hunting has died (ramp_reading), low by a
    lag that grows with the rate a as a^p: p = 1 for a decay at a fixed rate, 1/2 when the
    decay rate grows linearly below the critical speed, 2/3 for the slow passage through
    the fold of a subcritical limit cycle; measured 0.39-0.56 on the knife-edge wheelset of
    the tests (section 5a). From the two slowest ramps (rates a1 < a2, readings v1, v2) the
    zero-rate speed is taken between the extrapolations v1 + (v1 - v2) / ((a2/a1)^p - 1) with
    p = 1 and p = P_MIN = 1/3: the answer is their midpoint, the resolution half their spread
    (at least the speed lost over one hunting period). With one duration: that ramp's
    reading, low by its unknown lag (the note says so)."""
    durations = sorted(float(d) for d in durations)
    if not durations or durations[0] <= 0:
        raise StabilityError("ramp durations must be > 0 s")
    variants = [{"simulation.speed_times": [0.0, float(hold), float(hold + d)],
                 "simulation.speed_values": [float(v_start), float(v_start), float(v_end)],
                 "simulation.t_end": float(hold + d)} for d in durations]
    paths = run_probes(deck, variants, work, exe, backend, jobs, slurm_options, tag="ramps")
    probes, readings = [], []
    for d, path in zip(durations, paths):
        time, y = _series(path, channel)
        _, v = _series(path, "vehicle/speed")
        try:
            got = ramp_reading(time, y, v, hold, threshold)
        except StabilityError as exc:
            raise StabilityError(f"ramp from {v_start:g} m/s: {exc}") from None
        rate = abs(v_start - v_end) / d
        probes.append({"duration": d, "rate": rate, "critical_speed": got["speed"],
                       "amplitude": got["amplitude"], "peaks": got["peaks"]})
        if got["speed"] is None:
            return CriticalSpeed("ramp", None, None, (v_end, v_start), None, probes,
                                 f"ramp over {d:g} s: {got['note']}")
        readings.append((rate, got))
    a1, slow = readings[-1]                     # the slowest ramp (durations ascending)
    v1 = slow["speed"]
    period_speed = a1 * slow["period"]          # the speed lost over one hunting period
    if len(readings) == 1:
        vc, res = v1, period_speed
        note = "one ramp: it reads low by its lag (give two durations to extrapolate)"
    else:
        a2, fast = readings[-2]
        v2 = fast["speed"]
        if v1 > v2:
            lo_p1 = v1 + (v1 - v2) / (a2 / a1 - 1)
            hi_pmin = v1 + (v1 - v2) / ((a2 / a1) ** RAMP_LAG_P_MIN - 1)
            vc, res = 0.5 * (lo_p1 + hi_pmin), max(0.5 * (hi_pmin - lo_p1), period_speed)
            note = (f"ramps at {a1:.3g} and {a2:.3g} m/s/s read {v1:.3f} and {v2:.3f} m/s; zero-rate "
                    f"extrapolation {lo_p1:.3f} (lag ~ rate) to {hi_pmin:.3f} m/s (lag ~ rate^(1/3))")
        else:
            vc, res = v1, max(v2 - v1, period_speed)
            note = (f"the slower ramp ({a1:.3g} m/s/s) read {v1:.3f} m/s, not above the faster one's "
                    f"{v2:.3f} m/s: no lag to extrapolate")
    return CriticalSpeed("ramp", vc, res, (vc - res, vc + res), mode_near(deck, vc, 1.0 / slow["period"], exe),
                         probes, f"hunting amplitude {slow['amplitude']:.3g} at {v_start:g} m/s; {note}")


def main(argv: list[str] | None = None) -> int:
    """``raildyn critical-speed DECK --method linear|bisection|ramp [options] [--json]``."""
    parser = CommandParser(
        prog="raildyn critical-speed",
        description="Critical speed of a deck (docs/theory_stability.md): linear (root locus), "
                    "bisection (growth of disturbed runs) or ramp (speed ramp-down from hunting).")
    parser.error_prefix = "raildyn"
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
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="bisection, ramp: probe runs at once (local backend; Slurm: the array's size)")
    parser.add_argument("--backend", choices=list(BACKENDS), default="local",
                        help="bisection, ramp: where the probe runs run (raildyn campaign's executors: a "
                             "local process pool, or a Slurm job array per round, sbatch --wait)")
    parser.add_argument("--slurm-option", action="append", default=[], metavar="OPT",
                        help="an #SBATCH line of the probes' job arrays (repeatable), e.g. --time=00:30:00")
    parser.add_argument("--hold", type=float, default=4.0, help="ramp: time at HI before the ramp [s]")
    parser.add_argument("--duration", default="20,40",
                        help="ramp: ramp times from HI to LO [s], comma-separated (each a ramp; the slowest "
                             "is the answer, the next one its convergence check)")
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
    if args.jobs < 1:
        parser.error(f"--jobs expects a number of runs >= 1, got {args.jobs}")
    try:
        durations = [float(v) for v in args.duration.split(",")]
    except ValueError:
        parser.error(f"--duration expects ramp times in s, comma-separated, got {args.duration!r}")
    if not all(d > 0 for d in durations):
        parser.error(f"--duration expects ramp times > 0 s, got {args.duration!r}")
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
                                                      args.t_end, work, args.exe, args.jobs, backend=args.backend,
                                                      slurm_options=args.slurm_option)
                    if answer.critical_speed is not None:
                        # the mode shape at the crossing: the linear mode of the growing motion's frequency
                        above = min((p for p in answer.probes if p["speed"] >= answer.bracket[1]),
                                    key=lambda p: p["speed"])
                        answer.mode = mode_near(args.deck, answer.critical_speed, above["frequency_hz"], args.exe)
                else:
                    answer = ramp_critical_speed(args.deck, hi, lo, args.hold, durations, channel, work,
                                                 args.exe, backend=args.backend, jobs=args.jobs,
                                                 slurm_options=args.slurm_option)
                answer.note = (answer.note + "; " if answer.note else "") + f"channel {channel}"
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
