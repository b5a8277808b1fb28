#!/usr/bin/env bash
# The add-on suite in a Debian chroot that has only blender and python3-numpy (+ EGL for headless
# rendering) installed from the distribution, on the extension zip: run_blender_tests.py validates
# it, installs it with `blender --command extension install-file` and runs the tests.
#   trixie: Debian 13, Blender 4.3 / Python 3.13     sid: Debian unstable, Blender 5.2 LTS / Python 3.14
# pytest comes in as files (Debian 13's python3-pytest & deps, unpacked by build-portable.sh), on
# BDI_PYTEST_PATH. SuiteSparse and METIS, if a build put them into the chroot
# (test-toolchain-chroot.sh), are hidden, so the wheel must bring its own, but for those Blender
# links itself (Debian's Blender 5.2 loads SuiteSparse 7's CHOLMOD through Ceres: the tests check
# that the add-on's module still calls its own). Needs root.
#   scripts/test-blender-chroot.sh trixie|sid EXTENSION_ZIP [pytest args]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
suite=$1; zip=$(realpath "$2"); shift 2
case $suite in trixie) kind=blender ;; sid) kind=blender5 ;;
  *) echo "usage: $0 trixie|sid EXTENSION_ZIP [pytest args]" >&2; exit 2 ;; esac
CHROOT=${BDI_CHROOTS:-$ROOT/build/portable/chroots}/$suite
PYTEST=${BDI_PYTEST_FILES:-$ROOT/build/portable/deps/root/usr/lib/python3/dist-packages}
"$ROOT/scripts/make-chroot.sh" $kind "$CHROOT"
[ -f "$PYTEST/pytest/__init__.py" ] || { echo "no pytest files in $PYTEST: run make portable" >&2; exit 1; }
case $zip in "$ROOT"/*) ;; *) echo "the zip must be inside $ROOT" >&2; exit 1 ;; esac
mkdir -p "$CHROOT/src" "$CHROOT/pytest" "$CHROOT/dev/shm"
args=$(printf " %q" "$@")
start=$(date +%s)
# /proc is mounted for Blender and unmounted after it; the namespace drops every mount at exit.
keep=$(chroot "$CHROOT" ldd /usr/bin/blender | awk '$3 ~ /^\// {print $3}' |
       while read -r f; do chroot "$CHROOT" readlink -f "$f"; done | tr '\n' ' ')
unshare -m --propagation private sh -c "
  . '$ROOT/scripts/hide-libs.sh' && hide_suitesparse '$CHROOT' '$keep' &&
  mount --bind '$ROOT' '$CHROOT/src' && mount -o bind,ro '$PYTEST' '$CHROOT/pytest' &&
  mount -t proc proc '$CHROOT/proc' && mount -t tmpfs tmpfs '$CHROOT/tmp' &&
  mount -t tmpfs tmpfs '$CHROOT/dev/shm'; rc=0
  chroot '$CHROOT' env -i HOME=/tmp PATH=/usr/bin:/bin LANG=C.UTF-8 BDI_PYTEST_PATH=/pytest \
    blender --background --factory-startup --python-exit-code 1 \
    --python /src/tests/blender/run_blender_tests.py -- --extension '/src/${zip#$ROOT/}' $args || rc=\$?
  umount '$CHROOT/proc'; exit \$rc"
echo "test-blender-chroot: $(chroot "$CHROOT" blender --version 2>/dev/null | head -1) suite in $(( $(date +%s) - start )) s"
