#!/usr/bin/env python3
"""The one version number (the file VERSION) and the one licence (GPL-3.0-or-later).

CMake and pyproject read VERSION; the places that must hold a literal (bl_info,
blender_manifest.toml, bdinterp.__version__) are checked or rewritten here, and every licence
declaration (pyproject, manifest, bl_info, the CMake package) is checked.

    /usr/bin/python3 scripts/version.py            print the version
    /usr/bin/python3 scripts/version.py --check    fail if a literal differs from VERSION
    /usr/bin/python3 scripts/version.py --set X.Y.Z
"""
import argparse
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# file -> (pattern whose group 1 is the version, how to write a version there)
LITERALS = {
    "addon/bdinterp_blender/__init__.py":
        (r'"version":\s*\(([\d, ]+)\)', lambda v: ", ".join(v.split("."))),
    "addon/bdinterp_blender/blender_manifest.toml": (r'^version\s*=\s*"([^"]+)"', str),
    "python/bdinterp/__init__.py": (r'^__version__\s*=\s*"([^"]+)"', str),
}


LICENCE = "GPL-3.0-or-later"
# Where the licence is declared, as a pattern that must match there.
LICENCE_DECLARED = {
    "pyproject.toml": r'^license = \{ text = "%s" \}',
    "addon/bdinterp_blender/blender_manifest.toml": r'^license = \["SPDX:%s"\]',
    "addon/bdinterp_blender/__init__.py": r'"license": "%s"',
    "cmake/bdinterpConfig.cmake.in": r'set\(bdinterp_LICENSE "%s"\)',
}


def licence_mismatches():
    """The files of LICENCE_DECLARED that do not declare LICENCE."""
    bad = []
    for path, pattern in LICENCE_DECLARED.items():
        with open(os.path.join(ROOT, path), encoding="utf-8") as f:
            if not re.search(pattern % re.escape(LICENCE), f.read(), re.M):
                bad.append(path)
    return bad


def version():
    with open(os.path.join(ROOT, "VERSION"), encoding="utf-8") as f:
        return f.read().strip()


def literal(path):
    """The version written in `path`, as 'X.Y.Z'."""
    pattern, _ = LITERALS[path]
    with open(os.path.join(ROOT, path), encoding="utf-8") as f:
        m = re.search(pattern, f.read(), re.M)
    if not m:
        sys.exit("version: no version found in %s" % path)
    return ".".join(p.strip() for p in m.group(1).split(","))


def mismatches():
    """[(path, its version)] for every literal that differs from VERSION."""
    want = version()
    return [(p, literal(p)) for p in LITERALS if literal(p) != want]


def set_version(new):
    if not re.fullmatch(r"\d+\.\d+\.\d+", new):
        sys.exit("version: %r is not X.Y.Z" % new)
    with open(os.path.join(ROOT, "VERSION"), "w", encoding="utf-8") as f:
        f.write(new + "\n")
    for path, (pattern, fmt) in LITERALS.items():
        full = os.path.join(ROOT, path)
        with open(full, encoding="utf-8") as f:
            text = f.read()
        m = re.search(pattern, text, re.M)
        text = text[:m.start(1)] + fmt(new) + text[m.end(1):]
        with open(full, "w", encoding="utf-8") as f:
            f.write(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--set", metavar="X.Y.Z")
    args = ap.parse_args()
    if args.set:
        set_version(args.set)
    if args.check:
        if licence_mismatches():
            sys.exit("version: %s not declared in %s" % (LICENCE, ", ".join(licence_mismatches())))
        bad = mismatches()
        if bad:
            sys.exit("version: VERSION says %s but %s" % (version(), ", ".join(
                "%s says %s" % b for b in bad)))
    print(version())


if __name__ == "__main__":
    main()
