#!/usr/bin/env python3
"""Build the Blender add-on zips (installable with Blender's own installers).

    /usr/bin/python3 scripts/build_addon.py [--portable build/portable] [--core DIR] [--out dist]

From the one source tree addon/bdinterp_blender/ and the portable modules of
scripts/build-portable.sh (PORTABLE/py311/_core*.so, PORTABLE/py313/..., PORTABLE/py314/...,
PORTABLE/licenses/):
  dist/bdinterp_blender-<ver>-legacy-py311.zip  legacy add-on (bl_info), Blender 3.4-4.1: the
      package private to the add-on as bdinterp_blender/_vendor/bdinterp (Python 3.11 module)
  dist/bdinterp_blender-<ver>-extension.zip     extension (blender_manifest.toml), Blender 4.2+:
      ./wheels/ holds one bdinterp wheel per Python (3.11 for 4.2-5.0, 3.13 for 5.1+ and
      Debian 13's 4.3, 3.14 for Debian's 5.2), listed in the manifest; Blender installs the one
      its Python takes
  dist/bdinterp-<ver>-cpXY-cpXY-manylinux_2_31_x86_64.whl   those wheels, for pip
Every shipped .so is audited (scripts/audit_so.py prints the table; a violation fails the build).
--core DIR (development only): a legacy zip around DIR's compiled module, e.g. `make build`'s
python/bdinterp, for the Python it was built for; no extension, no audit.
"""

import argparse
import glob
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
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import make_wheel  # noqa: E402
import version as version_source  # noqa: E402

MANIFEST = "blender_manifest.toml"
# Build products and local state that must never go into a zip.
SKIP = shutil.ignore_patterns("__pycache__", "*.pyc", "_vendor", "build_info.json", "*.so")
FIXED_TIME = (2024, 1, 1, 0, 0, 0)  # reproducible zips
LEGACY_PYTHON = "311"  # Blender 3.4 (Debian 12) to 4.1 embed Python 3.11
PLATFORM = "linux-x64"


def die(msg):
    sys.exit("build_addon: " + msg)


def python_of(so_path):
    """'.../_core.cpython-313-x86_64-linux-gnu.so' -> '313'."""
    m = re.search(r"_core\.cpython-(\d+)-x86_64-linux-gnu\.so$", so_path)
    if not m:
        die("cannot read the Python ABI of %s (only linux-x64 is built here)" % so_path)
    return m.group(1)


def dotted(tag):
    return tag[0] + "." + tag[1:]


def portable_modules(portable):
    """{'311': path, '313': path, '314': path} of the portable build; dies if 3.11 is missing."""
    mods = {python_of(p): p for p in glob.glob(os.path.join(portable, "py3*", "_core*.so"))}
    if LEGACY_PYTHON not in mods:
        die("no portable module for Python 3.11 in %s: run scripts/build-portable.sh" % portable)
    return mods


def versions():
    """The version (file VERSION); dies if bl_info, the manifest or bdinterp differ, or if a
    licence declaration is not GPL-3.0-or-later."""
    if version_source.licence_mismatches():
        die("the licence %s is not declared in %s" % (
            version_source.LICENCE, ", ".join(version_source.licence_mismatches())))
    bad = version_source.mismatches()
    if bad:
        die("VERSION says %s but %s (scripts/version.py --set fixes)" % (
            version_source.version(), ", ".join("%s says %s" % b for b in bad)))
    return version_source.version()


def stage_addon(tmp, info, licenses):
    """Copy the add-on source into tmp/bdinterp_blender with build_info.json and licences."""
    dst = os.path.join(tmp, "bdinterp_blender")
    shutil.copytree(SRC, dst, ignore=SKIP)
    with open(os.path.join(dst, "build_info.json"), "w", encoding="utf-8") as f:
        json.dump(info, f, indent=1, sort_keys=True)
    os.makedirs(os.path.join(dst, "licenses"))
    shutil.copy(os.path.join(ROOT, "LICENSE"), os.path.join(dst, "LICENSE"))
    for path in glob.glob(os.path.join(licenses or "", "*")) if licenses else []:
        shutil.copy(path, os.path.join(dst, "licenses"))
    return dst


def vendor(staged, so_path):
    """The bdinterp package (Python files + one compiled module) as staged/_vendor/bdinterp."""
    pkg = os.path.join(staged, "_vendor", "bdinterp")
    shutil.copytree(os.path.join(ROOT, "python", "bdinterp"), pkg, ignore=SKIP)
    for lib in [so_path] + make_wheel.bundled_libs(so_path):
        shutil.copy(lib, pkg)
    with open(os.path.join(staged, "_vendor", "__init__.py"), "w", encoding="utf-8") as f:
        f.write('"""The add-on\'s private copy of bdinterp (imported as a subpackage)."""\n')


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


def legacy_zip(out, version, so_path, licenses, development=False):
    """Legacy: one top-level package folder; no manifest (4.2+ would treat it as an extension).
    development: a zip around a module built against this machine's libraries (--core)."""
    tag = python_of(so_path)
    info = {"version": version, "platform": PLATFORM, "layout": "legacy",
            "pythons": [dotted(tag)], "python": dotted(tag), "development": development,
            "ext_suffix": os.path.basename(so_path)[len("_core"):]}
    path = os.path.join(out, "bdinterp_blender-%s-legacy-py%s.zip" % (version, tag))
    with tempfile.TemporaryDirectory() as tmp:
        staged = stage_addon(tmp, info, licenses)
        vendor(staged, so_path)
        write_zip(path, staged, "bdinterp_blender/", skip={MANIFEST})
    return path


