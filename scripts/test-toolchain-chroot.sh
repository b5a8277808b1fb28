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
"$ROOT/scripts/chroot-apt.sh" "$CHROOT" install g++ make cmake pkg-config libsuitesparse-dev \
  libeigen3-dev libopenblas0-pthread pybind11-dev python3-dev python3-pytest python3-scipy \
  python3-matplotlib \
  libgtest-dev >"$CHROOT.toolchain.log" 2>&1 || { tail -20 "$CHROOT.toolchain.log" >&2; exit 1; }
echo "test-toolchain: packages in $(( $(date +%s) - start )) s"
mkdir -p "$CHROOT/src" "$CHROOT/dev/shm"
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
  mount -t tmpfs tmpfs '$CHROOT/tmp' && mount -t tmpfs tmpfs '$CHROOT/dev/shm'; rc=0
  chroot '$CHROOT' env -i HOME=/tmp PATH=/usr/bin:/bin LANG=C.UTF-8 JOBS=${JOBS:-2} \
    sh /bdi-toolchain.sh $args || rc=\$?
  umount '$CHROOT/proc'; exit \$rc"
echo "test-toolchain: passed in $(( $(date +%s) - start )) s"
