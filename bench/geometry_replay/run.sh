#!/bin/sh
# The geometry replay benchmark: the online strip geometry of both wheels at the wheelset
# poses of the acceptance deck's run (inputs/manchester_v1_tc1.nml, ~20 CPU s, or RESULTS=FILE
# of an earlier run of it), table printed and written into docs/performance.md.
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${BUILD_DIR:-$ROOT/build-bench}
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build "$BUILD" --target bench_geometry_replay raildyn_exe >/dev/null
TMP=$(mktemp -d)
RES=${RESULTS:-}
if [ -z "$RES" ]; then
  RES=$TMP/run.h5
  "$BUILD/bin/raildyn" run "$ROOT/inputs/manchester_v1_tc1.nml" -o "$RES" --quiet
fi
/usr/bin/python3 "$ROOT/bench/geometry_replay/poses.py" "$RES" "$TMP/poses.txt" >/dev/null
OUT=$TMP/table.md
"$BUILD/bench/bench_geometry_replay" "$TMP/poses.txt" 5 > "$OUT"
printf '\nHost: %s CPUs, load average %s at the end of the run; absolute times vary with the\nload (shared machine), ratios within one run are the figures to compare.\n' \
  "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" >> "$OUT"
cat "$OUT"
/usr/bin/python3 "$ROOT/bench/performance_section.py" geometry_replay "$OUT"
rm -rf "$TMP"
