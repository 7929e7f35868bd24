"""Parametric campaigns: many runs of one base deck with parameters swept.

A campaign is described by a TOML file (SI units, paths relative to the file)::

    name = "bogie_speed_sweep"
    deck = "../inputs/tgv_bogie_straight_20.nml"   # the base deck
    output = "runs/bogie_speed_sweep"              # one folder per run below this
    executor = "local"                             # "local" (process pool) or "slurm"
    jobs = 2                                       # local: runs at once
    raildyn = "../build/bin/raildyn"               # optional runner (an error if missing);
                                                   # default $RAILDYN_EXE, $RAILDYN_BUILD_DIR/bin

    [sweep]                                        # Cartesian product of the lists
    "simulation.speed" = [20.0, 30.0, 40.0]        # group.parameter (groups that occur once)
    "wheelset[w1].friction" = [0.3, 0.4]           # group[name].parameter (named groups)

    [[metrics]]                                    # one number per run for the summary
    name = "ws1_lateral_amplitude"
    channel = "bodies/ws1/position_track:y"        # series path, ':component' optional
    reduce = "max_abs"                             # max min mean max_abs rms final growth_rate
    window = [5.0, 10.0]                           # optional time window [s], or
    # window_position = [100.0, 400.0]             # track positions [m] (/vehicle/distance)

    [[metrics]]                                    # a quantity of raildyn assess instead
    name = "yq_w1"
    quantity = "Y/Q"                               # its "name" (docs/assessment.md)
    wheelset = "w1"                                # optional: wheelset side sensor direction patch
    take = "value"                                 # value (default) margin limit position
    window_position = [100.0, 400.0]               # optional: assess only these rows

    [slurm]                                        # executor = "slurm"
    options = ["--time=00:30:00", "--mem=2G"]

Each run gets a folder with `deck.nml` (an ``&include`` of the base deck followed by the
overriding groups, so the run's deck says exactly what differs), `results.h5`, `log.txt` and
`status.json`. A run that completed before is not run again if nothing it depends on changed:
every file its deck reads (the deck, included decks at any depth, profile, irregularity and
survey files: the runner lists them, ``raildyn check --json``), and the runner itself (version
and executable). So a campaign can be resumed after an interruption (Ctrl-C stops it with
"interrupted; rerun to resume", exit status 130); a completed run whose results file is
damaged or incomplete runs again with a notice on stderr naming the file and the fault (the
damaged file is kept as ``results.h5.damaged``). ``summary.csv`` collects parameters, status
and metrics; a failed run's row says why (``error``) and at which simulated time (``failed_at``, s).

Windows: ``window`` keeps the rows with time in ``[t_from, t_to]`` (s), ``window_position``
those whose track position ``/vehicle/distance`` (the vehicle reference point) lies in
``[s_from, s_to]`` (m), so that runs at different speeds compare the same stretch of track.
A window without rows is an error naming the metric and what the run covered.

Quantity metrics name a quantity of ``raildyn assess`` (``raildyn.assess``, docs/assessment.md)
by its JSON ``"name"`` (``"Y/Q"``, ``"sum_Y"``, ``"Q_max"``, ``"N_MV"``, ``"T_gamma"``, ...),
narrowed by ``wheelset``, ``side``, ``sensor``, ``direction``, ``patch``; where several
quantities match, the metric is the worst of them: the smallest margin to its limit, or for
quantities without a limit the largest magnitude (``RCF_index``, the surface fatigue index
FI_surf: the largest value, a negative one being below the shakedown limit). ``take`` chooses what the summary gets of
it: its ``value``, its ``margin`` ((limit - |value|) / limit), its ``limit`` or the track
``position`` of the value. With a window the assessment runs on a copy of the results cut to
the window's rows (``raildyn.results_window``), so windowed sliding means and percentiles
cover that stretch only. A quantity the assessment reports as not available (no sensors,
track shorter than a window) is an error with its reason.

Command line::

    python -m raildyn.campaign run CAMPAIGN.toml [--jobs N] [--executor local|slurm] [--submit]
    python -m raildyn.campaign summary CAMPAIGN.toml
    python -m raildyn.campaign decks CAMPAIGN.toml      # write the decks only

With ``executor = "slurm"`` the runs become one job array (``campaign.sbatch`` in the output
folder, one array task per run, ``sbatch --wait`` with ``--submit``); the summary is made when
the array has finished (or later with ``summary``).
"""

