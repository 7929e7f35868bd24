"""Validation harness: runs the validation scenes, compares them with published and expected
behaviour, writes a self-contained HTML report.

    python -m raildyn.validation [run] [--cases NAME ...] [--reuse] [--out DIR] [--exe PATH]
                                 [--results CASE=FILE ...]
    python -m raildyn.validation list
    python -m raildyn.validation freeze CASE [--channels CH ...] [--rel 0.02] [--abs 1e-6]

Cases (``CASES``): a deck in ``inputs/``, what to extract from its results, the comparison
and its acceptance rule. Reference data and thresholds live in ``validation/`` (CSV files
with their provenance in header comments):

- ``validation/manchester_v1_tc1/packages.csv``: thesis tables 5.9-5.11 as printed,
  ``corrections.csv``: documented digit slips. Acceptance: ``manchester_acceptance``.
- ``validation/tgv_checks.csv``: the TGV 001 expectations with thresholds and justification;
  the ``kind`` column names the check function in ``CHECK_KINDS``.
- ``validation/curves/<case>/*.csv``: optional reference curves with tolerance bands
  (columns time, value, lower, upper; the channel in a ``# channel:`` header line).
- ``validation/baselines/<case>.csv``: frozen approved runs of our own (``freeze``), compared
  at every later run of the case.

Runs use the runner (``<build>/bin/raildyn run DECK -o OUT``), read results with
``raildyn.Results``; everything is SI and follows docs/conventions.md. See
docs/validation.md for the cases, rules and how to add one.
"""

from __future__ import annotations

import argparse
import csv
import datetime as _dt
import hashlib
import math
import os
import re
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np

from .executable import ExecutableNotFound, find_raildyn_executable
from .results import Results
# the growth-rate estimator is the product's (raildyn critical-speed --method bisection)
from .stability import StabilityError, bisection_critical_speed, growth_rate, half_cycle_peaks

REPO = Path(__file__).resolve().parents[2]
INPUTS = REPO / "inputs"
VALIDATION = REPO / "validation"
#: Where reference curves (curves/<case>/*.csv) and frozen baselines (baselines/<case>.csv) are
#: looked up and frozen; the harness's own tests point it elsewhere to run synthetic cases.
BANDS = VALIDATION

__all__ = ["CASES", "Case", "CaseResult", "Check", "band_verdict", "family_scales", "manchester_acceptance",
           "load_package_table", "half_cycle_peaks", "growth_rate", "oscillation_wavelength",
           "window_mean", "run_case", "run_cases", "freeze_baseline", "compare_band_curve",
           "read_band_csv", "deck_assumptions", "deck_files", "run_notes", "main"]

# ------------------------------------------------------------------------------------------
# small data types


@dataclass
class Check:
    """One pass/fail statement of a case."""
    name: str
    passed: bool
    value: float | None = None       #: measured value (SI unit of ``unit``)
    limit: str = ""                  #: the acceptance limit in words (e.g. '< 0 1/s')
    unit: str = ""
    detail: str = ""                 #: justification / how it was measured / why it failed


@dataclass
class Table:
    """A comparison table for the report: column names and rows of cells (str or float);
    ``status`` holds one bool per row (pass/fail colouring) or None."""
    title: str
    columns: list[str]
    rows: list[list]
    status: list[bool | None] = field(default_factory=list)
    note: str = ""


@dataclass
class CaseResult:
    name: str
    title: str = ""
    description: str = ""
    deck: str = ""
    results_path: str = ""
    status: str = "not run"          #: run status ('completed', 'failed: ...', 'not run', ...)
    run_wall_time: float | None = None
    raildyn_version: str = ""
    deck_sha256: str = ""
    assumptions: list[str] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    plots: list[tuple[str, bytes]] = field(default_factory=list, repr=False)   #: (title, PNG)
    notes: list[str] = field(default_factory=list)
    error: str = ""                  #: why the case could not be evaluated

    @property
    def passed(self) -> bool:
        return not self.error and bool(self.checks) and all(c.passed for c in self.checks)

    def summary(self) -> str:
        lines = [f"case {self.name}: {'PASS' if self.passed else 'FAIL'} (run status: {self.status})"]
        if self.error:
            lines.append(f"  error: {self.error}")
        for c in self.checks:
            v = "" if c.value is None else f" = {c.value:.6g} {c.unit}".rstrip()
            lines.append(f"  [{'ok' if c.passed else 'FAIL'}] {c.name}{v} (limit {c.limit}) {c.detail}".rstrip())
        return "\n".join(lines)


class CaseError(RuntimeError):
    """A case cannot be evaluated (missing results, missing channel, run failure)."""


# ------------------------------------------------------------------------------------------
# CSV with header comments


def read_commented_csv(path: str | os.PathLike) -> tuple[list[str], list[dict[str, str]]]:
    """Header comment lines (without '# ') and the rows as dicts."""
    comments, lines = [], []
    with open(path, newline="") as f:
        for line in f:
            if line.startswith("#"):
                comments.append(line[1:].strip())
            elif line.strip():
                lines.append(line)
    return comments, list(csv.DictReader(lines))


# ------------------------------------------------------------------------------------------
# Manchester tables and the acceptance rule

#: Commercial packages of the benchmark (VIA is the thesis' own code, shown but not used).
PACKAGES = ("SIMPACK", "VAMPIRE", "GENSYS", "ADAMS", "NUCARS")
UNIT_SCALE = {"mm": 1e-3, "mrad": 1e-3, "kN": 1e3, "m": 1.0, "rad": 1.0, "N": 1.0}
SI_UNIT = {"mm": "m", "mrad": "rad", "kN": "N"}
#: The Manchester rule (docs/validation.md): the package range is widened by this
#: fraction of the family's S; at least MANCHESTER_MIN_INSIDE of the 32 entries must lie inside,
#: and none may be further than MANCHESTER_MAX_OFF_PERCENT % of S from the unwidened range.
MANCHESTER_WIDEN = 0.10
MANCHESTER_MIN_INSIDE = 29
MANCHESTER_MAX_OFF_PERCENT = 20.0


@dataclass
class PackageEntry:
    quantity: str
    wheelset: int
    side: str                       #: 'left' / 'right' / '' (wheelset quantities)
    unit: str                       #: printed unit (mm, mrad, kN)
    via: float                      #: printed VIA value
    printed: dict[str, float]       #: package -> printed value
    values: dict[str, float]        #: package -> value after corrections (printed unit)
    corrections: list[str] = field(default_factory=list)

    @property
    def key(self) -> str:
        return f"{self.quantity} ws{self.wheelset}" + (f" {self.side}" if self.side else "")

    def magnitudes_si(self, packages: Sequence[str] = PACKAGES) -> np.ndarray:
        return np.array([abs(self.values[p]) for p in packages]) * UNIT_SCALE[self.unit]

    def consensus_sign(self) -> float:
        return float(np.sign(np.median([self.values[p] for p in PACKAGES])))


def load_package_table(path: str | os.PathLike | None = None,
                       corrections: str | os.PathLike | None = None,
                       apply_corrections: bool = True) -> list[PackageEntry]:
    """Thesis tables 5.9-5.11 (validation/manchester_v1_tc1/packages.csv) with the
    documented corrections applied (corrections.csv)."""
    base = VALIDATION / "manchester_v1_tc1"
    _, rows = read_commented_csv(path or base / "packages.csv")
    fixes: dict[tuple, tuple[float, float, str]] = {}
    corr_path = Path(corrections) if corrections else base / "corrections.csv"
    if apply_corrections and corr_path.exists():
        for r in read_commented_csv(corr_path)[1]:
            fixes[(r["quantity"], int(r["wheelset"]), r["side"], r["package"])] = (
                float(r["printed"]), float(r["corrected"]), r["evidence"])
    entries = []
    for r in rows:
        printed = {p: float(r[p]) for p in PACKAGES}
        values = dict(printed)
        notes = []
        for p in PACKAGES:
            fix = fixes.pop((r["quantity"], int(r["wheelset"]), r["side"], p), None)
            if fix is not None:
                if not math.isclose(fix[0], printed[p]):
                    raise ValueError(f"{corr_path}: correction of {r['quantity']} ws{r['wheelset']} "
                                     f"{r['side']} {p} expects printed {fix[0]}, table has {printed[p]}")
                values[p] = fix[1]
                notes.append(f"{p} {fix[0]:g} -> {fix[1]:g} ({fix[2]})")
        entries.append(PackageEntry(r["quantity"], int(r["wheelset"]), r["side"], r["unit"],
                                    float(r["VIA"]), printed, values, notes))
    if fixes:
        raise ValueError(f"{corr_path}: corrections match no table entry: {sorted(fixes)}")
    return entries


@dataclass
class BandVerdict:
    """The Manchester rule for one entry (all magnitudes, SI)."""
    value: float          #: raildyn's magnitude
    lower: float          #: smallest package magnitude
    upper: float          #: largest package magnitude
    scale: float          #: S, the largest package median magnitude of the entry's family
    band_lower: float     #: lower - 10% S
    band_upper: float     #: upper + 10% S
    off_percent: float    #: distance to the unwidened package range, % of S (0 inside it)
    within: bool          #: inside the widened band


def band_verdict(value: float, package_values: Sequence[float], scale: float,
                 widen: float = MANCHESTER_WIDEN) -> BandVerdict:
    """Compare |value| with the range [lo, hi] of |package_values|: inside when
    lo - widen*scale <= |value| <= hi + widen*scale; 'off by' is the distance from |value| to the
    *unwidened* range, in percent of ``scale`` (so an entry inside the band is off by at most
    100*widen %)."""
    mags = np.abs(np.asarray(package_values, float))
    if mags.size == 0 or not np.all(np.isfinite(mags)) or not math.isfinite(value):
        raise ValueError("band_verdict: finite value and package values needed")
    if not (math.isfinite(scale) and scale > 0):
        raise ValueError(f"band_verdict: the scale must be finite and positive, got {scale}")
    v = abs(float(value))
    lo, hi = float(mags.min()), float(mags.max())
    dist = max(lo - v, v - hi, 0.0)
    return BandVerdict(v, lo, hi, scale, lo - widen * scale, hi + widen * scale,
                       100.0 * dist / scale, lo - widen * scale <= v <= hi + widen * scale)


def family_scales(entries: Sequence[PackageEntry], packages: Sequence[str] = PACKAGES) -> dict[str, float]:
    """S per quantity family (lateral shift, yaw, longitudinal, lateral, vertical force): the
    largest of the family's per-entry package median magnitudes [SI]. An entry's deviation is
    measured in S, not in its own median: entries near zero (yaw ws2, 0.5-1.1 mrad) would
    otherwise turn the packages' own scatter into large relative deviations."""
    scales: dict[str, float] = {}
    for e in entries:
        med = float(np.median(e.magnitudes_si(packages)))
        scales[e.quantity] = max(scales.get(e.quantity, 0.0), med)
    return scales


@dataclass
class AcceptanceOutcome:
    passed: bool
    n_inside: int                    #: entries inside their widened band
    n_entries: int
    max_off_percent: float           #: largest 'off by', % of the family's S
    worst: str                       #: key of the entry with the largest 'off by'
    verdicts: list[BandVerdict]      #: one per entry, in the order of the table


def manchester_acceptance(values: Mapping[str, float], entries: Sequence[PackageEntry] | None = None,
                          packages: Sequence[str] = PACKAGES) -> AcceptanceOutcome:
    """The Manchester rule (docs/validation.md): ``values`` (entry key -> signed value, SI) against
    the magnitudes of ``packages`` in ``entries`` (default: the thesis tables). Passes when at
    least MANCHESTER_MIN_INSIDE entries lie inside their widened band and none is off by more
    than MANCHESTER_MAX_OFF_PERCENT % of its family's S."""
    entries = load_package_table() if entries is None else entries
    if not entries:
        raise ValueError("manchester_acceptance: no table entries")
    missing = [e.key for e in entries if e.key not in values]
    if missing:
        raise ValueError("manchester_acceptance: no value for " + ", ".join(missing))
    scales = family_scales(entries, packages)
    verdicts = [band_verdict(values[e.key], e.magnitudes_si(packages), scales[e.quantity]) for e in entries]
    n_inside = sum(v.within for v in verdicts)
    k = int(np.argmax([v.off_percent for v in verdicts]))
    worst = verdicts[k].off_percent
    return AcceptanceOutcome(n_inside >= MANCHESTER_MIN_INSIDE and worst <= MANCHESTER_MAX_OFF_PERCENT,
                             n_inside, len(verdicts), worst, entries[k].key, verdicts)


