"""What a validation case reports (checks, tables, its result), its error, the repository's
places and the commented CSV files of validation/."""
from __future__ import annotations

import csv
import os
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
INPUTS = REPO / "inputs"
VALIDATION = REPO / "validation"


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
    ``status`` holds one bool per row (pass/fail colouring of the row's ``value_column`` cell)
    or None."""
    title: str
    columns: list[str]
    rows: list[list]
    status: list[bool | None] = field(default_factory=list)
    note: str = ""
    value_column: int = 2


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


@dataclass
class ReportSection:
    """A section of the report that is not a case: published measurements shown with the
    cases (the fidelity map). Paragraphs of text, tables and (title, PNG) plots."""
    name: str
    title: str
    paragraphs: list[str] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    plots: list[tuple[str, bytes]] = field(default_factory=list, repr=False)


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
