"""Export a results file as CSV: one file per series, the axis (``time``, or ``sigma`` for a
track export) as first column, every header cell ``name [unit]``.

The units are the ``unit`` attributes of the file (docs/output.md), never guessed: a series
without one, or with a number of tokens that is neither 1 nor its column count, is an error
naming it. Command line: ``raildyn export RESULTS.h5 --csv DIR`` (the runner calls
``python -m raildyn.export``); ``DIR/<series path>.csv`` mirrors the HDF5 hierarchy, e.g.
``DIR/bodies/ws1/position_track.csv``.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

from .results import Results


class ExportError(ValueError):
    """The file cannot be exported as asked; the message names the file and the series."""


def _header(results: Results, series: str) -> list[str]:
    path = results.path
    ncomp = 1 if series == results.axis else results.get(series).shape[1]
    # the stored attributes themselves: Results.components() would invent names c1, c2, ...
    names = str(results._attr(series, "components", "")).split()
    tokens = str(results._attr(series, "unit", "")).split()
    if len(tokens) not in (1, ncomp):
        raise ExportError(f"{path}: series {series} has unit attribute {' '.join(tokens)!r}: "
                          f"expected one SI unit or one per column ({ncomp})")
    if len(names) != ncomp:
        raise ExportError(f"{path}: series {series} has components {' '.join(names)!r}: "
                          f"expected {ncomp} column names")
    units = results.units(series)
    return [f"{n} [{u}]" for n, u in zip(names, units)]


def export_csv(results_path: str | os.PathLike, directory: str | os.PathLike) -> list[Path]:
    """Write one CSV per series of ``results_path`` under ``directory``; returns their paths.
    Rows are the complete output steps (a killed run's partly written last row is left out,
    as ``Results`` does); numbers are written with 17 significant digits (exact doubles)."""
    out = Path(directory)
    written = []
    with Results(results_path) as r:
        axis_header = _header(r, r.axis)
        axis = r.time
        for series in r.channels():
            header = axis_header + _header(r, series)
            target = out / f"{series}.csv"
            target.parent.mkdir(parents=True, exist_ok=True)
            table = np.column_stack([axis, r.get(series)])
            np.savetxt(target, table, fmt="%.17g", delimiter=",", header=",".join(header),
                       comments="")
            written.append(target)
    return written


def main(argv: list[str] | None = None) -> int:
    """``raildyn export RESULTS.h5 --csv DIR``: exit 0, 1 for bad usage or a file that is not
    a raildyn results file as docs/output.md describes, 4 when it cannot be read or written."""
    parser = argparse.ArgumentParser(prog="raildyn export", description=__doc__.split("\n\n")[0])
    parser.add_argument("results", help="results file (HDF5) of raildyn run or raildyn track")
    parser.add_argument("--csv", metavar="DIR", required=True,
                        help="directory for the CSV files (created; existing files are replaced)")
    args = parser.parse_args(argv)
    if not Path(args.results).is_file():
        print(f"raildyn export: error: {args.results}: no such file", file=sys.stderr)
        return 4
    try:
        files = export_csv(args.results, args.csv)
    except OSError as e:
        print(f"raildyn export: error: {e}", file=sys.stderr)
        return 4
    except ValueError as e:         # an ExportError, or Results: not a raildyn results file
        print(f"raildyn export: error: {e}", file=sys.stderr)
        return 1
    print(f"raildyn export: {len(files)} CSV files written to {args.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
