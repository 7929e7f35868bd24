"""Stability of a deck (docs/theory_stability.md): the modes `raildyn eigen` reports, read
back from its JSON and CSV answers.
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass, field

__all__ = ["Mode", "mode_from_json", "read_root_locus"]


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
