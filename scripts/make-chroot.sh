#!/usr/bin/env bash
# Makes a Debian chroot with debootstrap (idempotent: a finished chroot is kept), needs root.
#   scripts/make-chroot.sh build DIR   Debian 11 (bullseye): g++ 10, cmake 3.18, glibc 2.31 and the
#                                       static SuiteSparse/METIS/OpenBLAS the portable modules link
#   scripts/make-chroot.sh blender DIR Debian 13 (trixie): only blender + python3-numpy (+ EGL for
#                                       headless rendering) - Blender 4.3 with Python 3.13
set -euo pipefail
kind=$1 dir=$2
# debootstrap's own default mirror unless DEBIAN_MIRROR names another.
mirror=()
[ -n "${DEBIAN_MIRROR:-}" ] && mirror=("$DEBIAN_MIRROR")
case $kind in
  build)   suite=bullseye
           pkgs=g++,make,cmake,libsuitesparse-dev,libmetis-dev,libopenblas-dev,libeigen3-dev,gfortran,patchelf ;;
  blender) suite=trixie
           pkgs=blender,python3-numpy,libegl1,libegl-mesa0 ;;
  *) echo "usage: $0 build|blender DIR" >&2; exit 2 ;;
esac
if [ -f "$dir/.bdinterp-done" ]; then exit 0; fi
rm -rf "$dir"; mkdir -p "$dir"
start=$(date +%s)
debootstrap --variant=minbase --include="$pkgs" "$suite" "$dir" "${mirror[@]}" >"$dir.log" 2>&1 \
  || { tail -20 "$dir.log" >&2; exit 1; }
touch "$dir/.bdinterp-done"
echo "chroot $suite ($kind) in $dir: $(( $(date +%s) - start )) s"
