#!/usr/bin/env bash
# `pip wheel .` gives the portable build (the same _core file as the shipped wheel, byte for byte),
# it passes the audit, and it installs into a Python without SuiteSparse: the Python test suite runs
# against the installed wheel with the host's SuiteSparse and METIS hidden (needs root).
#   scripts/test-wheel.sh WORKDIR
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
work=$(mkdir -p "$1" && cd "$1" && pwd)
rm -rf "$work/pip" "$work/site"
cd "$ROOT"
BDINTERP_CORE=portable /usr/bin/python3 -m pip wheel . --no-build-isolation --no-deps -q -w "$work/pip"
wheel=$(ls "$work"/pip/bdinterp-*-cp311-cp311-manylinux_2_31_x86_64.whl)
/usr/bin/python3 scripts/audit_so.py "$wheel"
# The audit can fail: Debian 12's numpy module needs libblas.so.3 and GLIBC_2.35.
numpy_so=$(ls /usr/lib/python3/dist-packages/numpy/core/_multiarray_umath.cpython-311-*.so)
if /usr/bin/python3 scripts/audit_so.py "$numpy_so" >"$work/audit-numpy.txt"; then
  echo "test-wheel: the audit passed Debian's numpy module" >&2; exit 1
fi
grep -q "POLICY: needs GLIBC_2.3[2-9] > GLIBC_2.31" "$work/audit-numpy.txt"
grep -q "POLICY: needs libblas.so.3" "$work/audit-numpy.txt"
/usr/bin/python3 - "$wheel" dist/bdinterp-"$(cat VERSION)"-cp311-cp311-manylinux_2_31_x86_64.whl <<'PY'
import hashlib, sys, zipfile
def modules(path):
    with zipfile.ZipFile(path) as zf:
        return {n.split("/")[-1]: hashlib.sha256(zf.read(n)).hexdigest()
                for n in zf.namelist() if ".so" in n}
pip, shipped = map(modules, sys.argv[1:])
assert pip == shipped and pip, "pip wheel %s != shipped wheel %s" % (pip, shipped)
for path in sys.argv[1:]:  # GPL text and the bundled libraries' licences, in both wheels
    names = zipfile.ZipFile(path).namelist()
    for want in ("LICENSE", "suitesparse.copyright",
                 "libopenblas0-pthread.copyright", "libgfortran5.copyright"):
        assert any(n.endswith(want) and ".dist-info/" in n for n in names), (path, want)
print("test-wheel: pip wheel carries the shipped modules: %s" % ", ".join(sorted(pip)))
PY
/usr/bin/python3 -m pip install --no-deps --no-index --break-system-packages -q \
    --target "$work/site" "$wheel"
cd tests
"$ROOT/scripts/without-host-libs.sh" env PYTHONPATH="$work/site" /usr/bin/python3 -c \
    'import bdinterp, sys; assert bdinterp.__file__.startswith(sys.argv[1]), bdinterp.__file__' "$work/site"
"$ROOT/scripts/without-host-libs.sh" env PYTHONPATH="$work/site" /usr/bin/python3 -m pytest -q \
    -p no:cacheprovider python