from __future__ import annotations

import argparse
import csv
import difflib
import hashlib
import itertools
import json
import math
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import threading
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .executable import CommandParser, ExecutableNotFound, find_raildyn_executable, run_deck
from .results import Results
from .results_window import write_rows
# the growth-rate estimator is raildyn critical-speed's and the validation harness's
from .stability import StabilityError, growth_rate

KEY_RE = re.compile(r"^(?P<group>[a-z_]+)(\[(?P<name>[^\]]+)\])?\.(?P<param>[a-z_0-9]+)$")
#: reductions of a channel over a window's samples (reduce_channel; growth_rate besides these)
_REDUCERS = {"max": np.max, "min": np.min, "mean": np.mean, "max_abs": lambda y: np.max(np.abs(y)),
             "rms": lambda y: np.sqrt(np.mean(y ** 2)), "final": lambda y: y[-1]}
REDUCTIONS = (*_REDUCERS, "growth_rate")
#: quantities without a limit whose largest signed value is the worst (FI_surf < 0: below the
#: shakedown limit, the further the safer)
SIGNED_WORST = frozenset({"RCF_index"})
#: what a quantity metric takes of the quantity (raildyn assess JSON fields)
TAKES = ("value", "margin", "limit", "position")
#: fields of a raildyn assess quantity a metric may select by
QUANTITY_SELECTORS = ("wheelset", "side", "sensor", "direction", "patch")
METRIC_KEYS = {"name", "channel", "reduce", "window", "window_position", "quantity", "take",
               *QUANTITY_SELECTORS}


class CampaignError(ValueError):
    """A campaign file that cannot be used; the message names the file and the entry."""


@dataclass
class Metric:
    """One number per run: a channel reduced over a window, or a raildyn assess quantity."""
    name: str
    channel: str | None = None
    reduce: str | None = None
    window: tuple[float, float] | None = None            #: time [s]
    window_position: tuple[float, float] | None = None   #: track position [m]
    quantity: str | None = None
    select: dict[str, Any] = field(default_factory=dict)
    take: str = "value"


@dataclass
class Campaign:
    path: Path
    name: str
    deck: Path
    output: Path
    executor: str = "local"
    jobs: int = 1
    sweep: dict[str, list[Any]] = field(default_factory=dict)
    metrics: list[Metric] = field(default_factory=list)
    slurm_options: list[str] = field(default_factory=list)
    exe: Path | None = None
    #: explicit parameter sets instead of the sweep's product (a campaign built in code, e.g.
    #: the probes of raildyn critical-speed: raildyn.stability.run_probes)
    variants: list[dict[str, Any]] | None = None

    def runs(self) -> list[dict[str, Any]]:
        """Parameter sets: the variants if given, else the Cartesian product of the sweep, in
        a stable order."""
        if self.variants is not None:
            return [dict(v) for v in self.variants]
        keys = list(self.sweep)
        return [dict(zip(keys, values)) for values in itertools.product(*self.sweep.values())]

    def parameter_names(self) -> list[str]:
        """The swept parameters (summary columns), in order of first appearance."""
        if self.variants is None:
            return list(self.sweep)
        return list(dict.fromkeys(k for v in self.variants for k in v))


def _fortran_value(value: Any, where: str) -> str:
    """A namelist value; only numbers, strings, logicals and lists of them are accepted, so
    that a typo in the campaign file cannot become a silently different deck."""
    if isinstance(value, bool):
        return ".true." if value else ".false."
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise CampaignError(f"{where}: {value!r} is not a finite number")
        return repr(value)
    if isinstance(value, str):
        return "'" + value.replace("'", "''") + "'"
    if isinstance(value, list) and value and not any(isinstance(v, list) for v in value):
        return ", ".join(_fortran_value(v, where) for v in value)
    raise CampaignError(f"{where}: {value!r} is not a number, string, logical or list of them")


