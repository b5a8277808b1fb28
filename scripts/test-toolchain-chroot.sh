#!/usr/bin/env bash
# The library, the Python module and their tests built and run with Debian unstable's toolchain:
# Eigen 5, SuiteSparse 7, pybind11 3, Python 3.14 and numpy 2 (the sid chroot of the Blender 5.2
# suite, with the build packages added by apt). Needs root (chroot, mount namespace).
#   scripts/test-toolchain-chroot.sh [pytest args]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
CHROOT=${BDI_CHROOTS:-$ROOT/build/portable/chroots}/sid
start=$(date +%s)
"$ROOT/scripts/make-chroot.sh" blender5 "$CHROOT"
"$ROOT/scripts/chroot-apt.sh" "$CHROOT" install g++ make cmake ccache pkg-config libsuitesparse-dev \
  libeigen3-dev libopenblas0-pthread pybind11-dev python3-dev python3-pytest python3-scipy \
  python3-matplotlib python3-hypothesis \
  libgtest-dev >"$CHROOT.toolchain.log" 2>&1 || { tail -20 "$CHROOT.toolchain.log" >&2; exit 1; }
echo "test-toolchain: packages in $(( $(date +%s) - start )) s"
# ccache's cache kept on this machine outside the clone (BDI_CCACHE_DIR), as for the portable build:
# /src and /bdi-build are the same in every clone, so a later run compiles only what changed.
CACHE=${BDI_CCACHE_DIR:-/var/cache/bdinterp}/sid
mkdir -p "$CHROOT/src" "$CHROOT/dev/shm" "$CHROOT/ccache" "$CACHE"
# The in-tree package is copied next to the build so that its 3.14 module goes there, not into
# the checkout; the checkout is mounted read-only.
cat >"$CHROOT/bdi-toolchain.sh" <<'EOS'
set -e
echo "test-toolchain: $(dpkg-query -W -f='${Package} ${Version}; ' libeigen3-dev libsuitesparse-dev \
  pybind11-dev python3-numpy python3)"
rm -rf /bdi-py && mkdir -p /bdi-py && cp -r /src/python/bdinterp /bdi-py/ && rm -f /bdi-py/bdinterp/_core*.so
cmake -S /src -B /bdi-build -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=/usr/bin/python3 -DBDINTERP_SPRITE=OFF \
  -DBDINTERP_PYTHON_OUTPUT_DIR=/bdi-py/bdinterp >/bdi-cmake.log 2>&1 || { tail -40 /bdi-cmake.log; exit 1; }
cmake --build /bdi-build -j "${JOBS:-2}" >>/bdi-cmake.log 2>&1 || { tail -40 /bdi-cmake.log; exit 1; }
cd /bdi-build && { ctest --output-on-failure -j "${JOBS:-2}" >/bdi-ctest.log 2>&1 || { cat /bdi-ctest.log; exit 1; }; }
grep -E "tests passed|tests failed" /bdi-ctest.log
# the installed package (bdinterpConfig.cmake finds Eigen 5) works for a stand-alone project
cmake --install /bdi-build --prefix /bdi-prefix >/dev/null
cmake -S /src/examples/cpp -B /bdi-example -DCMAKE_PREFIX_PATH=/bdi-prefix >/dev/null
cmake --build /bdi-example >/dev/null && /bdi-example/bend_bar | tail -1
cd /src/tests && PYTHONPATH=/bdi-py python3 -m pytest -p no:cacheprovider python "$@"
EOS
args=$(printf " %q" "$@")
unshare -m --propagation private sh -c "
  mount -o bind,ro '$ROOT' '$CHROOT/src' && mount -t proc proc '$CHROOT/proc' &&
  mount -t tmpfs tmpfs '$CHROOT/tmp' && mount -t tmpfs tmpfs '$CHROOT/dev/shm' &&
  mount --bind '$CACHE' '$CHROOT/ccache'; rc=0
  chroot '$CHROOT' env -i HOME=/tmp PATH=/usr/bin:/bin LANG=C.UTF-8 JOBS=${JOBS:-2} CCACHE_DIR=/ccache \
    CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache \
    sh /bdi-toolchain.sh $args || rc=\$?
  umount '$CHROOT/proc'; exit \$rc"
echo "test-toolchain: passed in $(( $(date +%s) - start )) s"