def wheel_platforms(wheel):
    """Blender's platform names of a wheel, from its platform tag."""
    tag = os.path.basename(wheel)[:-len(".whl")].split("-")[-1]
    found = []
    for pattern, names in ((r"linux(_\d+_\d+)?_x86_64", ["linux-x64"]),
                           (r"linux(_\d+_\d+)?_aarch64", ["linux-arm64"]),
                           (r"win_amd64", ["windows-x64"]), (r"macosx_.*_arm64", ["macos-arm64"]),
                           (r"macosx_.*_x86_64", ["macos-x64"]),
                           (r"macosx_.*_universal2", ["macos-arm64", "macos-x64"])):
        found += names if any(re.search(pattern + "$", t) for t in tag.split(".")) else []
    if not found:
        die("no Blender platform for the wheel %s" % wheel)
    return found


def manifest_text(wheels, platforms=(PLATFORM,)):
    """The source manifest with this build's platforms and wheels."""
    with open(os.path.join(SRC, MANIFEST), encoding="utf-8") as f:
        text = f.read()
    listed_platforms = ", ".join('"%s"' % p for p in platforms)
    text = re.sub(r"^platforms\s*=.*$", "platforms = [%s]" % listed_platforms, text, flags=re.M)
    listed = "wheels = [\n%s]" % "".join('  "./wheels/%s",\n' % os.path.basename(w) for w in wheels)
    if re.search(r"^wheels\s*=", text, re.M):
        return re.sub(r"^wheels\s*=\s*\[[^\]]*\]", listed, text, flags=re.M)
    return text.rstrip("\n") + "\n\n" + listed + "\n"


def extension_zip(out, version, wheels, licenses):
    """Extension: the package contents at the zip root, the manifest, ./wheels/ (no _vendor)."""
    pythons = sorted(dotted(re.search(r"-cp(\d+)-", w).group(1)) for w in wheels)
    info = {"version": version, "platform": PLATFORM, "layout": "extension", "pythons": pythons,
            "python": ", ".join(pythons), "ext_suffix": "wheels"}
    path = os.path.join(out, "bdinterp_blender-%s-extension.zip" % version)
    with tempfile.TemporaryDirectory() as tmp:
        staged = stage_addon(tmp, info, licenses)
        os.makedirs(os.path.join(staged, "wheels"))
        for w in wheels:
            shutil.copy(w, os.path.join(staged, "wheels"))
        write_zip(path, staged, "", replace={MANIFEST: manifest_text(wheels)})
    return path


def extension_source(out, version, wheels, licenses):
    """The extension's source folder for every platform the wheels are for (wheels of several
    platforms; scripts/extension-split.sh has Blender split it into one zip per platform)."""
    platforms = sorted({p for w in wheels for p in wheel_platforms(w)})
    pythons = sorted({dotted(re.search(r"-cp(\d+)-", w).group(1)) for w in wheels})
    info = {"version": version, "platform": platforms[0], "platforms": platforms,
            "layout": "extension", "pythons": pythons, "python": ", ".join(pythons),
            "ext_suffix": "wheels"}
    shutil.rmtree(os.path.join(out, "bdinterp_blender"), ignore_errors=True)  # idempotent
    staged = stage_addon(out, info, licenses)
    os.makedirs(os.path.join(staged, "wheels"), exist_ok=True)
    for w in wheels:
        shutil.copy(w, os.path.join(staged, "wheels"))
    with open(os.path.join(staged, MANIFEST), "w", encoding="utf-8") as f:
        f.write(manifest_text(wheels, platforms))
    return staged, platforms


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--portable", default=os.path.join(ROOT, "build", "portable"))
    ap.add_argument("--core", help="development: a bdinterp package dir with a compiled module")
    ap.add_argument("--out", default=os.path.join(ROOT, "dist"))
    ap.add_argument("--extension-source", metavar="WHEELS",
                    help="only the extension's source folder (OUT/bdinterp_blender) for the wheels "
                         "in WHEELS, of any platforms")
    args = ap.parse_args()
    version = versions()
    os.makedirs(args.out, exist_ok=True)
    if args.extension_source:
        wheels = sorted(glob.glob(os.path.join(args.extension_source, "bdinterp-*.whl")))
        if not wheels:
            die("no bdinterp wheels in %s" % args.extension_source)
        staged, platforms = extension_source(args.out, version, wheels,
                                             os.path.join(args.portable, "licenses"))
        print("wrote %s: %d wheels for %s" % (staged, len(wheels), ", ".join(platforms)))
        return
    if args.core:
        so = glob.glob(os.path.join(args.core, "_core.cpython-*.so"))
        if len(so) != 1:
            die("expected one compiled module in %s, found %s" % (args.core, so or "none"))
        path = legacy_zip(args.out, version, so[0], None, development=True)
        print("wrote %s (development: this machine's libraries, unaudited)" % path)
        return
    licenses = os.path.join(args.portable, "licenses")
    mods = portable_modules(args.portable)
    wheels = [make_wheel.write_wheel(mods[t], args.out, licenses) for t in sorted(mods)]
    written = [legacy_zip(args.out, version, mods[LEGACY_PYTHON], licenses),
               extension_zip(args.out, version, wheels, licenses)] + wheels
    for path in written:
        print("wrote %s" % os.path.relpath(path))
    audit = [sys.executable, os.path.join(ROOT, "scripts", "audit_so.py")] + written
    if subprocess.run(audit).returncode:
        die("the audit failed (table above)")


if __name__ == "__main__":
    main()
