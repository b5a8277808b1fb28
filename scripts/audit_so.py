#!/usr/bin/env python3
"""Audit shipped compiled modules against the portability policy and print a table.

    /usr/bin/python3 scripts/audit_so.py FILE...     FILE: a .so, or a .zip/.whl holding .so files

For every .so: its NEEDED entries, RUNPATH and the highest GLIBC_ (GLIBCXX_, CXXABI_, GCC_) symbol
versions it requires (readelf). Fails (exit 1) if a module needs a library outside the manylinux
set that is not bundled next to it and found through RUNPATH $ORIGIN, has a RUNPATH that is not
$ORIGIN-relative, or requires a symbol version above the manylinux_2_31 caps.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import zipfile

# The libraries every manylinux machine provides (PEP 600 / auditwheel's manylinux_2_31 policy).
SYSTEM = {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "librt.so.1",
          "ld-linux-x86-64.so.2", "libgcc_s.so.1", "libstdc++.so.6"}
# manylinux_2_31 = Debian 11 / Ubuntu 20.04: glibc 2.31, GCC 10's libstdc++ (3.4.28, CXXABI 1.3.12).
CAPS = {"GLIBC": (2, 31), "GLIBCXX": (3, 4, 28), "CXXABI": (1, 3, 12), "GCC": (10, 0, 0)}


def readelf(args, path):
    return subprocess.run(["readelf", *args, path], capture_output=True, text=True,
                          check=True).stdout


def inspect(path):
    """{'needed': [...], 'runpath': str, 'versions': {'GLIBC': (2, 17), ...}} of one .so."""
    dyn = readelf(["-d", "-W"], path)
    needed = re.findall(r"\(NEEDED\).*\[(.+?)\]", dyn)
    runpath = re.findall(r"\((?:RUNPATH|RPATH)\).*\[(.+?)\]", dyn)
    versions = {}
    for name, ver in re.findall(r"Name: ([A-Z]+)_([\d.]+)", readelf(["-V", "-W"], path)):
        v = tuple(int(x) for x in ver.split("."))
        versions[name] = max(versions.get(name, v), v)
    return {"needed": needed, "runpath": ":".join(runpath), "versions": versions}


def violations(path, info):
    """Human-readable reasons why the module at `path` breaks the policy ([] if it does not)."""
    bad = []
    here = os.listdir(os.path.dirname(path) or ".")
    dirs = info["runpath"].split(":") if info["runpath"] else []
    if any(not d.startswith("$ORIGIN") for d in dirs):
        bad.append("RUNPATH %r is not $ORIGIN-relative" % info["runpath"])
    for lib in info["needed"]:
        if lib not in SYSTEM and not ("$ORIGIN" in dirs and lib in here):
            bad.append("needs %s (not in the manylinux set, not bundled via $ORIGIN)" % lib)
    for name, cap in CAPS.items():
        have = info["versions"].get(name)
        if have and have > cap:
            bad.append("needs %s_%s > %s_%s" % (name, fmt(have), name, fmt(cap)))
    return bad


def fmt(version):
    return ".".join(map(str, version))


def expand(files, tmp):
    """[(archive or directory, path)] of every .so in `files`, unpacking zips and wheels into tmp (all of an
    archive's libraries first: a module's bundled neighbours must be there when it is checked)."""
    found = []
    for f in files:
        if not f.endswith((".zip", ".whl")):
            found.append((os.path.dirname(f) or ".", f))
            continue
        with zipfile.ZipFile(f) as zf:
            for n in zf.namelist():
                if n.endswith(".so") or ".so." in os.path.basename(n):
                    found.append((f, zf.extract(n, os.path.join(tmp, os.path.basename(f)))))
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+")
    args = ap.parse_args()
    failed = found = 0
    print("%-38s %-6s %-8s %-8s %s" % ("module", "GLIBC", "GLIBCXX", "RUNPATH", "NEEDED"))
    with tempfile.TemporaryDirectory() as tmp:
        where = None
        for archive, path in expand(args.files, tmp):
            if archive != where:
                where = archive
                print("%s:" % archive)
            found += 1
            info = inspect(path)
            v = info["versions"]
            print("  %-36s %-6s %-8s %-8s %s" % (
                os.path.basename(path), fmt(v.get("GLIBC", ())) or "-", fmt(v.get("GLIBCXX", ())) or "static",
                info["runpath"] or "-", " ".join(info["needed"])))
            for reason in violations(path, info):
                failed += 1
                print("  POLICY: " + reason)
    if not found:
        sys.exit("audit_so: no .so in %s" % " ".join(args.files))
    if failed:
        sys.exit("audit_so: %d policy violation(s)" % failed)
    print("audit_so: %d module(s) within the manylinux_2_31 policy" % found)


if __name__ == "__main__":
    main()
