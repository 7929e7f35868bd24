#!/bin/sh
# Build and run the Fortran benchmark bench_NAME (bench/NAME/), print its table and write it
# into its section of docs/performance.md. BUILD_DIR (default build-bench) is configured in
# Release; BENCH_EXE skips the build.
#   bench/run_fortran_bench.sh NAME [TITLE]
set -eu
NAME=$1
TITLE=${2:-}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD_DIR:-$ROOT/build-bench}
EXE=${BENCH_EXE:-}
if [ -z "$EXE" ]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
  cmake --build "$BUILD" --target "bench_$NAME" >/dev/null
  EXE=$BUILD/bench/bench_$NAME
fi
OUT=$(mktemp)
"$EXE" > "$OUT"
printf '\nHost: %s CPUs, load average %s at the end of the run; absolute times vary with the\nload (shared machine), ratios within one run are the figures to compare.\n' \
  "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" >> "$OUT"
cat "$OUT"
/usr/bin/python3 "$ROOT/bench/performance_section.py" "$NAME" "$OUT" "$TITLE"
rm -f "$OUT"