def load_campaign(path: str | os.PathLike) -> Campaign:
    path = Path(path).resolve()
    try:
        data = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise CampaignError(f"{path}: no such campaign file") from None
    except tomllib.TOMLDecodeError as e:
        raise CampaignError(f"{path}: {e}") from None

    def need(key: str, kind: type) -> Any:
        if key not in data:
            raise CampaignError(f"{path}: '{key}' is required")
        if not isinstance(data[key], kind):
            raise CampaignError(f"{path}: '{key}' must be a {kind.__name__}")
        return data[key]

    known = {"name", "deck", "output", "executor", "jobs", "sweep", "metrics", "slurm", "raildyn"}
    for key in data:
        if key not in known:
            raise CampaignError(f"{path}: unknown entry '{key}'; expected one of {sorted(known)}")
    base = path.parent
    camp = Campaign(path=path, name=need("name", str), deck=(base / need("deck", str)).resolve(),
                    output=(base / data.get("output", "runs/" + data.get("name", "campaign"))).resolve())
    if not camp.deck.exists():
        raise CampaignError(f"{path}: deck '{data['deck']}' not found ({camp.deck})")
    camp.executor = data.get("executor", "local")
    if camp.executor not in ("local", "slurm"):
        raise CampaignError(f"{path}: executor must be 'local' or 'slurm', got {camp.executor!r}")
    camp.jobs = int(data.get("jobs", os.cpu_count() or 1))
    if camp.jobs < 1:
        raise CampaignError(f"{path}: jobs must be >= 1")
    sweep = data.get("sweep", {})
    if not isinstance(sweep, dict):
        raise CampaignError(f"{path}: [sweep] must be a table of lists")
    for key, values in sweep.items():
        if not KEY_RE.match(key):
            raise CampaignError(f"{path}: sweep key '{key}' must read group.parameter or "
                                "group[name].parameter")
        if not isinstance(values, list) or not values:
            raise CampaignError(f"{path}: sweep '{key}' must be a non-empty list of values")
        for v in values:
            _fortran_value(v, f"{path}: sweep '{key}'")
        camp.sweep[key] = values
    for i, m in enumerate(data.get("metrics", [])):
        camp.metrics.append(_load_metric(m, f"{path}: metrics[{i}]"))
    camp.slurm_options = list(data.get("slurm", {}).get("options", []))
    if "raildyn" in data:
        camp.exe = (base / data["raildyn"]).resolve()
    return camp


def _load_metric(m: dict[str, Any], where: str) -> Metric:
    """One [[metrics]] entry; `where` names it in errors."""
    unknown = sorted(set(m) - METRIC_KEYS)
    if unknown:
        raise CampaignError(f"{where}: unknown entry '{unknown[0]}'; expected some of {sorted(METRIC_KEYS)}")
    if "name" not in m:
        raise CampaignError(f"{where}: 'name' is required")
    windows = {}
    for key, what in (("window", "[t_from, t_to] (s) with t_from < t_to"),
                      ("window_position", "[s_from, s_to] (m) with s_from < s_to")):
        w = m.get(key)
        if w is None:
            continue
        if (not isinstance(w, list) or len(w) != 2
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in w)
                or not all(math.isfinite(v) for v in w) or not w[0] < w[1]):
            raise CampaignError(f"{where}: {key} must be {what}, got {w!r}")
        windows[key] = (float(w[0]), float(w[1]))
    if len(windows) == 2:
        raise CampaignError(f"{where}: give window (time) or window_position (track), not both")
    if "quantity" in m:
        if "channel" in m or "reduce" in m:
            raise CampaignError(f"{where}: a metric has a quantity (raildyn assess) or a channel "
                                "with reduce, not both")
        if m.get("take", "value") not in TAKES:
            raise CampaignError(f"{where}: take must be one of {TAKES}, got {m['take']!r}")
        return Metric(m["name"], quantity=str(m["quantity"]),
                      select={k: m[k] for k in QUANTITY_SELECTORS if k in m},
                      take=m.get("take", "value"), **windows)
    for k in ("channel", "reduce"):
        if k not in m:
            raise CampaignError(f"{where}: '{k}' is required (or 'quantity', a raildyn assess quantity)")
    if m["reduce"] not in REDUCTIONS:
        raise CampaignError(f"{where}: reduce must be one of {REDUCTIONS}, got {m['reduce']!r}")
    if "take" in m or any(k in m for k in QUANTITY_SELECTORS):
        raise CampaignError(f"{where}: take and {', '.join(QUANTITY_SELECTORS)} belong to quantity metrics")
    return Metric(m["name"], m["channel"], m["reduce"], **windows)


