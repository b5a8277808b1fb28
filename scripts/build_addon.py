#!/usr/bin/env python3
"""Build the Blender add-on zips (installable with Blender's own "Install from disk").

    /usr/bin/python3 scripts/build_addon.py [--core DIR] [--out dist]

Writes, from the one source tree addon/bdinterp_blender/:
  dist/bdinterp_blender-<ver>-legacy-py311.zip     legacy add-on (bl_info), Blender 3.4-4.1
  dist/bdinterp_blender-<ver>-extension-py311.zip  extension (blender_manifest.toml), 4.2+
Both vendor the compiled bdinterp package (default: the one this interpreter imports, i.e.
after `pip install .`) as bdinterp_blender/_vendor/bdinterp; 'py311' (and build_info.json in
the zip) name the Python ABI of its compiled module.  Run with the Python the module was built
for (Debian's /usr/bin/python3 = 3.11 = Debian's Blender).
"""

import argparse
import ast
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SRC = os.path.join(ROOT, "addon", "bdinterp_blender")
MANIFEST = "blender_manifest.toml"
# Build products and local state that must never go into a zip.
SKIP_DIRS = {"__pycache__", "_vendor"}
SKIP_FILES = {"build_info.json"}
FIXED_TIME = (2024, 1, 1, 0, 0, 0)  # reproducible zips
PLATFORMS = {"x86_64-linux-gnu": "linux-x64", "aarch64-linux-gnu": "linux-arm64"}


def die(msg):
    sys.exit("build_addon: " + msg)


def core_dir(explicit):
    if explicit:
        return os.path.abspath(explicit)
    try:
        import bdinterp
    except ImportError as exc:
        die("cannot import bdinterp (%s); build and install the core first:\n"
            "  /usr/bin/python3 -m pip install --no-build-isolation .\n"
            "or pass --core path/to/bdinterp" % exc)
    return os.path.dirname(os.path.abspath(bdinterp.__file__))


def compiled_module(pkg):
    """(file name, EXT_SUFFIX) of the compiled _core module in the package."""
    found = [n for n in os.listdir(pkg) if re.match(r"_core\..*\.(so|pyd)$", n)]
    if len(found) != 1:
        die("expected exactly one compiled _core module in %s, found %s" % (pkg, found or "none"))
    return found[0], found[0][len("_core"):]


def abi_of(ext_suffix):
    """'.cpython-311-x86_64-linux-gnu.so' -> ('3.11', 'py311', 'x86_64-linux-gnu')."""
    m = re.match(r"\.cpython-(\d)(\d+)-([^.]+)\.", ext_suffix)
    if not m:
        die("cannot read the Python ABI from %r" % ext_suffix)
    major, minor, triplet = m.groups()
    return "%s.%s" % (major, minor), "py%s%s" % (major, minor), triplet


def versions():
    with open(os.path.join(SRC, "__init__.py"), encoding="utf-8") as f:
        tree = ast.parse(f.read())
    bl_info = next(ast.literal_eval(node.value) for node in tree.body if isinstance(node, ast.Assign)
                   and getattr(node.targets[0], "id", "") == "bl_info")
    with open(os.path.join(SRC, MANIFEST), encoding="utf-8") as f:
        manifest = f.read()
    legacy = ".".join(map(str, bl_info["version"]))
    ext = re.search(r'^version\s*=\s*"([^"]+)"', manifest, re.M).group(1)
    if legacy != ext:
        die("bl_info version %s != %s version %s" % (legacy, MANIFEST, ext))
    return legacy, manifest


def check_links(so_path):
    """Refuse a module that needs shared libraries a user's machine will not find."""
    try:
        out = subprocess.run(["ldd", so_path], capture_output=True, text=True).stdout
    except OSError:
        return
    missing = [line.strip() for line in out.splitlines() if "not found" in line]
    if missing:
        die("%s links to libraries that are not found: %s" % (so_path, missing))


def stage(tmp, pkg, so_name, info):
    """Copy the add-on source plus vendored core into tmp/bdinterp_blender."""
    dst = os.path.join(tmp, "bdinterp_blender")
    shutil.copytree(SRC, dst, ignore=lambda d, names: [n for n in names if n in SKIP_DIRS
                                                       or n in SKIP_FILES or n.endswith(".pyc")])
    shutil.copytree(pkg, os.path.join(dst, "_vendor", "bdinterp"),
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    with open(os.path.join(dst, "build_info.json"), "w", encoding="utf-8") as f:
        json.dump(info, f, indent=1, sort_keys=True)
    return dst


def write_zip(path, staged, prefix, skip=(), replace=None):
    """Zip `staged` with entries under `prefix`; `replace` maps a relative name to new text."""
    replace = replace or {}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for dirpath, dirnames, filenames in os.walk(staged):
            dirnames.sort()
            for name in sorted(filenames):
                full = os.path.join(dirpath, name)
                rel = os.path.relpath(full, staged).replace(os.sep, "/")
                if rel in skip:
                    continue
                zi = zipfile.ZipInfo(prefix + rel, FIXED_TIME)
                zi.compress_type = zipfile.ZIP_DEFLATED
                zi.external_attr = (os.stat(full).st_mode & 0o777) << 16
                if rel in replace:
                    zf.writestr(zi, replace[rel])
                else:
                    with open(full, "rb") as f:
                        zf.writestr(zi, f.read())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--core", help="bdinterp package directory to vendor (default: installed)")
    ap.add_argument("--out", default=os.path.join(ROOT, "dist"))
    args = ap.parse_args()

    pkg = core_dir(args.core)
    so_name, ext_suffix = compiled_module(pkg)
    check_links(os.path.join(pkg, so_name))
    py, tag, triplet = abi_of(ext_suffix)
    platform = PLATFORMS.get(triplet)
    if platform is None:
        die("unknown platform %r for the extension manifest" % triplet)
    version, manifest = versions()
    info = {"python": py, "ext_suffix": ext_suffix, "platform": platform, "version": version,
            "compiled_module": so_name}
    # The extension manifest states the one platform the vendored module is built for.
    manifest = re.sub(r"^platforms\s*=.*$", 'platforms = ["%s"]' % platform, manifest, flags=re.M)

    os.makedirs(args.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        staged = stage(tmp, pkg, so_name, info)
        legacy = os.path.join(args.out, "bdinterp_blender-%s-legacy-%s.zip" % (version, tag))
        extension = os.path.join(args.out, "bdinterp_blender-%s-extension-%s.zip" % (version, tag))
        # Legacy: one top-level package folder; no manifest (4.2+ would treat it as extension).
        write_zip(legacy, staged, "bdinterp_blender/", skip={MANIFEST})
        # Extension: the package contents at the zip root, manifest included.
        write_zip(extension, staged, "", replace={MANIFEST: manifest})
    for path in (legacy, extension):
        print("wrote %s (compiled module for Python %s, %s)" % (os.path.relpath(path), py, platform))


if __name__ == "__main__":
    main()
