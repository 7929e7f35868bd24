"""``raildyn assess RESULTS.h5 [--json] [--csv DIR] [--html DIR]`` (the runner calls
``python -m raildyn.assess``): exit 0, 1 for a file that is not a results file or bad usage,
4 for a file that cannot be read or written."""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from .assessment import assess
from .report import text_table, to_json_text, write_csv, write_html


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="raildyn assess",
        description="EN 14363 running safety and track loading, EN 12299 ride comfort and wear "
                    "indices of a results file (docs/assessment.md)")
    parser.add_argument("results", help="results file (HDF5) of raildyn run")
    parser.add_argument("--json", action="store_true",
                        help="print one JSON object with the list 'quantities' instead of the table")
    parser.add_argument("--csv", metavar="DIR", help="write quantities.csv and the series as CSV files")
    parser.add_argument("--html", metavar="DIR", help="write assessment.html and the plots (PNG)")
    parser.add_argument("--prudhomme-alpha", type=float, default=1.0, metavar="ALPHA",
                        help="factor of the Prud'homme limit (1; 0.85 for freight wagons)")
    parser.add_argument("--instability-frequency", type=float, default=None, metavar="HZ",
                        help="f0 of the instability band f0 +- 2 Hz (default: the dominant "
                             "frequency of sum Y between 0.5 and 15 Hz)")
    parser.add_argument("--shear-yield", type=float, default=300e6, metavar="K",
                        help="yield limit in pure shear k [Pa] of the RCF index FI_surf "
                             "(default 3e8)")
    args = parser.parse_args(argv)
    if not Path(args.results).is_file():
        print(f"raildyn assess: error: {args.results}: no such file", file=sys.stderr)
        return 4
    if not 0 < args.prudhomme_alpha <= 1:
        print(f"raildyn assess: error: --prudhomme-alpha {args.prudhomme_alpha}: expected 0 < ALPHA <= 1",
              file=sys.stderr)
        return 1
    if args.instability_frequency is not None and not args.instability_frequency > 0:
        print(f"raildyn assess: error: --instability-frequency {args.instability_frequency}: "
              "expected a frequency > 0 Hz", file=sys.stderr)
        return 1
    if not args.shear_yield > 0:
        print(f"raildyn assess: error: --shear-yield {args.shear_yield}: expected a shear yield "
              "limit k > 0 Pa", file=sys.stderr)
        return 1
    try:
        a = assess(args.results, args.prudhomme_alpha, args.instability_frequency, args.shear_yield)
        if args.csv:
            write_csv(a, args.csv)
        if args.html:
            write_html(a, args.html)
    except OSError as e:
        print(f"raildyn assess: error: {e}", file=sys.stderr)
        return 4
    except (ValueError, KeyError) as e:    # Results: not a raildyn results file
        print(f"raildyn assess: error: {args.results}: {e}", file=sys.stderr)
        return 1
    try:
        print(to_json_text(a) if args.json else text_table(a))
        sys.stdout.flush()
    except BrokenPipeError:          # e.g. `raildyn assess out.h5 | head`: the reader left
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


if __name__ == "__main__":
    sys.exit(main())
