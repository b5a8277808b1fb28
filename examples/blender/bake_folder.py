"""Bake bounded-distortion in-betweens for every suitable object of every .blend in a folder.

    blender --background --factory-startup --python examples/blender/bake_folder.py -- FOLDER \
        [--count 8] [--easing EASE_IN_OUT] [--out OUTDIR] [--skip-nonplanar]

Suitable: a mesh with shape keys.  Per object the pair comes from its add-on settings if it has
them (Object.bdi.source/target), else: source = the reference key, and every other key that is
not itself a bake result is a target.  Prints one line per object; files are saved in place (or
into OUTDIR); the exit code is 1 if any bake failed.  Uses the installed add-on if importable,
else addon/ of this checkout.
"""

import argparse
import glob
import os
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def import_addon():
    try:
        import bdinterp_blender
    except ImportError:
        sys.path.insert(0, os.path.join(ROOT, "addon"))
        import bdinterp_blender
    return bdinterp_blender


def pairs(obj, addon):
    """(source, target) pairs to bake for obj."""
    key = obj.data.shape_keys
    settings = getattr(obj, "bdi", None)
    if settings is not None and settings.target:
        return [(settings.source or key.reference_key.name, settings.target)]
    ref = key.reference_key.name
    return [(ref, kb.name) for kb in key.key_blocks
            if kb.name != ref and ".bdi" not in kb.name and kb.name != addon.api.LIVE_KEY]


def bake_object(obj, addon, args):
    """One line about obj; True if it failed."""
    lines, failed = [], False
    for source, target in pairs(obj, addon):
        try:
            r = addon.bake(obj, source=source, target=target, count=args.count, easing=args.easing)
            lines.append("%s -> %s: %d keys, max K %.4g (inputs %.4g)"
                         % (source, target, len(r.keys), r.max_distortion, r.input_distortion))
        except (ValueError, RuntimeError) as exc:
            if args.skip_nonplanar and "not planar" in str(exc):
                lines.append("%s -> %s: skipped (not planar)" % (source, target))
                continue
            lines.append("%s -> %s: FAILED: %s" % (source, target, exc))
            failed = True
    return ("FAILED" if failed else "OK"), "; ".join(lines) or "no target keys", failed


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="bake_folder.py")
    ap.add_argument("folder")
    ap.add_argument("--count", type=int, default=8)
    ap.add_argument("--easing", default="LINEAR",
                    choices=["LINEAR", "EASE_IN", "EASE_OUT", "EASE_IN_OUT"])
    ap.add_argument("--out", help="save baked files here instead of in place")
    ap.add_argument("--skip-nonplanar", action="store_true",
                    help="skip (instead of failing on) objects whose keys are not planar")
    args = ap.parse_args(argv)
    addon = import_addon()
    files = sorted(glob.glob(os.path.join(args.folder, "*.blend")))
    if not files:
        print("bake_folder: no .blend files in %s" % args.folder)
        sys.exit(1)
    any_failed = False
    for path in files:
        bpy.ops.wm.open_mainfile(filepath=path)
        for obj in sorted(bpy.data.objects, key=lambda o: o.name):
            if obj.type != 'MESH' or obj.data.shape_keys is None or len(obj.data.shape_keys.key_blocks) < 2:
                continue
            status, text, failed = bake_object(obj, addon, args)
            any_failed |= failed
            print("%s: %s: %s %s" % (os.path.basename(path), obj.name, status, text))
        out = os.path.join(args.out, os.path.basename(path)) if args.out else path
        if args.out:
            os.makedirs(args.out, exist_ok=True)
        bpy.ops.wm.save_as_mainfile(filepath=out)
    sys.exit(1 if any_failed else 0)


main()