# ------------------------------------------------------------------------------------------
# signal analysis


def window_mask(t: np.ndarray, t_from: float, t_to: float) -> np.ndarray:
    return (t >= t_from - 1e-12) & (t <= t_to + 1e-12)


def window_mean(t: np.ndarray, y: np.ndarray, t_from: float, t_to: float) -> float:
    m = window_mask(t, t_from, t_to)
    if m.sum() < 2:
        raise CaseError(f"window [{t_from:g}, {t_to:g}] s holds fewer than 2 output points "
                        f"(results cover {t[0]:g} to {t[-1]:g} s)" if t.size else "no output rows")
    return float(np.mean(y[m]))


def oscillation_wavelength(t: np.ndarray, y: np.ndarray, speed: float) -> float:
    """Wavelength [m] = speed x period, the period from the mean spacing of the zero
    crossings (two per period, linearly interpolated)."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    i = np.flatnonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)
    if i.size < 3:
        raise CaseError("fewer than 3 zero crossings: no oscillation to measure a wavelength")
    tc = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    return float(speed * 2.0 * np.mean(np.diff(tc)))


# ------------------------------------------------------------------------------------------
# band curves: reference curves and frozen baselines


def read_band_csv(path: str | os.PathLike) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """A band CSV: either a reference curve (columns time, value, lower, upper and a header
    comment '# channel: <path:component>') or a baseline (columns time, <ch>, <ch>:lower,
    <ch>:upper for several channels). Returns {channel: (time, value, lower, upper)}."""
    comments, rows = read_commented_csv(path)
    if not rows:
        raise ValueError(f"{path}: no data rows")
    cols = list(rows[0].keys())
    data = {c: np.array([float(r[c]) for r in rows]) for c in cols}
    if "time" not in data:
        raise ValueError(f"{path}: no 'time' column")
    out = {}
    if "value" in data:
        chans = [c.split(":", 1)[1].strip() for c in comments if c.lower().startswith("channel:")]
        if len(chans) != 1:
            raise ValueError(f"{path}: a reference curve needs one '# channel: <series:component>' line")
        out[chans[0]] = (data["time"], data["value"], data["lower"], data["upper"])
    else:
        for c in cols:
            if c == "time" or c.endswith(":lower") or c.endswith(":upper"):
                continue
            out[c] = (data["time"], data[c], data[c + ":lower"], data[c + ":upper"])
    for ch, (_, v, lo, hi) in out.items():
        if np.any(lo > v) or np.any(hi < v):
            raise ValueError(f"{path}: band of {ch} does not contain its value")
    return out


def compare_band_curve(t: np.ndarray, y: np.ndarray, t_ref: np.ndarray, lower: np.ndarray,
                       upper: np.ndarray) -> tuple[bool, float, float, int]:
    """Interpolate the result (t, y) at the reference times inside the result's time span
    and check lower <= y <= upper. Returns (passed, largest violation [channel unit], time of
    it, number of points compared); no overlap fails."""
    m = (t_ref >= t[0] - 1e-12) & (t_ref <= t[-1] + 1e-12)
    if not m.any():
        return False, math.inf, math.nan, 0
    yi = np.interp(t_ref[m], t, y)
    viol = np.maximum(lower[m] - yi, yi - upper[m])
    k = int(np.argmax(viol))
    return bool(np.all(viol <= 0)), float(max(viol[k], 0.0)), float(t_ref[m][k]), int(m.sum())


def freeze_baseline(case: str, results_path: str | os.PathLike, channels: Sequence[str],
                    out: str | os.PathLike | None = None, rel: float = 0.02, abs_tol: float = 1e-6,
                    every: int = 1) -> Path:
    """Copy channels of an approved run into validation/baselines/<case>.csv with a band
    value +- (rel * (max - min over the run) + abs_tol)."""
    out = Path(out) if out else BANDS / "baselines" / f"{case}.csv"
    with Results(results_path) as r:
        t = r.time[::every]
        cols, header = [t], ["time"]
        for ch in channels:
            y = np.asarray(r.get(ch), float)
            if y.ndim != 1:
                raise ValueError(f"freeze: give one column ('series:component'), not {ch!r}")
            y = y[::every]
            half = rel * float(np.ptp(y)) + abs_tol
            cols += [y, y - half, y + half]
            header += [ch, ch + ":lower", ch + ":upper"]
        meta = r.metadata
        deck_hash = hashlib.sha256((r.deck_text or "").encode()).hexdigest()
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "w", newline="") as f:
        f.write(f"# Regression baseline of validation case '{case}', frozen "
                f"{_dt.datetime.now(_dt.timezone.utc).isoformat(timespec='seconds')} from "
                f"{Path(results_path).name}\n")   # the name only: no machine path in a tracked file
        f.write(f"# raildyn {meta.get('raildyn_version')}, deck sha256 {deck_hash}, run status "
                f"{meta.get('status')}\n")
        f.write(f"# band: value +- ({rel:g} x channel range over the run + {abs_tol:g}) (SI units)\n")
        w = csv.writer(f)
        w.writerow(header)
        for row in np.column_stack(cols):
            w.writerow([f"{x:.10g}" for x in row])
    return out


# ------------------------------------------------------------------------------------------
# decks: include tree, hashes, ASSUMPTION lines

_INCLUDE = re.compile(r"&include\s+file\s*=\s*(['\"])(.*?)\1", re.IGNORECASE)


def deck_files(deck: str | os.PathLike) -> list[Path]:
    """The deck and every deck it includes (depth first, each once)."""
    seen: list[Path] = []

    def visit(p: Path) -> None:
        p = p.resolve()
        if p in seen:
            return
        seen.append(p)
        for line in p.read_text().splitlines():
            code = line.split("!", 1)[0]
            for m in _INCLUDE.finditer(code):
                visit((p.parent / m.group(2)) if not os.path.isabs(m.group(2)) else Path(m.group(2)))

    visit(Path(deck))
    return seen


def deck_assumptions(deck: str | os.PathLike) -> list[str]:
    """'! ASSUMPTION: ...' comment blocks of the deck and its includes (continuation lines
    are the following comment lines indented by more than one blank), prefixed by the file."""
    out = []
    for p in deck_files(deck):
        lines = p.read_text().splitlines()
        i = 0
        while i < len(lines):
            s = lines[i].strip()
            if s.startswith("!") and s[1:].strip().upper().startswith("ASSUMPTION"):
                text = s[1:].strip()
                text = text[len("ASSUMPTION"):].lstrip(":").strip()
                i += 1
                while i < len(lines) and re.match(r"^\s*!\s{2,}\S", lines[i]):
                    text += " " + lines[i].strip()[1:].strip()
                    i += 1
                out.append(f"{p.relative_to(REPO) if p.is_relative_to(REPO) else p}: {text}")
            else:
                i += 1
    return out


def deck_sha256(deck: str | os.PathLike) -> str:
    h = hashlib.sha256()
    for p in deck_files(deck):
        h.update(p.read_bytes())
    return h.hexdigest()


# ------------------------------------------------------------------------------------------
# running


def find_executable(exe: str | os.PathLike | None = None) -> Path:
    """The raildyn runner (raildyn.executable: the explicit path or nothing, else
    $RAILDYN_EXE, $RAILDYN_BUILD_DIR/bin/raildyn, <repo>/build/bin/raildyn)."""
    try:
        return find_raildyn_executable(exe, "--exe")
    except ExecutableNotFound as exc:
        raise CaseError(str(exc)) from None


#: runner exit statuses (README): 3 = physics limit (derailment, lift-off): results readable
_EXIT = {0: "completed", 1: "bad input", 2: "solver failure", 3: "physics limit", 4: "file error",
         5: "internal error"}


@dataclass
class RunInfo:
    results: Path
    returncode: int
    wall_time: float
    stderr: str
    reused: bool = False
    stdout: str = ""


def run_notes(metadata: dict) -> list[str]:
    """The run's notes as the results file keeps them (``/meta`` attribute ``notes``, one per
    line; the 'note:' lines `raildyn run` prints), e.g. wheels that lost contact in some
    output samples. Files written before the attribute existed have none."""
    return [line.strip() for line in str(metadata.get("notes") or "").splitlines() if line.strip()]


#: Wall-clock limit of one run [s] ($RAILDYN_VALIDATION_TIMEOUT overrides): a run that takes
#: longer fails its case with that message instead of holding CI.
DEFAULT_RUN_TIMEOUT = 900.0


def run_timeout() -> float:
    value = os.environ.get("RAILDYN_VALIDATION_TIMEOUT")
    return float(value) if value else DEFAULT_RUN_TIMEOUT


def run_deck(deck: Path, results: Path, exe: str | os.PathLike | None = None, overrides: str = "",
             timeout: float | None = None, reuse: bool = False) -> RunInfo:
    """Run a deck (optionally with override groups appended through an including deck next to
    the results) and return where the results are. Statuses 0 and 3 leave usable results.
    ``exe`` as for ``find_executable`` (looked up only when a run is needed)."""
    if reuse and results.exists():
        return RunInfo(results, 0, 0.0, "", reused=True)
    exe = find_executable(exe)
    timeout = run_timeout() if timeout is None else timeout
    results.parent.mkdir(parents=True, exist_ok=True)
    run_deck_path = deck
    if overrides:
        run_deck_path = results.with_suffix(".nml")
        run_deck_path.write_text(f"! generated by raildyn.validation: {deck.name} with overrides\n"
                                 f"&include file = '{deck.resolve()}' /\n{overrides}\n")
    if results.exists():
        results.unlink()
    t0 = time.perf_counter()
    try:
        proc = subprocess.run([os.fspath(exe), "run", os.fspath(run_deck_path), "-o", os.fspath(results)],
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise CaseError(f"raildyn run {run_deck_path.name} exceeded the wall-clock limit of {timeout:g} s "
                        "(RAILDYN_VALIDATION_TIMEOUT); the partial results are in "
                        f"{results}") from None
    wall = time.perf_counter() - t0
    if proc.returncode not in (0, 3):
        msg = (proc.stderr.strip() or proc.stdout.strip()).splitlines()
        raise CaseError(f"raildyn run {run_deck_path} exited with {proc.returncode} "
                        f"({_EXIT.get(proc.returncode, '?')}): {msg[-1] if msg else 'no message'}")
    if not results.exists():
        raise CaseError(f"raildyn run {run_deck_path} wrote no results file {results}")
    return RunInfo(results, proc.returncode, wall, proc.stderr, stdout=proc.stdout)


# ------------------------------------------------------------------------------------------
# case context and registry


#: Channels are named as in docs/output.md; results written with one series per wheel
#: ('wheelsets/<w>/<side>/wheel') and per contact patch ('.../patch<j>') are read through
#: these (pattern, replacement) pairs, tried in order.
_W = r"^(wheelsets/[^/]+/(?:left|right))"
CHANNEL_ALIASES = [(re.compile(p), r) for p, r in (
    (_W + r"/force_track:fx$", r"\1/wheel:force_longitudinal"),
    (_W + r"/force_track:fy$", r"\1/wheel:force_lateral_Y"),
    (_W + r"/force_track:fz$", r"\1/wheel:force_vertical_Q"),
    (_W + r"/Y_Q:Y_Q$", r"\1/wheel:Y_over_Q"),
    (_W + r"/contact(\d+)/creepage:xi$", r"\1/patch\2:xi"),
    (_W + r"/contact(\d+)/creepage:eta$", r"\1/patch\2:eta"),
    (_W + r"/contact(\d+)/creepage:phi$", r"\1/patch\2:spin"),
    (_W + r"/contact(\d+)/creep_force_contact:fx$", r"\1/patch\2:creep_force_x"),
    (_W + r"/contact(\d+)/creep_force_contact:fy$", r"\1/patch\2:creep_force_y"),
    (_W + r"/contact(\d+)/creep_force_contact:mz$", r"\1/patch\2:spin_moment"),
    (_W + r"/contact(\d+)/normal_force:N$", r"\1/patch\2:normal_force"),
    (_W + r"/contact(\d+)/geometry:gamma$", r"\1/patch\2:contact_angle"),
    (_W + r"/contact(\d+)/ellipse:a$", r"\1/patch\2:semi_axis_a"),
    (_W + r"/contact(\d+)/ellipse:b$", r"\1/patch\2:semi_axis_b"),
)]


def resolve_channel(r: Results, channel: str) -> str | None:
    """The name under which results ``r`` hold a channel given by its docs/output.md name:
    itself, or its name in the per-wheel/per-patch layout (CHANNEL_ALIASES); None."""
    if channel in r:
        return channel
    for pattern, repl in CHANNEL_ALIASES:
        alt, n = pattern.subn(repl, channel)
        if n and alt in r:
            return alt
    return None


class Context:
    """What an evaluation function works with: the case's results and helpers."""

    def __init__(self, case: "Case", result: CaseResult, results: Results | None, out_dir: Path,
                 exe: str | os.PathLike | None, reuse: bool, others: dict[str, Path]):
        self.case, self.result, self.r, self.out_dir = case, result, results, out_dir
        self.exe, self.reuse, self.others = exe, reuse, others
        self.cache: dict = {}        #: values shared by the checks of one evaluation

    # data access with a clear message when the scene did not write a channel
    def resolve(self, channel: str, results: Results | None = None) -> str | None:
        """The name under which the results hold a channel given by its docs/output.md name:
        itself, or its name in the per-wheel/per-patch layout (CHANNEL_ALIASES); None."""
        r = results or self.r
        if r is None:
            raise CaseError(f"case {self.case.name} has no results of its own")
        return resolve_channel(r, channel)

    def has(self, channel: str, results: Results | None = None) -> bool:
        return self.resolve(channel, results) is not None

    def get(self, channel: str, results: Results | None = None) -> np.ndarray:
        r = results or self.r
        name = self.resolve(channel, r)
        if name is None:
            bodies = [c for c in r.channels() if c.startswith(("bodies/", "wheelsets/"))]
            hint = ("" if bodies else " (the results hold no bodies/ or wheelsets/ series: the "
                    "scene did not build bodies and wheelsets from the deck)")
            raise CaseError(f"{Path(r.path).name}: no channel {channel!r}{hint}")
        return np.asarray(r.get(name), float)

    def time(self, results: Results | None = None) -> np.ndarray:
        return np.asarray((results or self.r).time, float)

    def speed(self, results: Results | None = None) -> float:
        return float(np.mean(self.get("vehicle/speed:V", results)))

    def check(self, name: str, passed: bool, value: float | None = None, limit: str = "",
              unit: str = "", detail: str = "") -> Check:
        c = Check(name, bool(passed), value, limit, unit, detail)
        self.result.checks.append(c)
        return c

    def plot(self, title: str, series: Iterable[tuple[str, np.ndarray, np.ndarray]], ylabel: str,
             scale: float = 1.0, window: tuple[float, float] | None = None,
             bands: Iterable[tuple[str, np.ndarray, np.ndarray, np.ndarray]] = ()) -> None:
        from .report import figure_png
        self.result.plots.append((title, figure_png(title, list(series), ylabel, scale, window,
                                                    list(bands))))

    def other_results(self, case_name: str) -> Results:
        """Results of another case (opened once, closed by ``close``)."""
        if case_name not in self.others:
            raise CaseError(f"case {self.case.name} needs the results of case {case_name}")
        key = ("results", case_name)
        if key not in self.cache:
            self.cache[key] = Results(self.others[case_name])
        return self.cache[key]

    def close(self) -> None:
        for key, value in list(self.cache.items()):
            if isinstance(key, tuple) and key[0] in ("results", "fastsim_reference"):
                value.close()
                del self.cache[key]

    def run_variant(self, tag: str, overrides: str) -> Results:
        """Run the case's deck with override groups (e.g. another speed) into out_dir."""
        info = run_deck(self.case.deck_path, self.out_dir / f"{self.case.name}__{tag}.h5", self.exe,
                        overrides, reuse=self.reuse)
        return Results(info.results)


