#!/usr/bin/env bash
# Installs every Debian 12 package bdinterp needs to build, test and run (idempotent; needs root or sudo).
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libsuitesparse-dev libeigen3-dev libopenblas0-pthread   # CHOLMOD (fast BLAS for its supernodal path), Eigen
  libgtest-dev libbenchmark-dev                           # C++ tests and benchmarks
  python3-dev python3-pip python3-setuptools python3-pybind11 pybind11-dev
  python3-numpy python3-scipy python3-matplotlib python3-pytest python3-pil
  blender                                                 # the add-on's host (Debian's 3.4.1, Python 3.11)
  debootstrap patchelf binutils                           # portable modules: Debian 11/13 chroots, bundling, audit
  xvfb xauth nodejs                                       # panels in a real window; the Flamenco job compiled in node
  clang libclang-rt-14-dev                                # fuzz targets (libFuzzer) and the ASan/UBSan test build
  g++-mingw-w64-x86-64-posix wine64 googletest            # make test-windows: MinGW-w64 cross build, Wine, GoogleTest source
  libc++-dev libc++abi-dev                                # make test-libcxx: clang with libc++ (Apple's C++ library)
  libcgal-dev                                             # the sprite mesher (CGAL 2D mesher, header-only; its Boost headers)
)
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# tests/runtime: three.js and Khronos' glTF validator for node, at the versions of tests/node/package-lock.json
command -v npm >/dev/null || DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends npm
npm ci --prefix "$(dirname "$0")/../tests/node" --no-audit --no-fund --loglevel=error
