"""Where the `raildyn` runner is and how a deck is run: the one lookup and the one run shared
by the validation harness and the campaigns."""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

try:                            # written by cmake --install only
    from . import _installed_layout
except ImportError:             # a source tree
    _installed_layout = None


class ExecutableNotFound(ValueError):
    """No usable runner; the message says what was tried."""


def find_raildyn_executable(exe: str | os.PathLike | None = None, given_as: str = "--exe") -> Path:
    """The explicit path if given (an error if it is not an executable file: never another
    runner in its place), else $RAILDYN_EXE, $RAILDYN_BUILD_DIR/bin/raildyn, the runner
    installed with this package (cmake --install), <repo>/build/bin/raildyn. ``given_as``
    names the explicit setting in messages."""
    if exe:
        if Path(exe).is_file() and os.access(exe, os.X_OK):
            return Path(exe)
        raise ExecutableNotFound(f"raildyn executable {exe} ({given_as}) is not an executable file")
    cands = []
    if os.environ.get("RAILDYN_EXE"):
        cands.append(Path(os.environ["RAILDYN_EXE"]))
    if os.environ.get("RAILDYN_BUILD_DIR"):
        cands.append(Path(os.environ["RAILDYN_BUILD_DIR"]) / "bin" / "raildyn")
    if _installed_layout is not None:
        cands.append(_installed_layout.RUNNER)
    cands.append(REPO / "build" / "bin" / "raildyn")
    for c in cands:
        if c.is_file() and os.access(c, os.X_OK):
            return c
    raise ExecutableNotFound("raildyn executable not found (tried " + ", ".join(map(str, cands)) +
                             f"); build it, set RAILDYN_BUILD_DIR or give {given_as}")


#: raildyn run's exit statuses: the C API's status codes (raildyn.h; rd_error's failure
#: policy). After RESULTS_READABLE ones (completed, physics limit) the results file holds the run.
EXIT_OUTCOMES = {0: "completed", 1: "bad input", 2: "solver failure", 3: "physics limit", 4: "file error",
                 5: "internal error"}
RESULTS_READABLE = (0, 3)


class CommandParser(argparse.ArgumentParser):
    """The parser of a command the runner hands to Python (raildyn campaign, raildyn
    critical-speed): a usage error prints the usage line and exits with 1, bad input as the
    runner's commands, not with argparse's 2, the runner's solver-failure status. The message
    starts with ``error_prefix`` (default '<prog>: error')."""
    error_prefix = ""

    def error(self, message: str):
        self.print_usage(sys.stderr)
        self.exit(1, f"{self.error_prefix or self.prog + ': error'}: {message}\n")


def run_deck(exe: str | os.PathLike, deck: str | os.PathLike, results: str | os.PathLike, *, quiet: bool = False,
             cwd: str | os.PathLike | None = None, log=None, timeout: float | None = None,
             started=None) -> subprocess.CompletedProcess:
    """``raildyn run DECK -o RESULTS [--quiet]`` in ``cwd``: the one way Python runs a deck.
    Its output goes to the open file ``log`` (stdout and stderr interleaved) or is captured
    (the answer's ``stdout`` and ``stderr``); ``started(proc)`` gets the running process (the
    campaigns stop their runs on Ctrl-C). Past ``timeout`` seconds the run is killed and
    subprocess.TimeoutExpired raised, as subprocess.run does. Exit statuses: EXIT_OUTCOMES."""
    cmd = [os.fspath(exe), "run", os.fspath(deck), "-o", os.fspath(results), *(["--quiet"] if quiet else [])]
    with subprocess.Popen(cmd, cwd=cwd, text=True, stdout=log or subprocess.PIPE,
                          stderr=subprocess.STDOUT if log else subprocess.PIPE) as proc:
        if started is not None:
            started(proc)
        try:
            stdout, stderr = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
            raise
    return subprocess.CompletedProcess(cmd, proc.returncode, stdout, stderr)
