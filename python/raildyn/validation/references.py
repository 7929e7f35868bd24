"""Reference data of the cases: the Manchester packages' tables (thesis tables 5.9-5.11 with
their corrections), the TGV checks, reference curves and frozen baselines."""
from __future__ import annotations

import csv
import datetime as _dt
import hashlib
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from ..results import Results
from .core import VALIDATION, read_commented_csv

#: Where reference curves (curves/<case>/*.csv) and frozen baselines (baselines/<case>.csv) are
#: looked up and frozen; the harness's own tests point it elsewhere to run synthetic cases.
BANDS = VALIDATION

#: Commercial packages of the benchmark (VIA is the thesis' own code, shown but not used).
PACKAGES = ("SIMPACK", "VAMPIRE", "GENSYS", "ADAMS", "NUCARS")
UNIT_SCALE = {"mm": 1e-3, "mrad": 1e-3, "kN": 1e3, "m": 1.0, "rad": 1.0, "N": 1.0}


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


def load_tgv_checks(path: str | os.PathLike | None = None) -> list[dict[str, str]]:
    return read_commented_csv(path or VALIDATION / "tgv_checks.csv")[1]
