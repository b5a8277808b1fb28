#!/usr/bin/env python3
"""Assemble the wheel of the bdinterp package around one already-built compiled module.

    /usr/bin/python3 scripts/make_wheel.py SO [--out dist] [--licenses DIR]

The portable modules are built in Debian 11 (scripts/build-portable.sh) for Pythons that chroot
does not run, so pip cannot build these wheels; a wheel is a zip with a fixed layout (PEP 427):
the package, then NAME-VER.dist-info/{METADATA,WHEEL,entry_points.txt,licenses/,RECORD}.
The tag is cpXY-cpXY-manylinux_2_31_x86_64: scripts/audit_so.py checks the module keeps it.
"""
import argparse
import base64
import hashlib
import os
import re
import sys
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import version as version_source  # noqa: E402

PACKAGE = os.path.join(ROOT, "python", "bdinterp")
PLATFORM_TAG = {"x86_64-linux-gnu": "manylinux_2_31_x86_64"}
FIXED_TIME = (2024, 1, 1, 0, 0, 0)  # reproducible archives


def wheel_tag(so_name):
    """'_core.cpython-313-x86_64-linux-gnu.so' -> 'cp313-cp313-manylinux_2_31_x86_64'."""
    m = re.match(r"_core\.cpython-(\d+)-([^.]+)\.so$", so_name)
    if not m or m.group(2) not in PLATFORM_TAG:
        sys.exit("make_wheel: cannot tag %r" % so_name)
    return "cp%s-cp%s-%s" % (m.group(1), m.group(1), PLATFORM_TAG[m.group(2)])


def bundled_libs(so_path):
    """The shared libraries bundled next to the module (found through its RUNPATH $ORIGIN)."""
    here = os.path.dirname(so_path)
    return sorted(os.path.join(here, n) for n in os.listdir(here)
                  if n.startswith("lib") and ".so" in n)


def metadata(ver):
    return ("Metadata-Version: 2.1\nName: bdinterp\nVersion: %s\n"
            "Summary: Planar shape interpolation with bounded distortion "
            "(Chen, Weber, Keren, Ben-Chen 2013)\nLicense: GPL-3.0-or-later\n"
            "Classifier: License :: OSI Approved :: GNU General Public License v3 or later (GPLv3+)\n"
            "Requires-Python: >=3.10\nRequires-Dist: numpy\n" % ver)


def entries(so_path, tag, ver, licenses):
    """(archive name, bytes) of every file of the wheel except RECORD."""
    for dirpath, dirnames, filenames in os.walk(PACKAGE):
        dirnames[:] = sorted(d for d in dirnames if d != "__pycache__")
        for name in sorted(n for n in filenames if n.endswith((".py", ".typed", ".pyi"))):
            rel = os.path.relpath(os.path.join(dirpath, name), PACKAGE).replace(os.sep, "/")
            with open(os.path.join(dirpath, name), "rb") as f:
                yield "bdinterp/" + rel, f.read()
    for lib in [so_path] + bundled_libs(so_path):
        with open(lib, "rb") as f:
            yield "bdinterp/" + os.path.basename(lib), f.read()
    info = "bdinterp-%s.dist-info/" % ver
    yield info + "METADATA", metadata(ver).encode()
    yield info + "WHEEL", ("Wheel-Version: 1.0\nGenerator: bdinterp make_wheel.py\n"
                           "Root-Is-Purelib: false\nTag: %s\n" % tag).encode()
    yield info + "entry_points.txt", b"[console_scripts]\nbdinterp = bdinterp.cli:main\n"
    bundled = sorted(os.path.join(licenses, n) for n in os.listdir(licenses)) if licenses else []
    for path in [os.path.join(ROOT, "LICENSE")] + bundled:
        with open(path, "rb") as f:
            yield info + "licenses/" + os.path.basename(path), f.read()


def write_wheel(so_path, out, licenses=None):
    """Write the wheel for the module at so_path into out; return its path."""
    ver = version_source.version()
    tag = wheel_tag(os.path.basename(so_path))
    path = os.path.join(out, "bdinterp-%s-%s.whl" % (ver, tag))
    record = []
    os.makedirs(out, exist_ok=True)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, data in entries(so_path, tag, ver, licenses):
            zi = zipfile.ZipInfo(name, FIXED_TIME)
            zi.compress_type = zipfile.ZIP_DEFLATED
            zi.external_attr = (0o755 if ".so" in name else 0o644) << 16
            zf.writestr(zi, data)
            digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=")
            record.append("%s,sha256=%s,%d" % (name, digest.decode(), len(data)))
        name = "bdinterp-%s.dist-info/RECORD" % ver
        record.append(name + ",,")
        zf.writestr(zipfile.ZipInfo(name, FIXED_TIME), "\n".join(record) + "\n")
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("so")
    ap.add_argument("--out", default=os.path.join(ROOT, "dist"))
    ap.add_argument("--licenses", help="directory of bundled libraries' licence files")
    args = ap.parse_args()
    print(write_wheel(args.so, args.out, args.licenses))


if __name__ == "__main__":
    main()
