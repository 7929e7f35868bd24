#!/bin/sh
# Build and run the contact pipeline benchmark, print its table and write it into
# docs/performance.md between <!-- BEGIN contact_pipeline --> and <!-- END contact_pipeline -->.
# BUILD_DIR (default build-bench) is configured in Release; BENCH_EXE skips the build.
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${BUILD_DIR:-$ROOT/build-bench}
EXE=${BENCH_EXE:-}
if [ -z "$EXE" ]; then
  cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
  EXE=$BUILD/bench/bench_contact_pipeline
  if ! cmake --build "$BUILD" --target bench_contact_pipeline >/dev/null 2>&1; then
    # bench/CMakeLists.txt does not add this folder yet: build the libraries with CMake and
    # link the program by hand against them.
    cmake --build "$BUILD" --target rd_contact_wheelset >/dev/null
    mkdir -p "$BUILD/bench/contact_pipeline"
    INC=""
    for m in rd_contact_wheelset rd_contact_geometry rd_contact_normal rd_contact_creepage \
             rd_contact_tangential rd_dynamics rd_track rd_common; do
      INC="$INC -I $BUILD/modules/$m"
    done
    gfortran -O2 -ffree-line-length-none -fimplicit-none -J "$BUILD/bench/contact_pipeline" $INC \
      "$ROOT/bench/contact_pipeline/bench_contact_pipeline.f90" -o "$EXE" \
      "$BUILD/src/fortran/contact/wheelset/librd_contact_wheelset.a" \
      "$BUILD/src/fortran/contact/tangential/librd_contact_tangential.a" \
      "$BUILD/src/fortran/contact/creepage/librd_contact_creepage.a" \
      "$BUILD/src/fortran/contact/normal/librd_contact_normal.a" \
      "$BUILD/src/fortran/contact/geometry/librd_contact_geometry.a" \
      "$BUILD/src/fortran/dynamics/librd_dynamics.a" \
      "$BUILD/src/fortran/track/librd_track.a" \
      "$BUILD/src/fortran/common/librd_common.a" -llapack
  fi
fi
OUT=$(mktemp)
"$EXE" > "$OUT"
printf '\nHost: %s CPUs, load average %s at the end of the run; absolute times vary with the load\n(shared machine), ratios within one run are the figures to compare.\n' \
  "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" >> "$OUT"
cat "$OUT"
/usr/bin/python3 - "$ROOT/docs/performance.md" "$OUT" <<'PY'
import sys, pathlib
doc, table = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2]).read_text().rstrip() + "\n"
begin, end = "<!-- BEGIN contact_pipeline -->", "<!-- END contact_pipeline -->"
text = doc.read_text() if doc.exists() else "# Performance\n\nMeasured by the scripts in bench/.\n"
block = f"{begin}\n## Contact pipeline (bench/contact_pipeline)\n\n{table}{end}"
if begin in text and end in text:
    head, rest = text.split(begin, 1)
    text = head + block + rest.split(end, 1)[1]
else:
    text = text.rstrip() + "\n\n" + block + "\n"
doc.write_text(text)
PY
rm -f "$OUT"
