#!/usr/bin/env bash
# The add-on suite in Blender 4.3 / Python 3.13 inside a Debian 13 chroot that has only blender and
# python3-numpy (+ EGL for headless rendering) installed, on the extension zip: run_blender_tests.py
# validates it, installs it with `blender --command extension install-file` and runs the tests.
# pytest comes in as files (Debian 13's python3-pytest & deps, unpacked by build-portable.sh), on
# BDI_PYTEST_PATH. Needs root (chroot, mount namespace).
#   scripts/test-blender-chroot.sh EXTENSION_ZIP [pytest args]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
zip=$(realpath "$1"); shift
CHROOT=${BDI_CHROOTS:-$ROOT/build/portable/chroots}/trixie
PYTEST=${BDI_PYTEST_FILES:-$ROOT/build/portable/deps/root/usr/lib/python3/dist-packages}
"$ROOT/scripts/make-chroot.sh" blender "$CHROOT"
[ -f "$PYTEST/pytest/__init__.py" ] || { echo "no pytest files in $PYTEST: run make portable" >&2; exit 1; }
case $zip in "$ROOT"/*) ;; *) echo "the zip must be inside $ROOT" >&2; exit 1 ;; esac
mkdir -p "$CHROOT/src" "$CHROOT/pytest" "$CHROOT/dev/shm"
args=$(printf " %q" "$@")
# /proc is mounted for Blender and unmounted after it; the namespace drops every mount at exit.
unshare -m --propagation private sh -c "
  mount --bind '$ROOT' '$CHROOT/src' && mount -o bind,ro '$PYTEST' '$CHROOT/pytest' &&
  mount -t proc proc '$CHROOT/proc' && mount -t tmpfs tmpfs '$CHROOT/tmp' &&
  mount -t tmpfs tmpfs '$CHROOT/dev/shm'; rc=0
  chroot '$CHROOT' env -i HOME=/tmp PATH=/usr/bin:/bin LANG=C.UTF-8 BDI_PYTEST_PATH=/pytest \
    blender --background --factory-startup --python-exit-code 1 \
    --python /src/tests/blender/run_blender_tests.py -- --extension '/src/${zip#$ROOT/}' $args || rc=\$?
  umount '$CHROOT/proc'; exit \$rc"