def override_deck(base_deck: Path, params: dict[str, Any]) -> str:
    """The deck of one run: the base deck included, then one group per overridden entity."""
    lines = [f"! raildyn campaign run: base deck plus overrides",
             f"&include file = {_fortran_value(str(base_deck), 'deck')} /"]
    groups: dict[tuple[str, str | None], list[str]] = {}
    for key, value in params.items():
        m = KEY_RE.match(key)
        assert m is not None
        groups.setdefault((m["group"], m["name"]), []).append(
            f"{m['param']} = {_fortran_value(value, key)}")
    for (group, name), assigns in groups.items():
        head = [f"name = {_fortran_value(name, group)}"] if name is not None else []
        lines.append(f"&{group} " + ", ".join(head + assigns) + " /")
    return "\n".join(lines) + "\n"


def find_raildyn(campaign: Campaign) -> Path:
    """The campaign's `raildyn` if set (an error if it is not an executable), else the
    usual places (raildyn.executable)."""
    try:
        return find_raildyn_executable(campaign.exe, f"'raildyn' in {campaign.path}").resolve()
    except ExecutableNotFound as exc:
        raise CampaignError(str(exc)) from None


def run_dir(campaign: Campaign, index: int) -> Path:
    return campaign.output / f"run{index:04d}"


def write_decks(campaign: Campaign) -> list[tuple[int, dict[str, Any], Path]]:
    out = []
    for i, params in enumerate(campaign.runs()):
        d = run_dir(campaign, i)
        d.mkdir(parents=True, exist_ok=True)
        text = override_deck(campaign.deck, params)
        deck = d / "deck.nml"
        if not deck.exists() or deck.read_text() != text:
            deck.write_text(text)
        (d / "parameters.json").write_text(json.dumps(params, indent=1))
        out.append((i, params, d))
    return out


