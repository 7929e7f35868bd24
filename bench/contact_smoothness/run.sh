#!/bin/sh
# The contact smoothness benchmark: jumps and kinks of the contact outputs along pose and
# creepage sweeps per fidelity level; tables printed and written into docs/performance.md.
exec "$(dirname "$0")/../run_fortran_bench.sh" contact_smoothness "### Contact force smoothness (bench/contact_smoothness)"
