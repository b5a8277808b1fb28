#!/usr/bin/env bash
# Runs a Blender Python script in a Debian chroot's Blender (trixie: 4.3 / Python 3.13, sid: 5.2
# LTS / Python 3.14) with this checkout at /src and its wheel for that Python (dist/, from `make
# addon`) importable as bdinterp: the command of the benchmarks' rows for those Blenders. The
# script's paths are relative to the checkout. Needs root.
#   scripts/blender-chroot.sh trixie|sid SCRIPT [-- script args]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
suite=$1 script=$2; shift 2
case $suite in trixie) kind=blender tag=cp313 ;; sid) kind=blender5 tag=cp314 ;;
  *) echo "usage: $0 trixie|sid SCRIPT [-- script args]" >&2; exit 2 ;; esac
CHROOT=${BDI_CHROOTS:-$ROOT/build/portable/chroots}/$suite
"$ROOT/scripts/make-chroot.sh" $kind "$CHROOT"
wheel=$(ls "$ROOT"/dist/bdinterp-*-$tag-$tag-*.whl 2>/dev/null | tail -1)
[ -n "$wheel" ] || { echo "no $tag wheel in dist/: run make addon" >&2; exit 1; }
site=build/chroot-site/$tag
rm -rf "${ROOT:?}/$site" && mkdir -p "$ROOT/$site" "$CHROOT/src"
/usr/bin/python3 -m zipfile -e "$wheel" "$ROOT/$site"
args=$(printf " %q" "$@")
# Blender ignores PYTHONPATH unless told to use the system's environment.
unshare -m --propagation private sh -c "
  mount --bind '$ROOT' '$CHROOT/src' && mount -t proc proc '$CHROOT/proc' &&
  mount -t tmpfs tmpfs '$CHROOT/tmp'; rc=0
  chroot '$CHROOT' env -i HOME=/tmp PATH=/usr/bin:/bin LANG=C.UTF-8 PYTHONPATH=/src/$site \
    blender --python-use-system-env --background --factory-startup --python-exit-code 1 \
    --python '/src/$script' $args || rc=\$?
  umount '$CHROOT/proc'; exit \$rc"
