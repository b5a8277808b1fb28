#!/usr/bin/env bash
# Installs the Debian 12 packages bdinterp needs (idempotent; needs root or sudo).
#   scripts/setup-debian.sh        everything: build, test and run on every target (`make setup`)
#   scripts/setup-debian.sh demo   only what `make demo` needs: the host module and Blender 3.4
set -euo pipefail
demo=(
  build-essential cmake ccache
  libsuitesparse-dev libeigen3-dev libopenblas0-pthread   # CHOLMOD (fast BLAS for its supernodal path), Eigen
  python3-dev pybind11-dev python3-numpy                  # the compiled module for /usr/bin/python3
  blender libegl1 libegl-mesa0                            # the add-on's host (Debian's 3.4.1, Python 3.11), headless rendering
)
rest=(
  pkg-config
  libgtest-dev libbenchmark-dev                           # C++ tests and benchmarks
  python3-pip python3-setuptools python3-pybind11
  python3-scipy python3-matplotlib python3-pytest python3-pil
  python3-hypothesis                                      # the property-based fuzzer of the painting readers
  debootstrap patchelf binutils                           # portable modules: Debian 11/13 chroots, bundling, audit
  xvfb xauth nodejs                                       # panels in a real window; the Flamenco job compiled in node
  clang libclang-rt-14-dev                                # fuzz targets (libFuzzer) and the ASan/UBSan test build
  g++-mingw-w64-x86-64-posix wine64 googletest            # make test-windows: MinGW-w64 cross build, Wine, GoogleTest source
  libc++-dev libc++abi-dev                                # make test-libcxx: clang with libc++ (Apple's C++ library)
  libcgal-dev                                             # the sprite mesher (CGAL 2D mesher, header-only; its Boost headers)
)
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
case "${1:-all}" in
  demo) packages=("${demo[@]}") ;;
  all)  packages=("${demo[@]}" "${rest[@]}") ;;
  *) echo "usage: $0 [demo]" >&2; exit 2 ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  $SUDO apt-get update -qq
  # --force-unsafe-io: dpkg skips an fsync per file; unpacking ~500 packages is I/O-bound without it
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
      -o Dpkg::Options::=--force-unsafe-io "${missing[@]}"
fi
# tests/runtime: three.js and Khronos' glTF validator for node, at the versions of tests/node/package-lock.json
[ "${1:-all}" = demo ] && exit 0
command -v npm >/dev/null || DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends npm
npm ci --prefix "$(dirname "$0")/../tests/node" --no-audit --no-fund --loglevel=error