@dataclass
class Case:
    name: str
    deck: str                                   #: relative to inputs/
    title: str
    description: str
    evaluate: Callable[[Context], None]
    needs: tuple[str, ...] = ()                 #: cases whose results this one compares with
    baseline_channels: tuple[str, ...] = ()     #: default channels of ``freeze``
    run: bool = True                            #: False: evaluation runs its own variants only

    @property
    def deck_path(self) -> Path:
        return INPUTS / self.deck


# -- Manchester V1 TC1 ----------------------------------------------------------------------

#: Quasi-static window of the Manchester case: the vehicle reference (car body centre) between
#: these track positions [m] has every wheelset at least 15 m inside the constant curve
#: (curve 80-140 m; wheelsets at +-8.22, +-10.78 m from the reference), see the deck header.
MANCHESTER_SIGMA_WINDOW = (106.0, 128.5)

_MB_CHANNEL = {
    "lateral_shift": ("bodies/ws{k}/position_track:y", "m"),
    "yaw": ("bodies/ws{k}/position_track:yaw", "rad"),
    "longitudinal_force": ("wheelsets/w{k}/{side}/force_track:fx", "N"),
    "lateral_force": ("wheelsets/w{k}/{side}/force_track:fy", "N"),
    "vertical_force": ("wheelsets/w{k}/{side}/force_track:fz", "N"),
}


def manchester_window(ctx: Context) -> tuple[float, float]:
    return manchester_window_times(ctx.time(), ctx.get("vehicle/distance:sigma"))


def manchester_window_times(t: np.ndarray, sigma: np.ndarray) -> tuple[float, float]:
    """First and last output time [s] with the vehicle reference inside MANCHESTER_SIGMA_WINDOW."""
    m = (sigma >= MANCHESTER_SIGMA_WINDOW[0]) & (sigma <= MANCHESTER_SIGMA_WINDOW[1])
    if m.sum() < 2:
        raise CaseError(f"the run does not reach the quasi-static window (reference sigma "
                        f"{MANCHESTER_SIGMA_WINDOW[0]:g}-{MANCHESTER_SIGMA_WINDOW[1]:g} m); it ends at "
                        f"sigma = {sigma[-1] if sigma.size else float('nan'):.2f} m, t = "
                        f"{t[-1] if t.size else float('nan'):.2f} s")
    return float(t[m][0]), float(t[m][-1])


def manchester_window_values(t: np.ndarray, get: Callable[[str], np.ndarray], entries: Sequence[PackageEntry],
                             w0: float, w1: float) -> dict[str, float]:
    """Entry key -> signed window mean [SI] of the entry's channel (``get``: docs/output.md
    channel name -> series) over [w0, w1] s: the values the Manchester rule judges."""
    return {e.key: window_mean(t, get(_MB_CHANNEL[e.quantity][0].format(k=e.wheelset, side=e.side)), w0, w1)
            for e in entries}


def evaluate_manchester(ctx: Context) -> None:
    entries = load_package_table()
    t = ctx.time()
    w0, w1 = manchester_window(ctx)
    ours = manchester_window_values(t, ctx.get, entries, w0, w1)
    out = manchester_acceptance(ours, entries)
    rows, sign_rel = [], {}
    for e, v in zip(entries, out.verdicts):
        s = UNIT_SCALE[e.unit]
        # sign relation vs the package consensus (information); below 10% of S an entry is near
        # zero for its family and its sign says little
        if v.value > 0.1 * v.scale:
            sign_rel.setdefault(e.quantity, set()).add(np.sign(ours[e.key]) * e.consensus_sign())
        rows.append([e.key, e.unit, f"{ours[e.key] / s:.4g}", f"{v.lower / s:.4g}", f"{v.upper / s:.4g}",
                     f"{v.scale / s:.4g}", f"{v.band_lower / s:.4g} .. {v.band_upper / s:.4g}",
                     f"{v.off_percent:.1f}", f"{e.via:g}", "; ".join(e.corrections)])
    widen = f"{100 * MANCHESTER_WIDEN:g}"
    ctx.result.tables.append(Table(
        f"Quasi-static values, window t = {w0:.2f}-{w1:.2f} s (reference sigma "
        f"{MANCHESTER_SIGMA_WINDOW[0]:g}-{MANCHESTER_SIGMA_WINDOW[1]:g} m): magnitudes",
        ["entry", "unit", "raildyn (signed)", "package min |.|", "package max |.|", "S (family)",
         f"band (+-{widen}% S)", "off by % S", "VIA (thesis)", "corrections"], rows,
        [v.within for v in out.verdicts],
        "Packages: SIMPACK, VAMPIRE, GENSYS, ADAMS/Rail, NUCARS (thesis tables 5.9-5.11). "
        "Compared as magnitudes because the tables carry sign slips. S is the largest package "
        "median magnitude of the entry's quantity family (lateral shift, yaw, longitudinal, "
        f"lateral, vertical force); the band is the package range widened by {widen}% of S; "
        "'off by' is the distance to the unwidened package range in % of S."))
    ctx.check("entries inside the widened package band", out.n_inside >= MANCHESTER_MIN_INSIDE,
              out.n_inside, f">= {MANCHESTER_MIN_INSIDE} of {out.n_entries}", "entries",
              f"{out.n_inside} of {out.n_entries} entries")
    ctx.check("largest deviation from the package range", out.max_off_percent <= MANCHESTER_MAX_OFF_PERCENT,
              out.max_off_percent, f"<= {MANCHESTER_MAX_OFF_PERCENT:g} % of the family's S", "%",
              f"worst entry: {out.worst}")
    mixed = [q for q, s in sign_rel.items() if len(s) > 1]
    ctx.result.notes.append(
        "Sign pattern (information, not part of the rule): per quantity, raildyn's signs relative "
        "to the package consensus are " + ", ".join(
            f"{q}: {'consistent' if len(s) == 1 else 'MIXED'}" for q, s in sign_rel.items()) +
        (". Mixed patterns point at a wheelset or wheel behaving differently from the packages."
         if mixed else "."))
    # flange clearance (information): what separates raildyn from the packages at the
    # benchmark gauge (docs/validation.md, "Flange clearance sensitivity")
    shifts = [abs(window_mean(t, ctx.get(f"bodies/ws{k}/position_track:y"), w0, w1)) for k in range(1, 5)]
    pkg = [e.magnitudes_si() for e in entries if e.quantity == "lateral_shift"]
    ctx.result.notes.append(
        "Flange clearance (information, not part of the rule): raildyn's wheelsets sit "
        + " / ".join(f"{1e3 * y:.2f}" for y in shifts) + " mm from the track centre (ws1-ws4), "
        f"the packages' at {1e3 * min(map(min, pkg)):.1f}-{1e3 * max(map(max, pkg)):.1f} mm (medians "
        + " / ".join(f"{1e3 * float(np.median(m)):.1f}" for m in pkg) + "). With the stated profiles, "
        "gauge 1435 mm and back-to-back 1360 mm the rigid flange contact lies at 6.0-6.5 mm "
        "(CONTACT's Manchester A-2.2 reference); the bogie yaw (y1 - y2) / wheelbase, and with it "
        "the yaw of wheelset 2, follows these positions. Rerun with the gauge widened by 1.5-3 mm "
        "(validation/manchester_v1_tc1/gauge_sensitivity.toml, docs/validation.md) the wheelsets "
        "move outwards and yaw ws2 falls towards the packages' values: the packages' flange "
        "clearance is not in the benchmark data available to us.")
    # static balance (information): sum of vertical wheel forces against the weight
    qsum = sum(window_mean(t, ctx.get(f"wheelsets/w{k}/{side}/force_track:fz"), w0, w1)
               for k in range(1, 5) for side in ("left", "right"))
    ctx.result.notes.append(f"Sum of vertical wheel forces in the window: {qsum / 1e3:.2f} kN "
                            f"(vehicle weight 44 482 kg x g = 436.22 kN).")
    ws = range(1, 5)
    ctx.plot("Lateral shift of the wheelsets", [(f"ws{k}", t, ctx.get(f"bodies/ws{k}/position_track:y"))
                                                 for k in ws], "y [mm]", 1e3, (w0, w1))
    ctx.plot("Yaw angle of the wheelsets", [(f"ws{k}", t, ctx.get(f"bodies/ws{k}/position_track:yaw"))
                                             for k in ws], "yaw [mrad]", 1e3, (w0, w1))
    for q, comp in (("Lateral", "fy"), ("Vertical", "fz"), ("Longitudinal", "fx")):
        ctx.plot(f"{q} wheel forces (track frame, on the wheel)",
                 [(f"ws{k} {side}", t, ctx.get(f"wheelsets/w{k}/{side}/force_track:{comp}"))
                  for k in ws for side in ("left", "right")], "force [kN]", 1e-3, (w0, w1))
    if all(ctx.has(f"wheelsets/w1/{s}/Y_Q:Y_Q") for s in ("left", "right")):
        ctx.plot("Y/Q of wheelset 1", [(f"ws1 {s}", t, ctx.get(f"wheelsets/w1/{s}/Y_Q:Y_Q"))
                                       for s in ("left", "right")], "Y/Q [-]", 1.0, (w0, w1))


