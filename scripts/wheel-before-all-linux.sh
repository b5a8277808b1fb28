#!/usr/bin/env bash
# cibuildwheel's before-all step of the linux-x64 leg (.github/workflows/wheels.yml), in the
# manylinux_2_28 container (AlmaLinux 8): Eigen from the distribution, SuiteSparse 7.10.1's source
# from its release tarball (the same version `make test-cholmod-source` fetches from Debian) into
# /tmp/suitesparse/src, for CHOLMOD built from source (BDINTERP_SUITESPARSE_SOURCE).
#   scripts/wheel-before-all-linux.sh [TARBALL]   a local tarball instead of the download
set -euo pipefail
version=7.10.1
out=/tmp/suitesparse
if command -v dnf >/dev/null; then dnf install -y -q eigen3-devel; fi
[ -f "$out/src/CHOLMOD/Include/cholmod.h" ] && exit 0
mkdir -p "$out"
tarball=${1:-/tmp/SuiteSparse-$version.tar.gz}
[ -f "$tarball" ] || curl -fsSL -o "$tarball" "https://github.com/DrTimothyAldenDavis/SuiteSparse/archive/refs/tags/v$version.tar.gz"
tar -xf "$tarball" -C "$out"
mv "$out"/SuiteSparse-* "$out/src" 2>/dev/null || true
[ -f "$out/src/CHOLMOD/Include/cholmod.h" ] || { echo "no CHOLMOD in $tarball" >&2; exit 1; }
