#!/bin/sh
# Hertz tables vs the elliptic-integral path: accuracy and cost, written into docs/performance.md.
exec "$(dirname "$0")/../run_fortran_bench.sh" hertz_tables "### Hertz tables (bench/hertz_tables)"