# -- TGV checks -----------------------------------------------------------------------------


def load_tgv_checks(path: str | os.PathLike | None = None) -> list[dict[str, str]]:
    return read_commented_csv(path or VALIDATION / "tgv_checks.csv")[1]


#: The designed track curves to the left (inputs/tracks/tgv_designed_track.nml): outward = -y.
TGV_OUTWARD_SIGN = -1.0


def _window(ctx: Context, row: dict, channel: str | None = None, results: Results | None = None):
    t = ctx.time(results)
    t0, t1 = float(row["t_from"]), float(row["t_to"])
    y = ctx.get(channel or row["channel"], results)
    m = window_mask(t, t0, t1)
    if m.sum() < 2:
        raise CaseError(f"check {row['id']}: window [{t0:g}, {t1:g}] s not covered (results end at "
                        f"{t[-1] if t.size else float('nan'):g} s)")
    return t[m], y[m]


def _kind_growth(ctx, row, above: bool):
    t, y = _window(ctx, row)
    rate, npk = growth_rate(t, y)
    thr = float(row["threshold"])
    ok = rate > thr if above else rate < thr
    ctx.check(row["id"], ok, rate, f"{'>' if above else '<'} {thr:g}", "1/s",
              f"{npk} half-cycle peaks; {row['justification']}")


def _kind_amplitude(ctx, row, above: bool):
    t, y = _window(ctx, row)
    amp = float(np.max(np.abs(y)))
    thr = float(row["threshold"])
    ctx.check(row["id"], amp > thr if above else amp < thr, amp, f"{'>' if above else '<'} {thr:g}",
              row["unit"], row["justification"])


def _kind_relative_amplitude(ctx, row, above: bool):
    t_all = ctx.time()
    y_all = ctx.get(row["channel"])
    before = t_all < float(row["t_from"]) - 1e-12
    if not before.any():
        raise CaseError(f"check {row['id']}: no output before the window")
    peak = float(np.max(np.abs(y_all[before])))
    _, y = _window(ctx, row)
    amp = float(np.max(np.abs(y)))
    ratio = amp / peak if peak > 0 else math.inf
    thr = float(row["threshold"])
    ctx.check(row["id"], ratio > thr if above else ratio < thr, ratio, f"{'>' if above else '<'} {thr:g}",
              "1", f"max |y| {amp * 1e3:.4f} mm in the window, {peak * 1e3:.4f} mm before; "
              f"{row['justification']}")


def _kind_wavelength(ctx, row, above: bool):
    t, y = _window(ctx, row)
    lam = oscillation_wavelength(t, y, ctx.speed())
    thr = float(row["threshold"])
    ctx.check(row["id"], lam > thr if above else lam < thr, lam, f"{'>' if above else '<'} {thr:g}",
              "m", row["justification"])


def _kind_outward(ctx, row, above: bool):
    t, y = _window(ctx, row)
    out = TGV_OUTWARD_SIGN * float(np.mean(y))
    thr = float(row["threshold"])
    ctx.check(row["id"], out > thr if above else out < thr, out, f"{'>' if above else '<'} {thr:g}",
              "m", f"mean outward shift in the window; {row['justification']}")


def _kind_outward_less(ctx, row):
    a_ch, b_ch = row["channel"].split("|")
    _, a = _window(ctx, row, a_ch)
    _, b = _window(ctx, row, b_ch)
    da = TGV_OUTWARD_SIGN * float(np.mean(a))
    db = TGV_OUTWARD_SIGN * float(np.mean(b))
    ctx.check(row["id"], da < db - float(row["threshold"]), da - db, "< 0", "m",
              f"outward {a_ch.split('/')[1]} {da * 1e3:.3f} mm vs {b_ch.split('/')[1]} {db * 1e3:.3f} mm; "
              f"{row['justification']}")


def _kind_steadiness(ctx, row):
    _, y = _window(ctx, row)
    mean, std = float(np.mean(y)), float(np.std(y))
    thr = float(row["threshold"])
    ok = std < thr * abs(mean) or std < 5e-5
    ctx.check(row["id"], ok, std / abs(mean) if mean else math.inf, f"< {thr:g} (or std < 0.05 mm)", "1",
              f"std {std * 1e3:.4f} mm, mean {mean * 1e3:.4f} mm; {row['justification']}")


def _kind_same_mean(ctx, row):
    a_ch, b_ch = row["channel"].split("|")
    _, a = _window(ctx, row, a_ch)
    _, b = _window(ctx, row, b_ch)
    ma, mb = float(np.mean(a)), float(np.mean(b))
    thr = float(row["threshold"])
    rel = abs(ma - mb) / max(abs(mb), 1e-12)
    ctx.check(row["id"], abs(ma - mb) <= max(thr * abs(mb), 1e-4), rel, f"<= {thr:g} (or 0.1 mm)", "1",
              f"{a_ch.split('/')[1]} {ma * 1e3:.3f} mm vs {b_ch.split('/')[1]} {mb * 1e3:.3f} mm; "
              f"{row['justification']}")


def _kind_flange_contact(ctx, row):
    base = row["channel"]              # wheelsets/<w>/<side>
    side = base.rsplit("/", 1)[1]
    sgn = 1.0 if side == "right" else -1.0   # conventions: gamma > 0 at a right flange contact
    gam = []
    j = 1
    while ctx.has(f"{base}/contact{j}/geometry:gamma"):
        _, g = _window(ctx, row, f"{base}/contact{j}/geometry:gamma")
        _, nf = _window(ctx, row, f"{base}/contact{j}/normal_force:N")
        gam.append(np.where(nf > 0.0, sgn * g, -np.inf))      # active: carries normal force
        j += 1
    if not gam:
        raise CaseError(f"check {row['id']}: no contact point series under {base} "
                        f"(expected {base}/contact1/geometry, docs/output.md)")
    mean_max = float(np.mean(np.max(np.vstack(gam), axis=0)))
    thr = float(row["threshold"])
    ctx.check(row["id"], mean_max > thr, mean_max, f"> {thr:g}", "rad",
              f"window mean of the largest active contact angle; {row['justification']}")


def fastsim_reference(ctx: "Context") -> Results:
    """The case's own deck run again with FASTSIM on every wheelset (everything else, spin
    treatment included, as the deck says): the thesis' 5.6 compares Polach with FASTSIM on the
    same vehicle and track, both "as the spin creepage is not taken into account"."""
    key = ("fastsim_reference",)
    if key not in ctx.cache:
        overrides = "\n".join(f"&wheelset name = '{w}', creep_law = 'fastsim' /"
                              for w in deck_wheelsets(ctx.case.deck_path))
        ctx.cache[key] = ctx.run_variant("fastsim", overrides)
    return ctx.cache[key]


def _kind_case_difference(ctx, row, forces: bool):
    other = fastsim_reference(ctx)
    thr = float(row["threshold"])
    items = [(k, s) for k in range(1, 5) for s in (("left", "right") if forces else ("",))]
    worst, ok_all, parts = 0.0, True, []
    for k, side in items:
        ch = row["channel"].format(k=k, side=side)
        _, a = _window(ctx, row, ch)
        _, b = _window(ctx, row, ch, other)
        ma, mb = float(np.mean(a)), float(np.mean(b))
        d = abs(ma - mb)
        if forces:
            allowed = max(thr * max(abs(ma), abs(mb)), 2000.0)
        else:
            allowed = max(thr, 0.10 * abs(mb))
        ok_all &= d <= allowed
        worst = max(worst, d / allowed)
        parts.append(f"ws{k}{' ' + side if side else ''}: {ma:.4g} vs {mb:.4g}")
    ctx.check(row["id"], ok_all, worst, "<= 1 (difference / allowed)", "1",
              "Polach vs FASTSIM window means: " + "; ".join(parts) + f". {row['justification']}")


def _kind_critical_speed(ctx, row, above: bool):
    if "critical_speed" not in ctx.cache:
        ctx.cache["critical_speed"] = critical_speed_bisection(ctx, row)
    vc = ctx.cache["critical_speed"]
    thr = float(row["threshold"])
    ctx.check(row["id"], vc > thr if above else vc < thr, vc, f"{'>' if above else '<'} {thr:g}", "m/s",
              row["justification"])


# -- linear steady curving of a two-axle bogie (independent formulation) -------------------

#: TGV 001 bogie data used by the linear steady-curving model (same numbers as
#: inputs/vehicles/tgv001_bogie.nml, kept in sync by tests/python/test_validation_rules.py):
#: wheelset and bogie frame masses (table 5.8), primary kx, ky per spring (table 5.4), primary
#: spring lateral semi-spacing dp and semi-wheelbase l (deck ASSUMPTIONs), r0, e0, cone slope
#: (table 5.7).
TGV_BOGIE = dict(m_w=1500.0, m_b=3020.0, kx=3.90e7, ky=7.85e6, dp=1.0, l=1.5, r0=0.45, e0=0.75,
                 lam=0.10033)
#: Complete TGV 001 (inputs/vehicles/tgv001_vehicle.nml): car body mass (table 5.1), secondary
#: kx, ky per spring (table 5.6) at +-ds laterally, bogie pivots at +-pivot (deck ASSUMPTIONs).
TGV_VEHICLE = dict(m_c=43200.0, kx_s=1.73e5, ky_s=1.73e5, ds=1.0, pivot=9.35)


@dataclass
class PlanarBody:
    name: str
    x: float                 #: longitudinal position of its track frame in the vehicle [m]
    mass: float
    wheelset: bool = False


@dataclass
class PlanarSpring:
    body_a: str
    body_b: str
    x: float                 #: longitudinal position of the attachment in the vehicle [m]
    k_lat: float             #: total lateral stiffness [N/m]
    k_yaw: float             #: total yaw stiffness (sum of kx d^2) [N m/rad]


