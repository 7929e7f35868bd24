"""Command line of the harness: ``python -m raildyn.validation [run|list|freeze] ...``."""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

from .cases import CASES, run_cases
from .core import REPO
from .fidelity_map import published_section
from .references import freeze_baseline


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
    from ..report import write_report
    report = Path(a.report or Path(a.out) / "validation_report.html")
    write_report(results, report, git_commit=_git_commit(), total_time=time.perf_counter() - t0,
                 sections=[published_section()])
    for r in results:
        print(r.summary())
    print(f"report: {report}")
    return 0 if all(r.passed for r in results) else 1
