#!/bin/sh
# Build and run the contact geometry benchmark, print its table and write it into
# docs/performance.md between <!-- BEGIN contact_geometry --> and <!-- END contact_geometry -->.
# BUILD_DIR (default build-bench) is configured in Release; BENCH_EXE skips the build.
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${BUILD_DIR:-$ROOT/build-bench}
EXE=${BENCH_EXE:-}
if [ -z "$EXE" ]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
  cmake --build "$BUILD" --target bench_contact_geometry >/dev/null
  EXE=$BUILD/bench/bench_contact_geometry
fi
OUT=$(mktemp)
"$EXE" > "$OUT"
printf '\nHost: %s CPUs, load average %s at the end of the run; absolute times vary with the\nload (shared machine), ratios within one run are the figures to compare.\n' \
  "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" >> "$OUT"
cat "$OUT"
/usr/bin/python3 - "$ROOT/docs/performance.md" "$OUT" <<'PY'
import sys, pathlib
doc, table = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]).read_text().rstrip() + "\n"
begin, end = "<!-- BEGIN contact_geometry -->", "<!-- END contact_geometry -->"
text = doc.read_text() if doc.exists() else "# Performance\n\nMeasured by the scripts in bench/.\n"
block = f"{begin}\n{table}{end}"
if begin in text and end in text:
    head, rest = text.split(begin, 1)
    text = head + block + rest.split(end, 1)[1]
else:
    text = text.rstrip() + "\n\n" + block + "\n"
doc.write_text(text)
PY
rm -f "$OUT"
