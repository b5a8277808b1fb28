#!/usr/bin/env python3
"""Bundle the shared libraries a compiled module needs beyond the manylinux set next to it.

    /usr/bin/python3 scripts/bundle_libs.py MODULE LDD_OUTPUT ROOT

LDD_OUTPUT: `ldd MODULE` as run inside the build chroot ROOT (so its paths are the chroot's).
Each library outside the manylinux set is copied from ROOT next to MODULE under a private name
(libcholmod.so.3 -> libcholmod-bdi.so.3, as auditwheel does, so the loader never takes it for -
or replaces it with - another copy of that library in the process), its SONAME and every NEEDED
entry naming a bundled library are rewritten (patchelf), and RUNPATH is set to $ORIGIN.
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from audit_so import SYSTEM, inspect  # noqa: E402


def resolve(root, path):
    """The host path of `path` inside the chroot `root`, following its (absolute) symlinks there."""
    for _ in range(40):
        full = root + path
        if not os.path.islink(full):
            return full
        target = os.readlink(full)
        path = os.path.normpath(target if target.startswith("/") else
                                os.path.join(os.path.dirname(path), target))
    sys.exit("bundle_libs: symlink loop at %s" % path)


def private_name(soname):
    """'libcholmod.so.3' -> 'libcholmod-bdi.so.3'."""
    stem, _, rest = soname.partition(".so")
    return "%s-bdi.so%s" % (stem, rest)


def patchelf(*args):
    subprocess.run(["patchelf", *args], check=True)


def main():
    module, ldd_output, root = sys.argv[1:4]
    here = os.path.dirname(os.path.abspath(module))
    with open(ldd_output, encoding="utf-8") as f:
        found = dict(re.findall(r"^\s*(\S+) => (/\S+)", f.read(), re.M))
    missing = re.findall(r"^\s*(\S+) => not found", open(ldd_output).read(), re.M)
    if missing:
        sys.exit("bundle_libs: %s needs libraries not found in the chroot: %s" % (module, missing))
    bundled = {name: private_name(name) for name in found if name not in SYSTEM}
    for name, new in bundled.items():
        dst = os.path.join(here, new)
        shutil.copyfile(resolve(root, found[name]), dst)
        os.chmod(dst, 0o755)
        patchelf("--set-soname", new, dst)
    # One change per patchelf call: 0.14 (Debian 12) mixes up several in one call.
    for path in [module] + [os.path.join(here, n) for n in bundled.values()]:
        patchelf("--set-rpath", "$ORIGIN", path)
        for old in inspect(path)["needed"]:
            if old in bundled:
                patchelf("--replace-needed", old, bundled[old], path)
    print("bundle_libs: %s + %s" % (os.path.basename(module), ", ".join(sorted(bundled.values()))))


if __name__ == "__main__":
    main()