def _file_sha256(path: Path) -> str:
    with open(path, "rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def runner_identity(exe: Path) -> str:
    """The runner's version and the hash of its executable (the physics is linked into it):
    a rebuilt runner makes every run stale."""
    version = subprocess.run([str(exe), "version"], capture_output=True, text=True).stdout.strip()
    return f"{version} sha256:{_file_sha256(exe)}"


def run_inputs(exe: Path, run: Path) -> list[Path] | None:
    """Every file the run's deck reads, as the runner lists them (``raildyn check --json``:
    the deck, its includes at any depth, profile, irregularity and survey files); None when
    the deck does not check (the run then runs and reports why)."""
    proc = subprocess.run([str(exe), "check", "deck.nml", "--json"], cwd=run,
                          capture_output=True, text=True)
    try:
        answer = json.loads(proc.stdout)
    except json.JSONDecodeError:
        return None
    if answer.get("status") != "ok":
        return None
    return [run / name for name in answer["input_files"]]


def inputs_digest(runner: str, exe: Path, run: Path) -> str | None:
    """Hash of the runner's identity and of the name and bytes of every file the run reads;
    None when they cannot all be read (then nothing is reused)."""
    files = run_inputs(exe, run)
    if files is None:
        return None
    h = hashlib.sha256(runner.encode() + b"\0")
    try:
        for path in files:
            h.update(str(path.resolve()).encode() + b"\0" + _file_sha256(path).encode())
    except OSError:
        return None
    return h.hexdigest()


def _results_problem(path: Path) -> str:
    """What is wrong with the results file of a run recorded as completed: '' when it opens
    and says its run completed, else one line naming the file and the fault."""
    if not path.exists():
        return f"{path}: missing"
    try:
        with Results(path) as r:
            status = r.metadata.get("status")
    except (OSError, ValueError, KeyError) as exc:
        reason = " ".join(str(exc).split())
        return f"{path}: damaged, cannot be read as a results file ({reason})"
    if status != "completed":
        return f"{path}: incomplete, its run status is {status!r}, not 'completed'"
    return ""


#: Set when the campaign is interrupted: runs in flight are stopped and not recorded.
_interrupted = threading.Event()
_running: set[subprocess.Popen] = set()
_running_lock = threading.Lock()


def _run_runner(exe: Path, run: Path) -> int | None:
    """`raildyn run` in the run folder; None when the campaign was interrupted (Ctrl-C
    reaches the runs too: one killed by SIGINT is not a failed run)."""
    if _interrupted.is_set():
        return None
    procs: list[subprocess.Popen] = []

    def track(proc: subprocess.Popen) -> None:
        with _running_lock:
            _running.add(proc)
        procs.append(proc)
    with open(run / "log.txt", "w") as log:
        try:
            code = run_deck(exe, "deck.nml", "results.h5", quiet=True, cwd=run, log=log, started=track).returncode
        finally:
            with _running_lock:
                _running.difference_update(procs)
    return None if _interrupted.is_set() or code == -signal.SIGINT else code


def _stop_running_runs() -> None:
    _interrupted.set()
    with _running_lock:
        for proc in _running:
            proc.send_signal(signal.SIGINT)


def _failure(run: Path) -> tuple[str, float | str]:
    """Why and when a run failed: the runner's error line, and the simulated time its
    results file reached (from /meta: '' when the run failed before writing one)."""
    lines = (run / "log.txt").read_text(errors="replace").strip().splitlines()
    message = lines[-1].removeprefix("raildyn: error: ") if lines else ""
    when: float | str = ""
    try:
        with Results(run / "results.h5") as r:
            meta = r.metadata
            if str(meta.get("status", "")).startswith("failed: "):
                message = meta["status"].removeprefix("failed: ")
                when = float(meta.get("end_time", ""))
    except (OSError, ValueError, KeyError):
        pass
    return message, when


def run_one(exe: Path, run: Path, runner: str | None = None,
            notice=None) -> dict[str, Any] | None:
    """Run one deck unless it completed before with the same inputs (run_inputs) and runner
    (runner_identity); returns its status, None when the campaign was interrupted.

    A run recorded as completed whose results file is damaged (unreadable, cut short) or
    incomplete is run again, never silently: `notice` (default: print to stderr) gets one
    line naming the file and the fault before the run starts, the file is kept beside the
    new one as results.h5.damaged, and status.json records the reason (rerun_reason)."""
    status_file = run / "status.json"
    runner = runner or runner_identity(exe)
    digest = inputs_digest(runner, exe, run)
    rerun_reason = ""
    if digest is not None and status_file.exists():
        try:
            old = json.loads(status_file.read_text())
        except json.JSONDecodeError:
            old = {}
        if old.get("exit_code") == 0 and old.get("inputs_sha256") == digest:
            problem = _results_problem(run / "results.h5")
            if not problem:
                old["reused"] = True
                return old
            rerun_reason = problem
            kept = ""
            if (run / "results.h5").exists():
                (run / "results.h5").replace(run / "results.h5.damaged")
                kept = f"; kept as {run / 'results.h5.damaged'}"
            (notice or _notice)(f"raildyn campaign: {run.name}: completed before, but its results file "
                                f"is unusable: {problem}; running it again{kept}")
    # nothing of an earlier attempt may be read as this run's outcome (_failure)
    status_file.unlink(missing_ok=True)
    (run / "results.h5").unlink(missing_ok=True)
    t0 = time.time()
    code = _run_runner(exe, run)
    if code is None:
        return None
    status = {"exit_code": code, "wall_time": time.time() - t0,
              "inputs_sha256": digest, "runner": runner, "reused": False}
    if rerun_reason:
        status["rerun_reason"] = rerun_reason
    if code != 0:
        status["error"], status["failed_at"] = _failure(run)
    status_file.write_text(json.dumps(status, indent=1))
    return status


def _notice(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def reduce_channel(t: np.ndarray, y: np.ndarray, how: str) -> float:
    if len(y) == 0:
        return float("nan")
    if how in _REDUCERS:
        return float(_REDUCERS[how](y))
    if how == "growth_rate":
        # the envelope of the oscillation about the signal's mean, every half-cycle peak
        # counted (floor 0); fewer than 3 peaks: no oscillation, no rate
        try:
            rate, peaks = growth_rate(t, y - np.mean(y), floor=0.0)
        except StabilityError:
            return float("nan")
        return rate if peaks else float("nan")
    raise CampaignError(f"unknown reduction {how!r}")


def _window_rows(campaign: Campaign, m: Metric, res: Results, path: Path) -> np.ndarray | None:
    """The rows of metric m's window (None: every row); an empty window is a CampaignError
    saying what the run covered."""
    if m.window is not None:
        axis, what, unit, (a, b) = res.time, "time", "s", m.window
    elif m.window_position is not None:
        if "vehicle/distance" not in res:
            raise CampaignError(f"{campaign.path}: metric '{m.name}': window_position needs the "
                                f"track position /vehicle/distance, which {path} does not hold "
                                "(&output groups 'vehicle')")
        axis, what, unit, (a, b) = res.get("vehicle/distance:sigma"), "track position", "m", m.window_position
    else:
        return None
    rows = (axis >= a) & (axis <= b)
    if not rows.any():
        covered = f"{axis.min():g} to {axis.max():g} {unit}" if axis.size else "nothing"
        raise CampaignError(f"{campaign.path}: metric '{m.name}': no rows of {path} in its {what} "
                            f"window [{a:g}, {b:g}] {unit}; the run covered {covered}")
    return rows


def _assessment_quantities(path: Path) -> list[dict[str, Any]]:
    """The "quantities" of ``raildyn assess PATH --json`` (raildyn.assess)."""
    try:
        from . import assess
    except ImportError as exc:
        raise CampaignError(f"quantity metrics need raildyn.assess, which cannot be imported ({exc})") from None
    return assess.assess(path).to_json()["quantities"]


def _label(q: dict[str, Any]) -> str:
    return " ".join(str(q[k]) for k in ("name", *QUANTITY_SELECTORS) if q.get(k) is not None)


def quantity_metric(campaign: Campaign, m: Metric, quantities: list[dict[str, Any]], path: Path) -> float:
    """Metric m from an assessment's quantities (JSON objects): the worst match's `take`."""
    where = f"{campaign.path}: metric '{m.name}'"
    named = [q for q in quantities if q["name"] == m.quantity]
    if not named:
        names = sorted({q["name"] for q in quantities})
        raise CampaignError(f"{where}: raildyn assess has no quantity '{m.quantity}' for {path}; "
                            f"it has {', '.join(names)}")
    matches = [q for q in named if all(q.get(k) == v for k, v in m.select.items())]
    if not matches:
        raise CampaignError(f"{where}: no '{m.quantity}' with {m.select} in {path}; there are "
                            + ", ".join(_label(q) for q in named))
    missing = [q for q in matches if q.get("value") is None]
    if missing:
        raise CampaignError(f"{where}: {_label(missing[0])} is not available for {path}: "
                            f"{missing[0].get('reason', 'no reason given')}")
    limited = [q for q in matches if q.get("margin") is not None]
    if limited:
        worst = min(limited, key=lambda q: q["margin"])
    elif m.quantity in SIGNED_WORST:
        worst = max(matches, key=lambda q: q["value"])
    else:
        worst = max(matches, key=lambda q: abs(q["value"]))
    value = worst.get(m.take)
    if value is None:
        raise CampaignError(f"{where}: {_label(worst)} has no {m.take} (limit: {worst.get('limit')})")
    return float(value)


def metrics_of(campaign: Campaign, run: Path) -> dict[str, float]:
    """The campaign's metrics of one completed run; a results file that cannot be read, a
    metric whose channel it does not hold, an empty window or a quantity the assessment
    cannot give is a CampaignError naming them."""
    path = run / "results.h5"
    try:
        res = Results(path)
    except (OSError, ValueError) as exc:
        raise CampaignError(f"{path}: cannot read the results file ({exc}); delete it and "
                            "rerun the campaign to run it again") from None
    out = {}
    assessed: dict[Any, list[dict[str, Any]]] = {}    # one assessment per window
    with res:
        for m in campaign.metrics:
            rows = _window_rows(campaign, m, res, path)
            if m.quantity is not None:
                key = (m.window, m.window_position)
                if key not in assessed:
                    assessed[key] = _assess_rows(path, rows, run)
                out[m.name] = quantity_metric(campaign, m, assessed[key], path)
                continue
            try:
                data = res.get(m.channel)
            except KeyError:
                close = difflib.get_close_matches(m.channel.split(":")[0], res.channels(), n=3)
                raise CampaignError(
                    f"{campaign.path}: metric '{m.name}': channel '{m.channel}' is not in "
                    f"{path}" + (f"; close names: {', '.join(close)}" if close else "")) from None
            if data.ndim > 1:
                data = data[:, 0]
            t = res.time
            if rows is not None:
                t, data = t[rows], data[rows]
            out[m.name] = reduce_channel(t, data, m.reduce)
    return out


def _assess_rows(path: Path, rows: np.ndarray | None, run: Path) -> list[dict[str, Any]]:
    """The assessment of the results `path`, or of its rows `rows` only (a cut copy in a
    temporary folder)."""
    if rows is None:
        return _assessment_quantities(path)
    with tempfile.TemporaryDirectory(prefix="raildyn-window-") as tmp:
        cut = write_rows(path, rows, Path(tmp) / f"{run.name}.h5")
        return _assessment_quantities(cut)


def _read_status(run: Path) -> dict[str, Any]:
    try:
        return json.loads((run / "status.json").read_text())
    except (OSError, json.JSONDecodeError):
        return {}


def write_summary(campaign: Campaign) -> Path:
    """summary.csv: one row per run (parameters, exit code, wall time, error and failure
    time of a failed run, metrics). Metrics that cannot be computed are left empty and
    reported after the file is written, as one CampaignError."""
    rows = []
    problems: dict[str, int] = {}
    for i, params in enumerate(campaign.runs()):
        d = run_dir(campaign, i)
        status = _read_status(d)
        row = {"run": d.name, **params, "exit_code": status.get("exit_code", ""),
               "wall_time": status.get("wall_time", ""), "error": status.get("error", ""),
               "failed_at": status.get("failed_at", "")}
        if status.get("exit_code") == 0:
            try:
                row.update(metrics_of(campaign, d))
            except CampaignError as exc:
                problems[str(exc)] = problems.get(str(exc), 0) + 1
        rows.append(row)
    path = campaign.output / "summary.csv"
    fields = ["run", *campaign.parameter_names(), "exit_code", "wall_time", "error", "failed_at",
              *[m.name for m in campaign.metrics]]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow(r)
    if problems:
        raise CampaignError("; ".join(problems) + f" ({path} written without these metrics)")
    return path


def slurm_script(campaign: Campaign, exe: Path, runs: Sequence[Path]) -> Path:
    """A job array, one task per run; each task runs in its run folder and records its
    status like the local executor (status.json)."""
    listing = campaign.output / "runs.txt"
    listing.write_text("".join(f"{r}\n" for r in runs))
    py = shlex.quote(sys.executable)
    pkg = shlex.quote(str(Path(__file__).resolve().parents[1]))
    opts = "".join(f"#SBATCH {o}\n" for o in campaign.slurm_options)
    script = campaign.output / "campaign.sbatch"
    script.write_text(
        "#!/bin/bash\n"
        f"#SBATCH --job-name={campaign.name}\n"
        f"#SBATCH --array=0-{len(runs) - 1}\n"
        f"#SBATCH --output={campaign.output}/slurm-%A_%a.out\n"
        f"{opts}"
        "set -eu\n"
        f"run=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" {shlex.quote(str(listing))})\n"
        f"PYTHONPATH={pkg}${{PYTHONPATH:+:$PYTHONPATH}} {py} -m raildyn.campaign task "
        f"{shlex.quote(str(exe))} \"$run\"\n")
    return script


def run_campaign(campaign: Campaign, jobs: int | None = None, executor: str | None = None,
                 submit: bool = False, progress=print, notice=None) -> Path | None:
    """Run the campaign's decks (reusing completed runs) and write summary.csv; `progress`
    gets one line per run as it finishes, `notice` (default: stderr) the notices of runs
    that must run again because their results file is damaged (run_one)."""
    exe = find_raildyn(campaign)
    runs = write_decks(campaign)
    executor = executor or campaign.executor
    if executor == "slurm":
        script = slurm_script(campaign, exe, [d for _, _, d in runs])
        if not submit:
            progress(f"job array written: sbatch {script}")
            return None
        proc = subprocess.run(["sbatch", "--wait", str(script)], capture_output=True, text=True)
        progress(proc.stdout.strip() or proc.stderr.strip())
        return write_summary(campaign)
    jobs = jobs or campaign.jobs
    runner = runner_identity(exe)
    _interrupted.clear()
    pool = ThreadPoolExecutor(max_workers=jobs)
    try:
        futures = [pool.submit(run_one, exe, d, runner, notice) for _, _, d in runs]
        for done, ((_, _, d), future) in enumerate(zip(runs, futures), start=1):
            status = future.result()
            if status is None:
                continue
            state = "reused" if status.get("reused") else (
                "ok" if status["exit_code"] == 0 else f"failed ({status.get('error', '')})")
            if status.get("rerun_reason") and not status.get("reused"):
                state += ", run again because its results file was damaged or incomplete"
            progress(f"[{done}/{len(runs)}] {d.name}: {state}")
    except KeyboardInterrupt:
        # Stop the runs in flight (unrecorded: a rerun resumes them) and start no other;
        # a second Ctrl-C must not break this off.
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            _stop_running_runs()
            pool.shutdown(wait=True, cancel_futures=True)
        finally:
            signal.signal(signal.SIGINT, previous)
        raise
    pool.shutdown()
    return write_summary(campaign)


def main(argv: Sequence[str] | None = None) -> int:
    ap = CommandParser(prog="raildyn campaign", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="write the decks, run them, write summary.csv")
    r.add_argument("campaign")
    r.add_argument("--jobs", type=int)
    r.add_argument("--executor", choices=("local", "slurm"))
    r.add_argument("--submit", action="store_true", help="slurm: submit and wait")
    s = sub.add_parser("summary", help="(re)write summary.csv from finished runs")
    s.add_argument("campaign")
    d = sub.add_parser("decks", help="write the run decks only")
    d.add_argument("campaign")
    t = sub.add_parser("task", help=argparse.SUPPRESS)   # one Slurm array task
    t.add_argument("exe")
    t.add_argument("run")
    args = ap.parse_args(argv)
    try:
        if args.command == "task":
            status = run_one(Path(args.exe), Path(args.run))
            if status is None:
                raise KeyboardInterrupt
            return 0 if status["exit_code"] == 0 else 1
        camp = load_campaign(args.campaign)
        if args.command == "decks":
            for _, _, d in write_decks(camp):
                print(d / "deck.nml")
            return 0
        if args.command == "summary":
            print(write_summary(camp))
            return 0
        path = run_campaign(camp, jobs=args.jobs, executor=args.executor, submit=args.submit)
        if path is not None:
            print(f"summary: {path}")
            with open(path) as f:
                failed = [row for row in csv.DictReader(f) if row["exit_code"] != "0"]
            return 1 if failed else 0
        return 0
    except CampaignError as e:
        print(f"raildyn campaign: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("raildyn campaign: interrupted; rerun to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