def steady_curving(bodies: Sequence[PlanarBody], springs: Sequence[PlanarSpring], f11: float, f22: float,
                   radius: float, a_q: float, r0: float, e0: float, lam: float) -> dict[str, tuple[float, float]]:
    """Quasi-static curving of a vehicle with conical wheelsets, linear creep and linear
    springs, in the lateral/yaw plane (the classical linear model, e.g. Wickens 2003 ch. 6;
    Iwnicki (ed.) 2006, Handbook of Railway Vehicle Dynamics, ch. 8). Every body is written in
    its own track frame at x_b, like raildyn's bodies: y to the left, yaw nose left, left-hand
    curve (curvature 1/radius > 0). A point of body b at vehicle position X lies, in the track
    frame at X, at y_b + psi_b (X - x_b) - (X - x_b)^2 / (2R) with yaw psi_b - (X - x_b)/R
    (the track bends towards the curve centre and its tangent turns). Wheelsets:

    - longitudinal creepages xi_L,R = -+(e0/R + lam y/r0): yaw moment -2 f11 e0 (e0/R + lam y/r0);
    - lateral creepage eta = -psi: lateral force 2 f22 psi (spin neglected: it cancels between
      the wheels of a cone);

    and the uncompensated lateral acceleration a_q = V^2/R cos(phi) - g sin|phi| loads every
    mass (-m a_q along y). Returns {body: (y, psi)} [m, rad]."""
    kap = 1.0 / radius
    idx = {b.name: i for i, b in enumerate(bodies)}
    n = 2 * len(bodies)
    A = np.zeros((n, n))
    rhs = np.zeros(n)
    for i, b in enumerate(bodies):
        rhs[2 * i] += b.mass * a_q
        if b.wheelset:
            A[2 * i, 2 * i + 1] += 2 * f22
            A[2 * i + 1, 2 * i] += -2 * f11 * e0 * lam / r0
            rhs[2 * i + 1] += 2 * f11 * e0 * e0 * kap

    def disp(b: PlanarBody, X: float):
        """(coefficients of y, psi; constant) of the lateral displacement and of the yaw at X."""
        d = X - b.x
        return (1.0, d, -kap * d * d / 2), (0.0, 1.0, -kap * d)

    for s in springs:
        ib = idx[s.body_b]
        (ly_b, lp_b, lc_b), (_, yp_b, yc_b) = disp(bodies[ib], s.x)
        # relative lateral displacement delta = d_b - d_a, relative yaw theta = th_b - th_a;
        # 'ground' is body b's own track frame (conventions.md), fixed: d_a = th_a = 0
        dcoef = {(ib, 0): ly_b, (ib, 1): lp_b}
        tcoef = {(ib, 1): yp_b}
        dconst, tconst = lc_b, yc_b
        pairs = [(ib, -1.0)]
        if s.body_a != "ground":
            ia = idx[s.body_a]
            (ly_a, lp_a, lc_a), (_, yp_a, yc_a) = disp(bodies[ia], s.x)
            dcoef.update({(ia, 0): -ly_a, (ia, 1): -lp_a})
            tcoef[(ia, 1)] = -yp_a
            dconst -= lc_a
            tconst -= yc_a
            pairs.append((ia, 1.0))
        # body b: force -k delta, moment (X - x_b)(-k delta) - k_yaw theta; body a: opposite
        for body, sgn in pairs:
            lever = s.x - bodies[body].x
            for (j, c), v in dcoef.items():
                A[2 * body, 2 * j + c] += sgn * s.k_lat * v
                A[2 * body + 1, 2 * j + c] += sgn * s.k_lat * lever * v
            for (j, c), v in tcoef.items():
                A[2 * body + 1, 2 * j + c] += sgn * s.k_yaw * v
            rhs[2 * body] -= sgn * s.k_lat * dconst
            rhs[2 * body + 1] -= sgn * (s.k_lat * lever * dconst + s.k_yaw * tconst)
    u = np.linalg.solve(A, rhs)
    return {b.name: (float(u[2 * i]), float(u[2 * i + 1])) for i, b in enumerate(bodies)}


def tgv_planar_model(kind: str) -> tuple[list[PlanarBody], list[PlanarSpring]]:
    """The TGV 001 single wheelset on its primary springs to the track frame ('wheelset',
    inputs/tgv_wheelset.nml), bogie ('bogie', bogie centre at 0) or complete vehicle
    ('vehicle', car body centre at 0) for ``steady_curving`` / ``lateral_stability``, from
    TGV_BOGIE / TGV_VEHICLE."""
    p, q = TGV_BOGIE, TGV_VEHICLE
    if kind == "wheelset":
        return ([PlanarBody("ws1", 0.0, p["m_w"], wheelset=True)],
                [PlanarSpring("ground", "ws1", 0.0, 2 * p["ky"], 2 * p["kx"] * p["dp"] ** 2)])
    if kind not in ("bogie", "vehicle"):
        raise ValueError(f"tgv_planar_model: kind {kind!r}; expected 'wheelset', 'bogie' or 'vehicle'")
    vehicle = kind == "vehicle"
    centres = (q["pivot"], -q["pivot"]) if vehicle else (0.0,)
    bodies, springs = [], []
    k = 0
    for j, xc in enumerate(centres, start=1):
        bodies.append(PlanarBody(f"bogie{j}", xc, p["m_b"]))
        for dx in (p["l"], -p["l"]):
            k += 1
            bodies.append(PlanarBody(f"ws{k}", xc + dx, p["m_w"], wheelset=True))
            springs.append(PlanarSpring(f"bogie{j}", f"ws{k}", xc + dx, 2 * p["ky"], 2 * p["kx"] * p["dp"] ** 2))
        if vehicle:
            springs.append(PlanarSpring("car", f"bogie{j}", xc, 2 * q["ky_s"], 2 * q["kx_s"] * q["ds"] ** 2))
    if vehicle:
        bodies.append(PlanarBody("car", 0.0, q["m_c"]))
    return bodies, springs


#: Number of wheelsets of each planar model.
PLANAR_WHEELSETS = {"wheelset": 1, "bogie": 2, "vehicle": 4}

#: Yaw inertias [kg m2] of the TGV 001 bodies (tables 5.1, 5.8), for the linear stability model.
TGV_YAW_INERTIA = dict(wheelset=799.35, bogie=4063.712, car=2.43e6)
#: TGV secondary lateral damping per spring [N s/m] (table 5.6).
TGV_SECONDARY_CY = 3.5e4
#: Wheelset spin inertia Iyy [kg m2] (table 5.8) and the primary vertical stiffness kz [N/m] and
#: damping cz [N s/m] per spring (table 5.4) at +-dp: the roll restraint of the wheelsets by the
#: bogie frame in the knife-edge terms of ``lateral_stability``. The single-wheelset deck
#: (inputs/tgv_wheelset.nml) has no vertical springs.
TGV_WHEELSET_IYY = 93.75
TGV_PRIMARY_VERTICAL = dict(kz=9.75e5, cz=1.08e4)


@dataclass
class KnifeEdgeContact:
    """The straight-running contact state the knife-edge terms of ``lateral_stability`` need,
    per wheel: Kalker coefficients f11 = G a b C11, f22 = G a b C22 [N], f23 = G (ab)^1.5 C23
    [N m] (thesis eqs. 3.39-3.43) and the normal force N0 [N] of the centred wheelset."""
    f11: float
    f22: float
    f23: float = 0.0
    normal_force: float | None = None      #: None: the static wheel load of the model's masses


def _static_normal_force(kind: str) -> float:
    """Normal force [N] per wheel of a centred wheelset from the masses it carries (Q / cos d,
    spin forces' vertical share neglected): the wheelset, half a bogie frame and for the vehicle
    a quarter of the car body; the single-wheelset deck adds the vehicle's axle load."""
    p, q = TGV_BOGIE, TGV_VEHICLE
    if kind == "wheelset":
        w = p["m_w"] + (q["m_c"] + 2 * p["m_b"]) / 4
    else:
        w = p["m_w"] + p["m_b"] / 2 + (q["m_c"] / 4 if kind == "vehicle" else 0.0)
    return 0.5 * w * STANDARD_GRAVITY / math.cos(math.atan(p["lam"]))


