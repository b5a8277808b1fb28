#!/usr/bin/env bash
# Builds the shipped compiled modules bdinterp/_core for CPython 3.11, 3.13 and 3.14 (linux-x64) in a
# Debian 11 chroot (glibc 2.31, g++ 10), self-contained (cmake/Portable.cmake), audits them and
# collects the licences of everything linked in.  Needs root (debootstrap, chroot, mount namespace).
#
#   scripts/build-portable.sh [OUT]     default OUT: build/portable
#     OUT/py311/_core.cpython-311-x86_64-linux-gnu.so, OUT/py313/..., OUT/py314/..., OUT/licenses/*
#
# Chroots: $BDI_CHROOTS (default OUT/chroots; CI makes them afresh in the clone): bullseye (build),
# trixie (Blender 4.3) and sid (Blender 5.2). Here only their apt fetches the headers Debian 11
# lacks: from trixie Python 3.13, pybind11 2.13 (3.13 needs >= 2.12) and Eigen 3.4; from sid
# Python 3.14 and pybind11 3.1 (3.14 needs >= 3.0); from trixie also SuiteSparse 7's source, for
# the CHOLMOD linked into the modules. Python 3.11's headers are the host's.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=$(mkdir -p "${1:-$ROOT/build/portable}" && cd "${1:-$ROOT/build/portable}" && pwd)
CHROOTS=${BDI_CHROOTS:-$OUT/chroots}
BUILDER=$CHROOTS/bullseye FETCHER=$CHROOTS/trixie FETCHER5=$CHROOTS/sid
start=$(date +%s)
"$ROOT/scripts/make-chroot.sh" build "$BUILDER" &
"$ROOT/scripts/make-chroot.sh" blender "$FETCHER" &
"$ROOT/scripts/make-chroot.sh" blender5 "$FETCHER5" &
wait %1 && wait %2 && wait %3

