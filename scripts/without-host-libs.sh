#!/usr/bin/env bash
# Runs a command with the host's SuiteSparse and METIS made unavailable (needs root): in a private
# mount namespace an empty file is bind-mounted over each of their shared objects, so anything that
# still needs them fails to load. Debian's Blender 3.4 itself links OpenBLAS, LAPACK, gfortran and
# libgomp, so those stay; scripts/audit_so.py is what proves the modules do not need them.
#   scripts/without-host-libs.sh CMD [ARGS...]
set -euo pipefail
if [ "${BDI_LIBS_HIDDEN:-}" != 1 ]; then
  exec unshare -m --propagation private env BDI_LIBS_HIDDEN=1 "$0" "$@"
fi
. "$(dirname "$0")/hide-libs.sh"
hide_suitesparse /
# The proof that hiding works: the host's CHOLMOD must not load here.
if /usr/bin/python3 -c 'import ctypes; ctypes.CDLL("libcholmod.so.3")' 2>/dev/null; then
  echo "without-host-libs: libcholmod.so.3 still loads" >&2; exit 1
fi
"$@"
