#!/usr/bin/env bash
# Builds the shipped compiled modules bdinterp/_core for CPython 3.11 and 3.13 (linux-x64) in a
# Debian 11 chroot (glibc 2.31, g++ 10), self-contained (cmake/Portable.cmake), audits them and
# collects the licences of everything linked in.  Needs root (debootstrap, chroot, mount namespace).
#
#   scripts/build-portable.sh [OUT]     default OUT: build/portable
#     OUT/py311/_core.cpython-311-x86_64-linux-gnu.so, OUT/py313/..., OUT/licenses/*
#
# Chroots: $BDI_CHROOTS (default OUT/chroots; CI makes them afresh in the clone): bullseye (build)
# and trixie (Blender 4.3; here only its apt fetches the headers Debian 11 lacks: Python 3.13,
# pybind11 2.13 - 3.13 needs >= 2.12 -, Eigen 3.4). Python 3.11's headers are the host's (Debian 12).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
OUT=$(mkdir -p "${1:-$ROOT/build/portable}" && cd "${1:-$ROOT/build/portable}" && pwd)
CHROOTS=${BDI_CHROOTS:-$OUT/chroots}
BUILDER=$CHROOTS/bullseye FETCHER=$CHROOTS/trixie
start=$(date +%s)
"$ROOT/scripts/make-chroot.sh" build "$BUILDER" &
"$ROOT/scripts/make-chroot.sh" blender "$FETCHER" &
wait %1 && wait %2

# Headers from Debian 13 (apt-get download + dpkg -x: nothing is installed in either chroot).
DEPS=$OUT/deps
if [ ! -f "$DEPS/.done" ]; then
  rm -rf "$DEPS"; mkdir -p "$DEPS/debs"
  cp -L /etc/resolv.conf "$FETCHER/etc/resolv.conf"
  # apt as root without its _apt sandbox user (which cannot write into the chroot's /tmp/debs)
  chroot "$FETCHER" sh -c 'apt-get update -qq && mkdir -p /tmp/debs && cd /tmp/debs &&
    apt-get -o APT::Sandbox::User=root download -qq libpython3.13-dev pybind11-dev libeigen3-dev \
      python3-pytest python3-pluggy python3-iniconfig python3-packaging'
  mv "$FETCHER"/tmp/debs/*.deb "$DEPS/debs/"
  for deb in "$DEPS"/debs/*.deb; do dpkg -x "$deb" "$DEPS/root"; done
  touch "$DEPS/.done"
fi
mkdir -p "$DEPS/root/usr/include/py311/x86_64-linux-gnu"  # Debian's pyconfig.h includes the triplet's
cp -r /usr/include/python3.11 "$DEPS/root/usr/include/py311/"
cp -r /usr/include/x86_64-linux-gnu/python3.11 "$DEPS/root/usr/include/py311/x86_64-linux-gnu/"

rm -rf "$OUT"/py3*  # relinked and re-bundled every time (bundling rewrites the module)
# One build tree, configured once per Python: the library is compiled once, the bindings twice.
mkdir -p "$BUILDER/src" "$BUILDER/deps" "$BUILDER/out"
build_one() {  # $1 = 311 | 313, $2 = Python include dirs (;-separated, chroot paths)
  cat <<EOS
cmake -S /src -B /out/cmake -DCMAKE_BUILD_TYPE=Release -DBDINTERP_PORTABLE=ON -DBDINTERP_TESTS=OFF \
  -DEigen3_DIR=/deps/usr/share/eigen3/cmake -DBDINTERP_PYBIND11_INCLUDE_DIR=/deps/usr/include \
  -DBDINTERP_PYTHON_INCLUDE_DIR="$2" -DBDINTERP_PYTHON_EXT_SUFFIX=.cpython-$1-x86_64-linux-gnu.so \
  -DBDINTERP_PYTHON_OUTPUT_DIR=/out/py$1 >/out/cmake-py$1.log 2>&1
cmake --build /out/cmake -j ${JOBS:-2} --target _core >>/out/cmake-py$1.log 2>&1
EOS
}
script="set -e
$(build_one 311 "/deps/usr/include/py311/python3.11;/deps/usr/include/py311")
$(build_one 313 "/deps/usr/include/python3.13;/deps/usr/include")"
unshare -m sh -c "mount --bind '$ROOT' '$BUILDER/src' && mount -o bind,ro '$DEPS/root' '$BUILDER/deps' &&
  mount --bind '$OUT' '$BUILDER/out' && chroot '$BUILDER' sh -c '$script'" \
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
for pkg in libcholmod3 libamd2 libcamd2 libcolamd2 libccolamd2 libsuitesparseconfig5 libmetis5 \
           libopenblas0-pthread libgfortran5 libquadmath0 libgomp1 libstdc++6 libgcc-s1; do
  cp "$BUILDER/usr/share/doc/$pkg/copyright" "$OUT/licenses/$pkg.copyright"
done
for pkg in libeigen3-dev pybind11-dev; do
  cp "$DEPS/root/usr/share/doc/$pkg/copyright" "$OUT/licenses/$pkg.copyright"
done
/usr/bin/python3 "$ROOT/scripts/audit_so.py" "$OUT"/py3*/*.so*
echo "portable modules in $OUT: $(( $(date +%s) - start )) s"
