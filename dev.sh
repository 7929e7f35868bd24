#!/usr/bin/env bash
# raildyn developer/user entry point.
#
#   ./dev.sh run    install what is missing, build, run the default scene (inputs/default.nml)
#   ./dev.sh test   install what is missing, build, run the whole test suite (ctest: Fortran
#                   test programs and pytest)
#
# Both are idempotent and fast when nothing changed. Other sub-commands:
#   ./dev.sh setup  only install/check the dependencies
#   ./dev.sh build  setup + configure + build
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build_dir="${RAILDYN_BUILD_DIR:-$here/build}"
build_type="${RAILDYN_BUILD_TYPE:-Release}"

cmd="${1:-}"
case "$cmd" in
  setup) "$here/scripts/setup.sh" ;;
  build|run|test)
    if [ "$cmd" = test ]; then "$here/scripts/setup.sh" --tests; else "$here/scripts/setup.sh"; fi
    python="$("$here/scripts/setup.sh" --python)"
    if [ ! -f "$build_dir/CMakeCache.txt" ]; then
      cmake -S "$here" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
            -DPython3_EXECUTABLE="$python"
    fi
    cmake --build "$build_dir" --parallel
    case "$cmd" in
      run)
        shift
        out_dir="$here/out"
        mkdir -p "$out_dir"
        exec "$build_dir/bin/raildyn" run "$here/inputs/default.nml" -o "$out_dir/default.h5" "$@" ;;
      test)
        exec ctest --test-dir "$build_dir" --output-on-failure ;;
    esac ;;
  *)
    echo "usage: ./dev.sh run | test | build | setup" >&2
    exit 2 ;;
esac
