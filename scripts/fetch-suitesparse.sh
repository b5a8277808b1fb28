#!/usr/bin/env bash
# Fetches Debian 13's SuiteSparse 7 source (apt-get source in the trixie chroot DIR; this mirror
# answers 404 for the .dsc, so the orig and debian tarballs are unpacked here instead of by
# dpkg-source) into OUT: OUT/src (the SuiteSparse tree) and OUT/copyright (Debian's DEP-5 file,
# naming the licence of every part, the METIS copy in CHOLMOD among them). Idempotent; needs root.
#   scripts/fetch-suitesparse.sh OUT TRIXIE_CHROOT
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
out=$1 chroot=$2
[ -f "$out/.done" ] && exit 0
rm -rf "$out"; mkdir -p "$out"
grep -q "^deb-src" "$chroot/etc/apt/sources.list.d/bdi-src.list" 2>/dev/null || {
  sed -n 's/^deb /deb-src /p' "$chroot/etc/apt/sources.list" >"$chroot/etc/apt/sources.list.d/bdi-src.list"
  rm -f "$chroot/var/lib/apt/.bdi-updated"; }
# apt fails on the missing .dsc after it has fetched the tarballs: the tarballs are what is checked.
"$ROOT/scripts/chroot-apt.sh" "$chroot" source --download-only suitesparse >"$out.log" 2>&1 || true
mv "$chroot"/tmp/suitesparse_*.orig.tar.xz "$chroot"/tmp/suitesparse_*.debian.tar.xz "$out/" \
  || { tail -5 "$out.log" >&2; echo "fetch-suitesparse: no SuiteSparse source from apt" >&2; exit 1; }
tar -xf "$out"/suitesparse_*.orig.tar.xz -C "$out"
mv "$out"/SuiteSparse-* "$out/src"
tar -xf "$out"/suitesparse_*.debian.tar.xz -C "$out" debian/copyright
mv "$out/debian/copyright" "$out/copyright" && rmdir "$out/debian"
[ -f "$out/src/CHOLMOD/Include/cholmod.h" ] || { echo "fetch-suitesparse: no CHOLMOD in the source" >&2; exit 1; }
touch "$out/.done"
echo "fetch-suitesparse: $(ls "$out"/suitesparse_*.orig.tar.xz | xargs -n1 basename) in $out/src"
