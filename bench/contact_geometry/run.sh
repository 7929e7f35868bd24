#!/bin/sh
# The contact_geometry benchmark: table printed and written into docs/performance.md.
exec "$(dirname "$0")/../run_fortran_bench.sh" contact_geometry