# Debian packages' files, unpacked into $1/root (apt-get download + dpkg -x: nothing is installed).
fetch_debs() {  # $1 = folder, $2 = chroot whose apt fetches, $3... = packages
  local deps=$1 chroot=$2; shift 2
  [ -f "$deps/.done" ] && return 0
  rm -rf "$deps"; mkdir -p "$deps/debs"
  "$ROOT/scripts/chroot-apt.sh" "$chroot" download "$@"
  mv "$chroot"/tmp/*.deb "$deps/debs/"
  for deb in "$deps"/debs/*.deb; do dpkg -x "$deb" "$deps/root"; done
  touch "$deps/.done"
}
DEPS=$OUT/deps DEPS5=$OUT/deps-sid
fetch_debs "$DEPS" "$FETCHER" libpython3.13-dev pybind11-dev libeigen3-dev \
  python3-pytest python3-pluggy python3-iniconfig python3-packaging
fetch_debs "$DEPS5" "$FETCHER5" libpython3.14-dev pybind11-dev
# CHOLMOD is built from Debian 13's SuiteSparse 7 source and linked in with hidden symbols.
SUITESPARSE=$OUT/suitesparse
"$ROOT/scripts/fetch-suitesparse.sh" "$SUITESPARSE" "$FETCHER"
mkdir -p "$DEPS/root/usr/include/py311/x86_64-linux-gnu"  # Debian's pyconfig.h includes the triplet's
cp -r /usr/include/python3.11 "$DEPS/root/usr/include/py311/"
cp -r /usr/include/x86_64-linux-gnu/python3.11 "$DEPS/root/usr/include/py311/x86_64-linux-gnu/"

rm -rf "$OUT"/py3*  # relinked and re-bundled every time (bundling rewrites the module)
# One build tree, configured once per Python: the library is compiled once, the bindings twice.
mkdir -p "$BUILDER/src" "$BUILDER/deps" "$BUILDER/deps5" "$BUILDER/suitesparse" "$BUILDER/out"
build_one() {  # $1 = 311 | 313 | 314, $2 = Python include dirs (;-separated, chroot paths), $3 = pybind11's
  cat <<EOS
cmake -S /src -B /out/cmake -DCMAKE_BUILD_TYPE=Release -DBDINTERP_PORTABLE=ON -DBDINTERP_TESTS=OFF -DBDINTERP_SPRITE=ON \
  -DEigen3_DIR=/deps/usr/share/eigen3/cmake -DBDINTERP_PYBIND11_INCLUDE_DIR=$3 \
  -DBDINTERP_SUITESPARSE_SOURCE=/suitesparse \
  -DBDINTERP_PYTHON_INCLUDE_DIR="$2" -DBDINTERP_PYTHON_EXT_SUFFIX=.cpython-$1-x86_64-linux-gnu.so \
  -DBDINTERP_PYTHON_OUTPUT_DIR=/out/py$1 >/out/cmake-py$1.log 2>&1
cmake --build /out/cmake -j ${JOBS:-2} --target _core >>/out/cmake-py$1.log 2>&1
EOS
}
script="set -e
$(build_one 311 "/deps/usr/include/py311/python3.11;/deps/usr/include/py311" /deps/usr/include)
$(build_one 313 "/deps/usr/include/python3.13;/deps/usr/include" /deps/usr/include)
$(build_one 314 "/deps5/usr/include/python3.14;/deps5/usr/include" /deps5/usr/include)"
# ccache where the chroot has it (make-chroot.sh installs it), its cache kept on this machine outside
# the clone (BDI_CCACHE_DIR): the chroot's paths are the same in every clone, so a later run
# compiles only what changed. Without it, the host's launcher (the Makefile's) is dropped.
launch="-u CMAKE_C_COMPILER_LAUNCHER -u CMAKE_CXX_COMPILER_LAUNCHER" cache=true
if [ -x "$BUILDER/usr/bin/ccache" ]; then
  mkdir -p "${BDI_CCACHE_DIR:-/var/cache/bdinterp}/bullseye" "$BUILDER/ccache"
  launch="CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache CCACHE_DIR=/ccache"
  cache="mount --bind '${BDI_CCACHE_DIR:-/var/cache/bdinterp}/bullseye' '$BUILDER/ccache'"
fi
unshare -m sh -c "mount --bind '$ROOT' '$BUILDER/src' && mount -o bind,ro '$DEPS/root' '$BUILDER/deps' &&
  mount -o bind,ro '$DEPS5/root' '$BUILDER/deps5' && mount -o bind,ro '$SUITESPARSE/src' '$BUILDER/suitesparse' &&
  mount --bind '$OUT' '$BUILDER/out' && $cache &&
  chroot '$BUILDER' env $launch sh -c '$script'" \
  || { tail -30 "$OUT"/cmake-py3*.log >&2; exit 1; }

# Everything outside the manylinux set, bundled next to each module under private names.
for so in "$OUT"/py3*/_core*.so; do
  unshare -m sh -c "mount --bind '$OUT' '$BUILDER/out' && chroot '$BUILDER' ldd /out/${so#$OUT/}" \
    >"$so.ldd"
  /usr/bin/python3 "$ROOT/scripts/bundle_libs.py" "$so" "$so.ldd" "$BUILDER"
  rm "$so.ldd"
done

# The licences of what the modules carry (Debian's copyright files name every upstream licence).
rm -rf "$OUT/licenses"; mkdir -p "$OUT/licenses"
cp "$ROOT/LICENSE" "$OUT/licenses/bdinterp-LICENSE"
cp "$SUITESPARSE/copyright" "$OUT/licenses/suitesparse.copyright"
for pkg in libopenblas0-pthread libgfortran5 libquadmath0 libgomp1 libstdc++6 libgcc-s1; do
  cp "$BUILDER/usr/share/doc/$pkg/copyright" "$OUT/licenses/$pkg.copyright"
done
for pkg in libeigen3-dev pybind11-dev; do
  cp "$DEPS/root/usr/share/doc/$pkg/copyright" "$OUT/licenses/$pkg.copyright"
done
cp "$DEPS5/root/usr/share/doc/pybind11-dev/copyright" "$OUT/licenses/pybind11-3-dev.copyright"
/usr/bin/python3 "$ROOT/scripts/audit_so.py" "$OUT"/py3*/*.so*
echo "portable modules in $OUT: $(( $(date +%s) - start )) s"
