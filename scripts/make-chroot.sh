#!/usr/bin/env bash
# Makes a Debian chroot with debootstrap (idempotent: a finished chroot is kept), needs root.
#   scripts/make-chroot.sh build DIR   Debian 11 (bullseye): g++ 10, cmake 3.18, glibc 2.31 and the
#                                       OpenBLAS the portable modules link (CHOLMOD: from source)
#   scripts/make-chroot.sh blender DIR Debian 13 (trixie): only blender + python3-numpy (+ EGL for
#                                       headless rendering) - Blender 4.3 with Python 3.13
#   scripts/make-chroot.sh blender5 DIR Debian unstable (sid): the same packages - Blender 5.2 LTS with
#                                       Python 3.14 (and Eigen 5, SuiteSparse 7, pybind11 3, numpy 2
#                                       for scripts/test-toolchain-chroot.sh)
set -euo pipefail
kind=$1 dir=$2
# debootstrap's own default mirror unless DEBIAN_MIRROR names another.
mirror=()
[ -n "${DEBIAN_MIRROR:-}" ] && mirror=("$DEBIAN_MIRROR")
case $kind in
  build)   suite=bullseye
           pkgs=g++,make,cmake,ccache,libopenblas-dev,libeigen3-dev,gfortran,patchelf,libcgal-dev ;;
  blender) suite=trixie
           pkgs=blender,python3-numpy,libegl1,libegl-mesa0 ;;
  blender5) suite=sid  # + what Blender 5.2 imports at start (cattrs, requests) and renders with
           pkgs=blender,python3-numpy,libegl1,libegl-mesa0,python3-cattr,python3-requests,libgl1,libopengl0 ;;
  *) echo "usage: $0 build|blender|blender5 DIR" >&2; exit 2 ;;
esac
if [ -f "$dir/.bdinterp-done" ]; then exit 0; fi
rm -rf "$dir"; mkdir -p "$dir"
start=$(date +%s)
rc=0
debootstrap --variant=minbase --include="$pkgs" "$suite" "$dir" "${mirror[@]}" >"$dir.log" 2>&1 || rc=$?
if [ $rc -ne 0 ] && [ "$suite" != sid ]; then tail -20 "$dir.log" >&2; exit 1; fi
if [ "$suite" = sid ]; then
  # debootstrap fails to configure blender there (one dependency is virtual) and the mirror's
  # unstable Release file is past its Valid-Until date: apt finishes the install inside.
  "$(dirname "$0")/chroot-apt.sh" "$dir" install -f libopenexr-3-4-33 >>"$dir.log" 2>&1 \
    || { tail -20 "$dir.log" >&2; exit 1; }
  chroot "$dir" blender --version >/dev/null || { echo "blender does not start in $dir" >&2; exit 1; }
fi
touch "$dir/.bdinterp-done"
echo "chroot $suite ($kind) in $dir: $(( $(date +%s) - start )) s"
