#!/usr/bin/env bash
# The linux-x64 leg of .github/workflows/wheels.yml, as far as it runs here: its before-all step
# (scripts/wheel-before-all-linux.sh, given Debian's SuiteSparse tarball instead of the download)
# and its build command (pip wheel with BDINTERP_CORE=source and CHOLMOD from that source); the
# wheel then passes the Python suite with the host's SuiteSparse and METIS hidden. Not run here:
# the manylinux container, cibuildwheel itself and auditwheel's repair. Needs root.
#   scripts/test-wheel-source.sh WORKDIR SUITESPARSE_DIR (scripts/fetch-suitesparse.sh's OUT)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
work=$(mkdir -p "$1" && cd "$1" && pwd)
tarball=$(ls "$2"/suitesparse_*.orig.tar.xz)
start=$(date +%s)
rm -rf "$work/wheel" "$work/site"
bash "$ROOT/scripts/wheel-before-all-linux.sh" "$tarball"
cd "$ROOT"
BDINTERP_CORE=source BDINTERP_SUITESPARSE_SOURCE=/tmp/suitesparse/src CMAKE_BUILD_PARALLEL_LEVEL=${JOBS:-2} \
  /usr/bin/python3 -m pip wheel . --no-build-isolation --no-deps -q -w "$work/wheel"
wheel=$(ls "$work"/wheel/bdinterp-*-cp311-cp311-linux_x86_64.whl)
/usr/bin/python3 -m pip install --no-deps --no-index --break-system-packages -q --target "$work/site" "$wheel"
if nm -D --defined-only "$work"/site/bdinterp/_core*.so | grep -q " cholmod_"; then
  echo "test-wheel-source: the module exports CHOLMOD's symbols" >&2; exit 1
fi
cd tests
"$ROOT/scripts/without-host-libs.sh" env PYTHONPATH="$work/site" /usr/bin/python3 -c \
  'import bdinterp, sys; assert bdinterp.__file__.startswith(sys.argv[1]), bdinterp.__file__' "$work/site"
"$ROOT/scripts/without-host-libs.sh" env PYTHONPATH="$work/site" /usr/bin/python3 -m pytest -q \
  -p no:cacheprovider python
echo "test-wheel-source: $(basename "$wheel") built and tested in $(( $(date +%s) - start )) s"
