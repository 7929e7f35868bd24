#!/bin/sh
# The contact pipeline benchmark: table printed and written into docs/performance.md.
exec "$(dirname "$0")/../run_fortran_bench.sh" contact_pipeline "## Contact pipeline (bench/contact_pipeline)"
