#!/usr/bin/env bash
# Install ppohdem's build and test dependencies from Debian packages (run as root, or with
# sudo available). Idempotent: a machine that already has them only pays for apt-get update.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev                      # Eigen 3.4: vectors, quaternions
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev   # CGAL 5.5: the validation oracle only
  libopenmpi-dev openmpi-bin         # Open MPI 4.1
  libgtest-dev libgmock-dev googletest librapidcheck-dev   # tests
  libbenchmark-dev                   # Google Benchmark
  libtomlplusplus-dev libcli11-dev   # scene files, command line
  python3-matplotlib python3-numpy   # plots in docs/ (system python: /usr/bin/python3)
  liblzma-dev xz-utils               # the original program's outputs, stored as .xz fixtures
  zlib1g-dev                         # CRC-32 of checkpoint files (core/src/dem/checkpoint.cpp)
  yade                               # YADE 2023.02a: `ppohdem validate --live` reruns the YADE
                                     # reference scenes (validation/yade; ~1 min to install here)
  python3-scipy                      # validation/peers/crosscheck.py (k-d tree)
  gfortran                           # bindings/fortran: the original ppohDEM_util modules
  pybind11-dev python3-pytest        # bindings/python: the `ppohdem` module and its tests
  python3-nbconvert python3-ipykernel   # docs/tutorials: notebooks executed by ctest
  clang libomp-14-dev libclang-rt-14-dev   # the Clang 14 build and the libFuzzer targets
)
# The other peer DEM codes only for the benchmark (ci/bench-dem.sh calls `install-deps.sh --peers`).
if [ "${1:-}" = "--peers" ]; then
  PACKAGES+=(liggghts lammps)
fi
# The aarch64 cross build run under qemu-user (docs/portability.md); its zlib is Debian's arm64
# package (multiarch: the arm64 architecture is added to dpkg first).
if [ "${1:-}" = "--cross" ]; then
  PACKAGES+=(g++-aarch64-linux-gnu qemu-user zlib1g-dev:arm64)
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then $SUDO dpkg --add-architecture arm64; fi
fi
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