def knife_edge_wheelset_terms(contact: KnifeEdgeContact, speed: float, roll_stiffness: float = 0.0,
                              roll_damping: float = 0.0, iyy: float = TGV_WHEELSET_IYY,
                              p: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Linear lateral force F and yaw moment M on one conical wheelset on knife-edge rails
    (wheels: cones of slope lam = tan d, rails: lines at +-e0), F = -(K q + C q'), q = (y, psi),
    as (K, C), each 2x2 (rows F, M). Derived to first order for rigid contacts (the Hertz
    approach, ~3e-5 m, is neglected against the geometry) and quasi-static roll, every term from
    the rigid-body kinematics of the cone and Kalker's linear law (thesis 3.6, 5.3.3):

    - roll follows the lateral shift: the left rail point lies on the cone at axial coordinate
      e0 - y - r0 phi, so sin(phi) ~ (r_L - r_R)/(2 e0) gives phi = s y, s = lam/(e0 - r0 lam),
      and the rolling radii r_L,R = r0 +- lam_e y with lam_e = lam e0/(e0 - r0 lam) (the
      classical cone model has phi = 0 and lam_e = lam; here +6% for the TGV);
    - longitudinal creepages -+(lam_e y/r0 + e0 psi'/V): yaw moment -2 f11 e0 (lam_e y/r0 + e0 psi'/V);
    - lateral creepage of the wheel's material point, (y' + r0 phi') cos d + e0 phi' sin d in the
      contact plane, minus psi (cos d + lam sin d) from the yawed spin (the contact point sits
      r0 lam psi ahead of the wheel's lowest point): eta = (kap y'/V - psi)/cos d, kap = e0/(e0 - r0 lam);
      on the track's Y axis the lateral creep forces give F_cr = -2 f22 (kap y'/V - psi);
    - load transfer: the roll balance of the wheelset, ell (N_L - N_R) + m_c (Fy_L + Fy_R) +
      M_0 = -Iyy Omega psi' (gyroscopic, Omega = V/r0), with ell = e0 cos d - r0 sin d the lever
      of a normal force and m_c = e0 sin d + r0 cos d that of a lateral creep force (contact
      frame) about the centre of mass, and M_0 = -2 N0 (cos d + m_c s) y - k_roll s y - c_roll s y'
      the moment of the unchanged normal forces moved by y and phi and of the primary vertical
      springs (bogie frame roll neglected). N_L - N_R acts laterally through the inclined
      normals (-sin d each) and through the spin force of the cone, Fs = f23 sin(d)/r0 per wheel
      (outwards), which grows with the load (f23 ~ (ab)^1.5 ~ N): g = Fs/N0 - sin d per newton;
    - the normal forces turned by the roll: -2 N0 cos(d) s y;
    - spin creepages (omega . n / V_ref, thesis 3.6.1.3) sum to (sin d/r0)(lam_e y/r0 + e0 psi'/V)
      + 2 psi' cos(d)/V over the two wheels (lateral force -f23 cos d times that) and give the spin
      moments 2 f23 (kap y'/V - psi); the yaw-rate gyroscopic moment is -Iyy Omega s y'.

    f33 terms (~1e-5 of the others) are left out. With f23 = 0 and N0 = 0 (and the kinematic
    factors set to 1) this is the classical model of Wickens / Iwnicki's handbook ch. 7."""
    p = p or TGV_BOGIE
    e0, r0, lam = p["e0"], p["r0"], p["lam"]
    d = math.atan(lam)
    sd, cd = math.sin(d), math.cos(d)
    f11, f22, f23 = contact.f11, contact.f22, contact.f23
    n0 = contact.normal_force or 0.0
    s = lam / (e0 - r0 * lam)
    lam_e = lam * e0 / (e0 - r0 * lam)
    kap = e0 / (e0 - r0 * lam)
    ell = e0 * cd - r0 * sd
    m_c = e0 * sd + r0 * cd
    g = (f23 * sd / r0 / n0 if n0 > 0 else 0.0) - sd
    omega = speed / r0
    Fq, Fv = np.zeros((2, 2)), np.zeros((2, 2))          # F = Fq q + Fv q'
    cr_q, cr_v = np.array([0.0, 2 * f22]), np.array([-2 * f22 * kap / speed, 0.0])
    Fq[0] += cr_q
    Fv[0] += cr_v
    # load transfer N_L - N_R = dq q + dv q' and its lateral force g (N_L - N_R)
    dq = (-m_c * cr_q / cd + np.array([2 * n0 * (cd + m_c * s) + roll_stiffness * s, 0.0])) / ell
    dv = (-m_c * cr_v / cd + np.array([roll_damping * s, -iyy * omega])) / ell
    Fq[0] += g * dq
    Fv[0] += g * dv
    Fq[0, 0] += -2 * n0 * cd * s
    # spin creep: lateral forces and spin moments
    Fq[0, 0] += -cd * f23 * sd / r0 * lam_e / r0
    Fv[0, 1] += -cd * f23 * (sd / r0 * e0 / speed + 2 * cd / speed)
    Fv[1, 0] += 2 * f23 * kap / speed
    Fq[1, 1] += -2 * f23
    # longitudinal creep and gyroscopic yaw moment
    Fq[1, 0] += -2 * f11 * e0 * lam_e / r0
    Fv[1, 1] += -2 * f11 * e0 ** 2 / speed
    Fv[1, 0] += -iyy * omega * s
    return -Fq, -Fv


def lateral_stability(kind: str, f11: float | KnifeEdgeContact, f22: float | None = None,
                      speed: float = 0.0) -> complex:
    """Least-damped eigenvalue [1/s] of the linear lateral/yaw dynamics of the TGV wheelset,
    bogie or vehicle on straight track, with the bodies and springs of ``tgv_planar_model``:
    body masses and yaw inertias, springs between attachment points (lateral k at lever
    X - x_b, yaw k), secondary lateral dampers, and per wheelset the knife-edge contact of
    ``knife_edge_wheelset_terms`` (Wickens 1965 / Iwnicki's handbook ch. 7 extended by the
    knife-edge roll kinematics, load transfer, spin creep and gyroscopic terms, which shift the
    growth rate of the TGV bogie by more than its size: docs/validation.md). ``f11`` is either
    a KnifeEdgeContact or f11 [N] with ``f22`` [N] (then f23 = 0 and the static wheel load).
    Real part > 0: the motion grows (hunting)."""
    if isinstance(f11, KnifeEdgeContact):
        contact = f11
    elif f22 is None:
        raise ValueError("lateral_stability: f22 missing; expected f11, f22 [N] or a KnifeEdgeContact")
    else:
        contact = KnifeEdgeContact(float(f11), float(f22))
    if contact.normal_force is None:
        contact = KnifeEdgeContact(contact.f11, contact.f22, contact.f23, _static_normal_force(kind))
    if not speed > 0:
        raise ValueError(f"lateral_stability: speed {speed!r} m/s; expected > 0")
    p = TGV_BOGIE
    roll_k = roll_c = 0.0
    if kind != "wheelset":        # wheelset deck: ground springs without kz (its header)
        roll_k = 2 * TGV_PRIMARY_VERTICAL["kz"] * p["dp"] ** 2
        roll_c = 2 * TGV_PRIMARY_VERTICAL["cz"] * p["dp"] ** 2
    kw, cw = knife_edge_wheelset_terms(contact, speed, roll_k, roll_c)
    bodies, springs = tgv_planar_model(kind)
    n = 2 * len(bodies)
    M, C, K = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    idx = {b.name: i for i, b in enumerate(bodies)}
    for i, b in enumerate(bodies):
        M[2 * i, 2 * i] = b.mass
        kind_b = "wheelset" if b.wheelset else ("car" if b.name == "car" else "bogie")
        M[2 * i + 1, 2 * i + 1] = TGV_YAW_INERTIA[kind_b]
        if b.wheelset:
            K[2 * i:2 * i + 2, 2 * i:2 * i + 2] += kw
            C[2 * i:2 * i + 2, 2 * i:2 * i + 2] += cw
    for s in springs:
        ib = idx[s.body_b]
        d = np.zeros(n)      # relative lateral displacement at the attachment: d . q
        d[2 * ib], d[2 * ib + 1] = 1.0, s.x - bodies[ib].x
        r = np.zeros(n)      # relative yaw
        r[2 * ib + 1] = 1.0
        if s.body_a != "ground":          # ground: body b's track frame, fixed
            ia = idx[s.body_a]
            d[2 * ia], d[2 * ia + 1] = -1.0, -(s.x - bodies[ia].x)
            r[2 * ia + 1] = -1.0
        K += s.k_lat * np.outer(d, d) + s.k_yaw * np.outer(r, r)
        if s.body_a == "car":
            C += 2 * TGV_SECONDARY_CY * np.outer(d, d)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    ev = np.linalg.eigvals(A)
    return complex(ev[int(np.argmax(ev.real))])


def linear_critical_speed(kind: str, f11: float | KnifeEdgeContact, f22: float | None = None, lo: float = 1.0,
                          hi: float = 300.0) -> float:
    """Lowest speed [m/s] at which ``lateral_stability`` turns unstable (scan, then bisection
    to 0.01 m/s); inf if stable up to ``hi``. Arguments as ``lateral_stability``."""
    grid = np.linspace(lo, hi, 300)
    unstable = [v for v in grid if lateral_stability(kind, f11, f22, v).real > 0]
    if not unstable:
        return math.inf
    b = unstable[0]
    a = grid[max(int(np.searchsorted(grid, b)) - 1, 0)]
    if lateral_stability(kind, f11, f22, a).real > 0:
        return float(a)
    while b - a > 0.01:
        m = 0.5 * (a + b)
        if lateral_stability(kind, f11, f22, m).real > 0:
            b = m
        else:
            a = m
    return 0.5 * (a + b)


def steady_curving_bogie(f11: float, f22: float, radius: float, a_q: float, p: dict | None = None) -> dict:
    """``steady_curving`` of the TGV bogie (or the bogie data ``p``): y1, psi1, y2, psi2, yb, psib."""
    saved = dict(TGV_BOGIE)
    try:
        if p is not None:
            TGV_BOGIE.update(p)
        bodies, springs = tgv_planar_model("bogie")
        s = steady_curving(bodies, springs, f11, f22, radius, a_q, TGV_BOGIE["r0"], TGV_BOGIE["e0"],
                           TGV_BOGIE["lam"])
    finally:
        TGV_BOGIE.clear()
        TGV_BOGIE.update(saved)
    return dict(y1=s["ws1"][0], psi1=s["ws1"][1], y2=s["ws2"][0], psi2=s["ws2"][1],
                yb=s["bogie1"][0], psib=s["bogie1"][1])


def _identify_creep_coefficients(ctx: Context, row: dict, wheelsets: Sequence[str]) -> tuple[float, float]:
    """f11, f22 [N] of the run's own contacts in the window, least squares over the wheelsets:
    f11 from the difference right - left of Fx against that of xi, f22 from the sum left + right
    of Fy against that of eta (the spin contributions of a cone's two wheels cancel in the sum)."""
    dfx, dxi, sfy, seta = [], [], [], []
    for w in wheelsets:
        c = {}
        for side in ("left", "right"):
            base = f"wheelsets/{w}/{side}/contact1"
            _, cr = _window(ctx, row, f"{base}/creepage:xi")
            _, et = _window(ctx, row, f"{base}/creepage:eta")
            _, fx = _window(ctx, row, f"{base}/creep_force_contact:fx")
            _, fy = _window(ctx, row, f"{base}/creep_force_contact:fy")
            c[side] = [float(np.mean(v)) for v in (cr, et, fx, fy)]
        dxi.append(c["right"][0] - c["left"][0])
        dfx.append(c["right"][2] - c["left"][2])
        seta.append(c["right"][1] + c["left"][1])
        sfy.append(c["right"][3] + c["left"][3])
    dxi, dfx, seta, sfy = map(np.array, (dxi, dfx, seta, sfy))
    if not (np.dot(dxi, dxi) > 0 and np.dot(seta, seta) > 0):
        raise CaseError("zero creepages in the window: cannot identify the creep coefficients")
    return float(-np.dot(dfx, dxi) / np.dot(dxi, dxi)), float(-np.dot(sfy, seta) / np.dot(seta, seta))


#: Gravity of the decks (&simulation gravity default = rd_kinds standard_gravity) [m/s^2].
STANDARD_GRAVITY = 9.80665

#: Designed track curve (inputs/tracks/tgv_designed_track.nml): radius, cant, cant base.
TGV_CURVE = dict(radius=1000.0, cant=0.050, cant_base=1.5)


def identify_knife_edge_contact(ctx: Context, wheelsets: Sequence[str], t_from: float,
                                results: Results | None = None) -> KnifeEdgeContact:
    """The run's own contact state for ``lateral_stability``, from the samples after t_from of
    every wheel of the wheelsets: Kalker's linear law (thesis eqs. 3.39-3.43) scales with the
    contact ellipse as Fx = -k11 (ab) xi, Fy = -k22 (ab) eta - k23 (ab)^1.5 phi, so k11 is fitted
    to Fx and k22, k23 together to Fy by least squares over all samples of all wheels (the ellipse
    of each sample from the outputs), and f11 = k11 ab0, f22 = k22 ab0, f23 = k23 ab0^1.5 at the
    mean ab0; N0 is the mean normal force. Fitting per wheel with the ellipse keeps the load
    transfer out of the coefficients: a fit of the wheel sums Fy_L + Fy_R against eta and phi
    alone takes the spin force that moves with the load (f23 ~ N) for part of f22 (-7% on the
    TGV bogie, docs/validation.md)."""
    t = ctx.time(results)
    m = t >= t_from
    cols = {k: [] for k in ("xi", "eta", "phi", "fx", "fy", "ab", "n")}
    for w in wheelsets:
        for side in ("left", "right"):
            base = f"wheelsets/{w}/{side}/contact1"
            for k, ch in (("xi", "creepage:xi"), ("eta", "creepage:eta"), ("phi", "creepage:phi"),
                          ("fx", "creep_force_contact:fx"), ("fy", "creep_force_contact:fy"),
                          ("n", "normal_force:N")):
                cols[k].append(ctx.get(f"{base}/{ch}", results)[m])
            cols["ab"].append(ctx.get(f"{base}/ellipse:a", results)[m] * ctx.get(f"{base}/ellipse:b", results)[m])
    xi, eta, phi, fx, fy, ab, n = (np.concatenate(cols[k]) for k in ("xi", "eta", "phi", "fx", "fy", "ab", "n"))
    if not (ab.size and np.all(ab > 0)):
        raise CaseError("no loaded contact ellipse in the samples: cannot identify the creep coefficients")
    ab0 = float(np.mean(ab))
    u = ab / ab0 * xi
    v = ab / ab0 * eta
    w = (ab / ab0) ** 1.5 * phi
    if not (np.dot(u, u) > 0 and np.dot(v, v) > 0):
        raise CaseError("zero creepages: cannot identify the creep coefficients")
    f11 = float(-np.dot(fx, u) / np.dot(u, u))
    # scale the columns so that lstsq's rank decision is unit-free
    nv, nw = np.linalg.norm(v), max(np.linalg.norm(w), 1e-300)
    coef = np.linalg.lstsq(np.column_stack([v / nv, w / nw]), -fy, rcond=1e-9)[0]
    return KnifeEdgeContact(f11, float(coef[0] / nv), float(coef[1] / nw), float(np.mean(n)))


def _contact_text(c: KnifeEdgeContact) -> str:
    return (f"f11 = {c.f11:.4g} N, f22 = {c.f22:.4g} N, f23 = {c.f23:.4g} N m, "
            f"N0 = {c.normal_force:.4g} N")


def _kind_linear_stability(ctx, row, what: str):
    """what = 'rate' (growth rate vs the model's least-damped eigenvalue) or 'wavelength'."""
    kind = row["channel"]
    nws = PLANAR_WHEELSETS[kind]
    t0 = float(row["t_from"])
    contact = identify_knife_edge_contact(ctx, [f"w{k}" for k in range(1, nws + 1)], t0)
    V = ctx.speed()
    ev = lateral_stability(kind, contact, speed=V)
    t, y = _window(ctx, row, "bodies/ws1/position_track:y")
    thr = float(row["threshold"])
    info = f"linear model with the run's own {_contact_text(contact)} at {V:g} m/s"
    if what == "rate":
        rate, npk = growth_rate(t, y)
        allowed = thr * abs(ev.real) + 0.1
        ctx.check(row["id"], abs(rate - ev.real) <= allowed, rate, f"{ev.real:.4g} +- {allowed:.2g}", "1/s",
                  f"{info}; {npk} peaks; {row['justification']}")
    else:
        lam_model = V * 2 * math.pi / abs(ev.imag)
        lam = oscillation_wavelength(t, y, V)
        allowed = thr * lam_model
        ctx.check(row["id"], abs(lam - lam_model) <= allowed, lam, f"{lam_model:.4g} +- {allowed:.2g}", "m",
                  f"{info}; {row['justification']}")


def _kind_linear_curving(ctx, row):
    kind = row["channel"]
    nws = PLANAR_WHEELSETS[kind]
    f11, f22 = _identify_creep_coefficients(ctx, row, [f"w{k}" for k in range(1, nws + 1)])
    V = ctx.speed()
    phi = math.asin(TGV_CURVE["cant"] / TGV_CURVE["cant_base"])
    a_q = V ** 2 / TGV_CURVE["radius"] * math.cos(phi) - STANDARD_GRAVITY * math.sin(phi)
    bodies, springs = tgv_planar_model(kind)
    model = steady_curving(bodies, springs, f11, f22, TGV_CURVE["radius"], a_q, TGV_BOGIE["r0"],
                           TGV_BOGIE["e0"], TGV_BOGIE["lam"])
    thr = float(row["threshold"])
    ws = [f"ws{k}" for k in range(1, nws + 1)]
    scale_y = max(abs(model[w][0]) for w in ws)
    scale_p = max(abs(model[w][1]) for w in ws)
    for w in ws:
        for comp, col, scale, floor, unit in (("y", 0, scale_y, 5e-5, "m"), ("yaw", 1, scale_p, 2e-5, "rad")):
            _, v = _window(ctx, row, f"bodies/{w}/position_track:{comp}")
            got, ref = float(np.mean(v)), model[w][col]
            allowed = thr * scale + floor
            ctx.check(f"{row['id']}:{w} {comp}", abs(got - ref) <= allowed, got, f"{ref:.4g} +- {allowed:.2g}",
                      unit, f"linear steady-curving model with the run's own f11 = {f11:.4g} N, "
                      f"f22 = {f22:.4g} N, a_q = {a_q:.4g} m/s^2; {row['justification']}")


CHECK_KINDS: dict[str, Callable] = {
    "linear_steady_curving": _kind_linear_curving,
    "linear_growth_rate": lambda c, r: _kind_linear_stability(c, r, "rate"),
    "linear_wavelength": lambda c, r: _kind_linear_stability(c, r, "wavelength"),
    "linear_critical_speed": lambda c, r: _kind_linear_critical_speed(c, r),
    "growth_rate_below": lambda c, r: _kind_growth(c, r, False),
    "growth_rate_above": lambda c, r: _kind_growth(c, r, True),
    "amplitude_below": lambda c, r: _kind_amplitude(c, r, False),
    "amplitude_above": lambda c, r: _kind_amplitude(c, r, True),
    "relative_amplitude_below": lambda c, r: _kind_relative_amplitude(c, r, False),
    "relative_amplitude_above": lambda c, r: _kind_relative_amplitude(c, r, True),
    "wavelength_above": lambda c, r: _kind_wavelength(c, r, True),
    "wavelength_below": lambda c, r: _kind_wavelength(c, r, False),
    "outward_above": lambda c, r: _kind_outward(c, r, True),
    "outward_below": lambda c, r: _kind_outward(c, r, False),
    "outward_less_than": _kind_outward_less,
    "steadiness_below": _kind_steadiness,
    "same_mean": _kind_same_mean,
    "flange_contact_above": _kind_flange_contact,
    "case_difference_below": lambda c, r: _kind_case_difference(c, r, False),
    "case_force_difference_below": lambda c, r: _kind_case_difference(c, r, True),
    "critical_speed_above": lambda c, r: _kind_critical_speed(c, r, True),
    "critical_speed_below": lambda c, r: _kind_critical_speed(c, r, False),
}


#: Critical-speed search (case tgv_bogie_critical_speed: the 40 m/s bogie deck, whose small
#: disturbance keeps unstable runs short of large amplitudes, at other speeds).
CRITICAL_SPEED_BRACKET = (20.0, 40.0)
CRITICAL_SPEED_RESOLUTION = 1.0
CRITICAL_SPEED_T_END = 8.0


def _kind_linear_critical_speed(ctx, row):
    if "critical_speed" not in ctx.cache:
        ctx.cache["critical_speed"] = critical_speed_bisection(ctx, row)
    vc = ctx.cache["critical_speed"]
    if "creep_coefficients" not in ctx.cache:
        raise CaseError("no probe run to identify the creep coefficients from")
    contact = ctx.cache["creep_coefficients"]
    vc_model = linear_critical_speed("bogie", contact)
    thr = float(row["threshold"])
    allowed = thr * vc_model
    ctx.check(row["id"], abs(vc - vc_model) <= allowed + CRITICAL_SPEED_RESOLUTION / 2, vc,
              f"{vc_model:.4g} +- {allowed + CRITICAL_SPEED_RESOLUTION / 2:.2g}", "m/s",
              f"linear model with {_contact_text(contact)} identified from the "
              f"{ctx.cache['creep_coefficients_speed']:g} m/s probe; {row['justification']}")


def critical_speed_bisection(ctx: Context, row: dict) -> float:
    """The product's bisection (raildyn.stability, ``raildyn critical-speed --method
    bisection``) on the sign of the growth rate of wheelset 1's lateral motion between the
    bracket speeds; returns the midpoint of the final bracket (a bracket end when the sign
    does not change). Each probe is a variant run of the case (reused with --reuse), checked
    for wheel forces, and the fastest one identifies the creep coefficients."""
    lo, hi = CRITICAL_SPEED_BRACKET
    rows = []

    def probe(v: float) -> dict:
        res = ctx.run_variant(f"v{v:.3f}", f"&simulation speed = {v:.6g}, t_end = {CRITICAL_SPEED_T_END:g} /")
        with res:
            missing = [w for w in deck_wheelsets(ctx.case.deck_path)
                       if not ctx.has(f"wheelsets/{w}/left/force_track:fy", res)]
            if missing:
                raise CaseError(f"speed {v:g} m/s: no wheel forces of {', '.join(missing)}: the scene "
                                "ran without wheel-rail contact (contact not wired)")
            t = ctx.time(res)
            y = ctx.get(row["channel"], res)
            m = window_mask(t, float(row["t_from"]), float(row["t_to"]))
            rate, npk = growth_rate(t[m], y[m])
            best = ctx.cache.get("creep_coefficients_speed", -1.0)
            if v > best:      # identified at the fastest probe (largest creepages of the runs)
                ctx.cache["creep_coefficients"] = identify_knife_edge_contact(ctx, ["w1", "w2"], float(row["t_from"]),
                                                                              res)
                ctx.cache["creep_coefficients_speed"] = v
        rows.append([f"{v:.3f}", f"{rate:.4g}", npk, "growth" if rate > 0 else "decay"])
        return {"speed": v, "growth_rate": rate, "peaks": npk}

    # resolution: the half-width, so that the final bracket is CRITICAL_SPEED_RESOLUTION wide
    answer = bisection_critical_speed(ctx.case.deck_path, lo, hi, CRITICAL_SPEED_RESOLUTION / 2, row["channel"],
                                      float(row["t_from"]), float(row["t_to"]), ctx.out_dir, ctx.exe, jobs=1,
                                      probe=probe)
    a, b = answer.bracket
    if answer.critical_speed is None:
        ctx.result.tables.append(Table("Critical speed search", ["speed m/s", "growth rate 1/s", "peaks", ""], rows))
        return a
    vc = answer.critical_speed
    ctx.result.tables.append(Table(f"Critical speed search: {vc:.2f} m/s (bracket {a:.2f}-{b:.2f} m/s)",
                                   ["speed m/s", "growth rate 1/s", "peaks", ""], rows))
    return vc


def evaluate_tgv(ctx: Context) -> None:
    rows = [r for r in load_tgv_checks() if r["case"] == ctx.case.name]
    if not rows:
        raise CaseError(f"validation/tgv_checks.csv has no check for case {ctx.case.name}")
    for row in rows:
        kind = CHECK_KINDS.get(row["kind"])
        if kind is None:
            raise CaseError(f"tgv_checks.csv: unknown kind {row['kind']!r} (check {row['id']})")
        try:
            kind(ctx, row)
        except (CaseError, StabilityError) as exc:
            ctx.check(row["id"], False, None, "", "", f"not evaluated: {exc}")
    if not ctx.case.run:
        return
    t = ctx.time()
    nws = sum(1 for k in range(1, 5) if ctx.has(f"bodies/ws{k}/position_track:y"))
    if nws:
        ctx.plot("Lateral displacement of the wheelsets", [(f"ws{k}", t, ctx.get(f"bodies/ws{k}/position_track:y"))
                                                          for k in range(1, nws + 1)], "y [mm]", 1e3)
        ctx.plot("Yaw angle of the wheelsets", [(f"ws{k}", t, ctx.get(f"bodies/ws{k}/position_track:yaw"))
                                                for k in range(1, nws + 1)], "yaw [mrad]", 1e3)
    if ctx.has("wheelsets/w1/left/force_track:fy"):
        ctx.plot("Lateral wheel forces of wheelset 1", [(f"w1 {s}", t, ctx.get(f"wheelsets/w1/{s}/force_track:fy"))
                                                        for s in ("left", "right")], "force [kN]", 1e-3)


def evaluate_manchester_quiet(ctx: Context) -> None:
    """The Manchester rule, plus the quiet state the acceptance deck must reach: no wheel without
    contact in any sample (no run note) and, in the window, every wheel's vertical force with a
    standard deviation of at most 1 kN (issue 12)."""
    evaluate_manchester(ctx)
    check_manchester_quiet(ctx)


def check_manchester_quiet(ctx: Context) -> None:
    """The quiet state alone (a variant of the acceptance deck whose data differ from the
    benchmark's, e.g. another friction coefficient, so that the packages' tables do not apply)."""
    t = ctx.time()
    w0, w1 = manchester_window(ctx)
    m = window_mask(t, w0, w1)
    worst = max(float(np.std(ctx.get(f"wheelsets/w{k}/{side}/force_track:fz")[m]))
                for k in range(1, 5) for side in ("left", "right"))
    ctx.check("largest standard deviation of a wheel's vertical force in the window", worst <= 1.0e3,
              worst / 1e3, "<= 1 kN", "kN")
    lost = [n for n in ctx.result.notes if n.startswith("run: ") and "without contact" in n]
    ctx.check("no wheel without contact in any sample (run notes)", not lost, len(lost), "0 notes", "notes",
              "; ".join(lost))


_TGV_BASE = ("bodies/ws1/position_track:y", "bodies/ws1/position_track:yaw", "bodies/ws2/position_track:y")

CASES: dict[str, Case] = {c.name: c for c in [
    Case("manchester_v1_tc1", "manchester_v1_tc1.nml", "Manchester Benchmark Vehicle 1, Track Case 1",
         "Quasi-static curving in R 150 m with 100 mm cant at 4.4 m/s: wheelset lateral shift and yaw, "
         "wheel forces against the five packages of thesis tables 5.9-5.11, and quiet (no contact "
         "loss, wheel loads steady within 1 kN in the window; issue 12).", evaluate_manchester_quiet,
         baseline_channels=("bodies/ws1/position_track:y", "bodies/ws1/position_track:yaw",
                            "wheelsets/w1/left/force_track:fy", "wheelsets/w1/left/force_track:fz")),
    Case("manchester_v1_tc1_tables", "manchester_v1_tc1_tables.nml",
         "Manchester Benchmark Vehicle 1, Track Case 1, contact tables",
         "The acceptance scene with its profile contact evaluated from pre-computed tables of the strip "
         "model (docs/theory_contact_geometry.md section 10): the same rule.", evaluate_manchester,
         baseline_channels=("bodies/ws1/position_track:y", "bodies/ws1/position_track:yaw",
                            "wheelsets/w1/left/force_track:fy", "wheelsets/w1/left/force_track:fz")),
    Case("tgv_wheelset", "tgv_wheelset.nml", "TGV 001 single wheelset, straight, 20 m/s",
         "Knife-edge wheelset on primary springs to the track frame: the 1 mm disturbance decays.",
         evaluate_tgv, baseline_channels=_TGV_BASE[:2]),
    Case("tgv_bogie_straight_20", "tgv_bogie_straight_20.nml", "TGV 001 bogie, straight, 20 m/s",
         "Thesis 5.3.4.1, figs. 5.16-5.17: stable, the 1 mm offset decays.", evaluate_tgv,
         baseline_channels=_TGV_BASE),
    Case("tgv_bogie_straight_40", "tgv_bogie_straight_40.nml", "TGV 001 bogie, straight, 40 m/s",
         "Thesis fig. 5.18: hunting grows; wavelength between the wheelset and rigid-bogie Klingel values.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_bogie_critical_speed", "tgv_bogie_straight_40.nml", "TGV 001 bogie, critical speed",
         "Bisection between 20 and 40 m/s on decay vs growth after a lateral pulse (8 s runs of the 40 m/s deck).",
         evaluate_tgv, run=False),
    Case("tgv_bogie_curve", "tgv_bogie_curve.nml", "TGV 001 bogie, transition into R 1000 m, 20 m/s",
         "Thesis 5.3.4.2, figs. 5.20-5.22: wheelsets move outward, the trailing one less; settle in the curve.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_vehicle_straight", "tgv_vehicle_straight.nml", "TGV 001 vehicle (42 DOF), straight, 20 m/s",
         "Thesis 5.3.4.3: the complete vehicle is stable.", evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_vehicle_curve", "tgv_vehicle_curve.nml", "TGV 001 vehicle (42 DOF), transition into R 1000 m",
         "Thesis 5.3.4.4, figs. 5.24-5.27: wheelsets 1/3 and 2/4 alike, trailing wheelsets shifted less.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_profile_fastsim", "tgv_profile_fastsim.nml", "TGV 001 vehicle, S1002/UIC60, FASTSIM, 25.6 m/s",
         "Thesis 5.5, figs. 5.52-5.64: flange-limited lateral shift of the leading wheelsets.",
         evaluate_tgv, baseline_channels=_TGV_BASE),
    Case("tgv_profile_polach", "tgv_profile_polach.nml", "TGV 001 vehicle, S1002/UIC60, Polach, 25.6 m/s",
         "Thesis 5.6, figs. 5.65-5.70: Polach close to FASTSIM, both without spin creepage as in the "
         "thesis; the FASTSIM reference is this deck rerun with creep_law = 'fastsim'.", evaluate_tgv,
         baseline_channels=_TGV_BASE),
]}


# ------------------------------------------------------------------------------------------
# case execution


_WHEELSET_NAME = re.compile(r"&wheelset\s+name\s*=\s*(['\"])(.*?)\1", re.IGNORECASE)


def deck_wheelsets(deck: str | os.PathLike) -> list[str]:
    """Names of the &wheelset groups of a deck and its includes (an override repeats a name)."""
    names: list[str] = []
    for p in deck_files(deck):
        for line in p.read_text().splitlines():
            for m in _WHEELSET_NAME.finditer(line.split("!", 1)[0]):
                if m.group(2) not in names:
                    names.append(m.group(2))
    return names


def _check_contact_outputs(ctx: Context) -> None:
    """Every wheelset of the deck must have written its wheel forces: a scene that runs the
    bodies without wheel-rail contact must not pass a validation case by accident."""
    missing = [w for w in deck_wheelsets(ctx.case.deck_path)
               if not ctx.has(f"wheelsets/{w}/left/force_track:fy")]
    ctx.check("wheel-rail contact outputs present", not missing, None, "all wheelsets", "",
              "" if not missing else "no wheelsets/<name>/left/force_track for " + ", ".join(missing) +
              ": the scene ran without wheel-rail contact for these wheelsets (contact not wired)")


def _attach_band_checks(ctx: Context) -> None:
    """Reference curves (validation/curves/<case>/*.csv) and the frozen baseline."""
    files = sorted((BANDS / "curves" / ctx.case.name).glob("*.csv"))
    base = BANDS / "baselines" / f"{ctx.case.name}.csv"
    sources = [("reference curve", f) for f in files] + ([("baseline", base)] if base.exists() else [])
    t = ctx.time()
    for kind, f in sources:
        for ch, (tr, v, lo, hi) in read_band_csv(f).items():
            try:
                y = ctx.get(ch)
            except CaseError as exc:
                ctx.check(f"{kind} {f.name}: {ch}", False, None, "", "", str(exc))
                continue
            ok, worst, tw, n = compare_band_curve(t, y, tr, lo, hi)
            ctx.check(f"{kind} {f.name}: {ch}", ok, worst, "0 (inside the band)", "",
                      f"largest excursion outside the band at t = {tw:.3f} s over {n} points")
            ctx.plot(f"{ch} against {kind} {f.name}", [("raildyn", t, y)], ch, 1.0,
                     bands=[(kind, tr, lo, hi)])


def run_case(name: str, out_dir: str | os.PathLike, exe: str | os.PathLike | None = None,
             reuse: bool = False, others: dict[str, Path] | None = None,
             given: str | os.PathLike | None = None) -> CaseResult:
    """Run (or reuse) one case and evaluate it. Never raises for physics or run problems:
    they are reported in the CaseResult (``error`` and failed checks).
    ``given``: evaluate this results file instead of running the case's deck (e.g. one run of
    a campaign that varies the deck); the report says so."""
    case = CASES[name]
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = CaseResult(name, case.title, case.description, f"inputs/{case.deck}")
    try:
        res.assumptions = deck_assumptions(case.deck_path)
        res.deck_sha256 = deck_sha256(case.deck_path)
    except OSError as exc:
        res.error = f"deck {case.deck_path}: {exc}"
        return res
    others = dict(others or {})
    results_path = out_dir / f"{name}.h5"
    try:
        for dep in case.needs:
            p = others.get(dep) or out_dir / f"{dep}.h5"
            if not p.exists():
                run_deck(CASES[dep].deck_path, p, exe)
            others[dep] = p
        r = None
        if case.run and given is not None:
            given = Path(given)
            if not given.is_file():
                raise CaseError(f"results file {given} given for case {name} (--results) does not exist")
            info = RunInfo(given, 0, 0.0, "", reused=True)
            res.results_path = os.fspath(given)
            res.notes.append(f"results taken from {given} (--results), not run from the case deck "
                             f"inputs/{case.deck}: the assumptions listed are that deck's")
            r = Results(given)
        elif case.run:
            info = run_deck(case.deck_path, results_path, exe, reuse=reuse)
            res.results_path = os.fspath(info.results)
            res.run_wall_time = None if info.reused else info.wall_time
            r = Results(info.results)
        try:
            if r is not None:
                meta = r.metadata
                res.status = str(meta.get("status"))
                res.raildyn_version = str(meta.get("raildyn_version") or "")
                if info.reused:
                    wt = meta.get("wall_time")
                    res.run_wall_time = float(wt) if wt is not None else None
                    if given is None:
                        res.notes.append("results reused from an earlier run (--reuse)")
                if res.status != "completed":
                    res.notes.append(f"run status: {res.status}")
                res.notes.extend(f"run: {n}" for n in run_notes(meta))
                if meta.get("solver"):
                    res.notes.append("solver statistics: " + ", ".join(
                        f"{k} = {v:.4g}" if isinstance(v, float) else f"{k} = {v}"
                        for k, v in sorted(meta["solver"].items())))
            else:
                res.status = "variants only"
            ctx = Context(case, res, r, out_dir, exe, reuse, others)
            try:
                if r is not None:
                    _check_contact_outputs(ctx)
                case.evaluate(ctx)
                if r is not None:
                    _attach_band_checks(ctx)
            finally:
                ctx.close()
        finally:
            if r is not None:
                r.close()
    except (CaseError, StabilityError) as exc:
        res.error = str(exc)
    except (KeyError, ValueError, OSError) as exc:
        res.error = f"{type(exc).__name__}: {exc}"
    return res


def run_cases(names: Sequence[str], out_dir: str | os.PathLike, exe: str | os.PathLike | None = None,
              reuse: bool = False, given: dict[str, Path] | None = None) -> list[CaseResult]:
    """Run and evaluate the cases (dependencies first). ``given``: case name -> results file
    to evaluate instead of running that case's deck."""
    out_dir = Path(out_dir)
    given = dict(given or {})
    done: dict[str, Path] = {}
    results = []
    # dependencies first
    order = []
    for n in names:
        for d in CASES[n].needs:
            if d not in order:
                order.append(d)
        if n not in order:
            order.append(n)
    for n in order:
        r = run_case(n, out_dir, exe, reuse, done, given.get(n))
        if r.results_path:
            done[n] = Path(r.results_path)
        if n in names:
            results.append(r)
    return results


def _git_commit() -> str:
    try:
        return subprocess.run(["git", "-C", os.fspath(REPO), "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


# ------------------------------------------------------------------------------------------
# command line


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "list":
        for c in CASES.values():
            print(f"{c.name:28s} inputs/{c.deck:28s} {c.title}")
        return 0
    if argv and argv[0] == "freeze":
        p = argparse.ArgumentParser(prog="python -m raildyn.validation freeze",
                                    description="Freeze an approved run of a case as a regression baseline.")
        p.add_argument("case", choices=sorted(CASES))
        p.add_argument("--out", default="validation-out", help="directory of the case results (default %(default)s)")
        p.add_argument("--results", help="results file (default OUT/CASE.h5)")
        p.add_argument("--channels", nargs="+", help="'series:component' columns (default: the case's list)")
        p.add_argument("--rel", type=float, default=0.02, help="band half-width, fraction of the channel range")
        p.add_argument("--abs", type=float, default=1e-6, dest="abs_tol", help="band half-width added [SI]")
        p.add_argument("--every", type=int, default=1, help="keep every n-th output row")
        a = p.parse_args(argv[1:])
        src = Path(a.results or Path(a.out) / f"{a.case}.h5")
        if not src.exists():
            print(f"freeze: no results {src}; run the case first", file=sys.stderr)
            return 1
        chans = a.channels or list(CASES[a.case].baseline_channels)
        if not chans:
            print("freeze: no channels given and the case has no default list", file=sys.stderr)
            return 1
        path = freeze_baseline(a.case, src, chans, rel=a.rel, abs_tol=a.abs_tol, every=a.every)
        print(f"wrote {path}")
        return 0
    if argv and argv[0] == "run":
        argv = argv[1:]
    p = argparse.ArgumentParser(prog="python -m raildyn.validation",
                                description="Run the validation cases and write the HTML report.")
    p.add_argument("--cases", nargs="+", choices=sorted(CASES), help="cases to run (default: all)")
    p.add_argument("--reuse", action="store_true", help="reuse existing results files in OUT")
    p.add_argument("--out", default="validation-out", help="output directory (default %(default)s)")
    p.add_argument("--exe", help="raildyn executable (default: $RAILDYN_BUILD_DIR/bin/raildyn or build/bin/raildyn)")
    p.add_argument("--report", help="HTML report path (default OUT/validation_report.html)")
    p.add_argument("--results", action="append", default=[], metavar="CASE=FILE",
                   help="evaluate FILE (e.g. a campaign run's results.h5) for CASE instead of "
                        "running the case's deck; repeatable")
    a = p.parse_args(argv)
    names = a.cases or list(CASES)
    given: dict[str, Path] = {}
    for item in a.results:
        case_name, sep, file = item.partition("=")
        if not sep or not file:
            p.error(f"--results {item!r}: expected CASE=FILE")
        if case_name not in names:
            p.error(f"--results {item!r}: case {case_name!r} is not among the cases to run "
                    f"({', '.join(names)})")
        if not CASES[case_name].run:
            p.error(f"--results {item!r}: case {case_name!r} runs its own variants of its deck, "
                    "it has no single results file to take")
        given[case_name] = Path(file)
    t0 = time.perf_counter()
    results = run_cases(names, a.out, a.exe, a.reuse, given)
    from .report import write_report
    report = Path(a.report or Path(a.out) / "validation_report.html")
    write_report(results, report, git_commit=_git_commit(), total_time=time.perf_counter() - t0)
    for r in results:
        print(r.summary())
    print(f"report: {report}")
    return 0 if all(r.passed for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
