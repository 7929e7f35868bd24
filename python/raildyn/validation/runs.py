"""Decks and runs of the cases: a deck as the runner reads it, its ASSUMPTION lines, running a
deck with the runner, the context an evaluation works with (channels, plots, variant runs)
and the case record."""
from __future__ import annotations

import functools
import hashlib
import json
import os
import re
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from .. import executable
from ..executable import EXIT_OUTCOMES, RESULTS_READABLE, ExecutableNotFound, find_raildyn_executable
from ..results import Results
from .core import INPUTS, REPO, Check, CaseError, CaseResult


@functools.lru_cache(maxsize=None)
def read_deck(deck: str | os.PathLike) -> dict:
    """The deck as the runner reads it, ``raildyn check DECK --json`` (docs/validation.md):
    "decks" (the deck and its includes in reading order), "groups" (every group resolved:
    overrides merged, defaults applied). Read by the runner found the usual way
    (raildyn.executable; reading runs nothing, so not the ``--exe`` of the runs); once per deck
    and process. A deck that does not read is a CaseError with the runner's message."""
    exe = find_executable()
    proc = subprocess.run([os.fspath(exe), "check", os.fspath(deck), "--json"], capture_output=True, text=True)
    try:
        answer = json.loads(proc.stdout)
    except json.JSONDecodeError:
        raise CaseError(f"{exe} check {deck} --json gave no answer: {proc.stderr.strip()}") from None
    if not answer.get("decks"):
        raise CaseError(f"raildyn check {deck}: {answer.get('message')}")
    return answer


def deck_files(deck: str | os.PathLike) -> list[Path]:
    """The deck and every deck it includes (reading order, each once)."""
    return [Path(p).resolve() for p in read_deck(os.fspath(deck))["decks"]]


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
        proc = executable.run_deck(exe, run_deck_path, results, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise CaseError(f"raildyn run {run_deck_path.name} exceeded the wall-clock limit of {timeout:g} s "
                        "(RAILDYN_VALIDATION_TIMEOUT); the partial results are in "
                        f"{results}") from None
    wall = time.perf_counter() - t0
    if proc.returncode not in RESULTS_READABLE:
        msg = (proc.stderr.strip() or proc.stdout.strip()).splitlines()
        raise CaseError(f"raildyn run {run_deck_path} exited with {proc.returncode} "
                        f"({EXIT_OUTCOMES.get(proc.returncode, '?')}): {msg[-1] if msg else 'no message'}")
    if not results.exists():
        raise CaseError(f"raildyn run {run_deck_path} wrote no results file {results}")
    return RunInfo(results, proc.returncode, wall, proc.stderr, stdout=proc.stdout)


# ------------------------------------------------------------------------------------------
# case context and registry


class Context:
    """What an evaluation function works with: the case's results and helpers."""

    def __init__(self, case: "Case", result: CaseResult, results: Results | None, out_dir: Path,
                 exe: str | os.PathLike | None, reuse: bool):
        self.case, self.result, self.r, self.out_dir = case, result, results, out_dir
        self.exe, self.reuse = exe, reuse
        self.cache: dict = {}        #: values shared by the checks of one evaluation

    # data access by the names of docs/output.md ('series:component'), with a clear message
    # when the scene did not write a channel
    def _results(self, results: Results | None) -> Results:
        if (results or self.r) is None:
            raise CaseError(f"case {self.case.name} has no results of its own")
        return results or self.r

    def has(self, channel: str, results: Results | None = None) -> bool:
        return channel in self._results(results)

    def get(self, channel: str, results: Results | None = None) -> np.ndarray:
        r = self._results(results)
        if channel not in r:
            bodies = [c for c in r.channels() if c.startswith(("bodies/", "wheelsets/"))]
            hint = ("" if bodies else " (the results hold no bodies/ or wheelsets/ series: the "
                    "scene did not build bodies and wheelsets from the deck)")
            raise CaseError(f"{Path(r.path).name}: no channel {channel!r}{hint}")
        return np.asarray(r.get(channel), float)

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
        from ..report import figure_png
        self.result.plots.append((title, figure_png(title, list(series), ylabel, scale, window,
                                                    list(bands))))

    def close(self) -> None:
        for key, value in list(self.cache.items()):
            if isinstance(key, tuple) and key[0] == "fastsim_reference":
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
    baseline_channels: tuple[str, ...] = ()     #: default channels of ``freeze``
    run: bool = True                            #: False: evaluation runs its own variants only

    @property
    def deck_path(self) -> Path:
        return INPUTS / self.deck


def deck_wheelsets(deck: str | os.PathLike) -> list[str]:
    """Names of the deck's wheelsets (its &wheelset groups, overrides merged), in deck order."""
    return [w["name"] for w in read_deck(os.fspath(deck))["groups"].get("wheelset", [])]
