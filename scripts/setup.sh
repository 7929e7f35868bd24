#!/usr/bin/env bash
# Install what raildyn needs and is missing. On Debian/Ubuntu as root: apt-get install.
# Otherwise: print the exact install line and stop (exit 1).
# `setup.sh --python` prints the Python interpreter the build and tests use.
set -euo pipefail

# Build and run: compilers, LAPACK, SUNDIALS, HDF5, Python with numpy/h5py/matplotlib.
packages=(gfortran gcc cmake ninja-build pkg-config liblapack-dev libsundials-dev libhdf5-dev
          python3 python3-numpy python3-h5py python3-matplotlib)
# `setup.sh --tests` also: pytest, a real single-node Slurm (campaigns as job arrays) and
# headless Chromium (tests/python/test_html_render.py renders the HTML reports).
test_packages=(python3-pytest slurmctld slurmd slurm-client munge chromium)
if [ "${1:-}" = "--tests" ]; then
  packages+=("${test_packages[@]}")
fi

python=/usr/bin/python3

if [ "${1:-}" = "--python" ]; then
  echo "$python"
  exit 0
fi

missing=()
if command -v dpkg-query >/dev/null 2>&1; then
  for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
else
  echo "raildyn setup: this is not a Debian/Ubuntu system. Install: gfortran >= 12, CMake >= 3.24," >&2
  echo "  Ninja, LAPACK, SUNDIALS >= 6.4 (CVODE, ARKODE), HDF5 with Fortran (serial)," >&2
  echo "  Python 3 with numpy, h5py, pytest, matplotlib; for the tests headless Chromium; then rerun." >&2
  for tool in gfortran cmake ninja; do
    command -v "$tool" >/dev/null 2>&1 || { echo "raildyn setup: $tool not found" >&2; exit 1; }
  done
  exit 0
fi

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

line="apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "raildyn setup: missing packages. Run as root:" >&2
  echo "  apt-get update && $line" >&2
  exit 1
fi
echo "raildyn setup: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
