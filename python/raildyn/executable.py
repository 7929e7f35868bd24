"""Where the `raildyn` runner is: the one lookup shared by the validation harness and the
campaigns."""
from __future__ import annotations

import os
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
