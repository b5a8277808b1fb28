"""Bake bounded-distortion in-betweens for every suitable object of every .blend in a folder.

    blender --background --factory-startup --python examples/blender/bake_folder.py -- FOLDER... \
        [--count 8] [--easing EASE_IN_OUT] [--out OUTDIR] [--skip-nonplanar] [--summary FILE] \
        [--addon DIR]
    blender --background shot.blend --python examples/blender/bake_folder.py -- [options]

FOLDER... : folders (relative or absolute) and/or .blend files; none: the .blend opened on the
command line (one file per process, as a render farm runs it).  Suitable: a mesh with shape keys.
Per object the pair comes from its add-on settings if it has them (Object.bdi.source/target),
else: source = the reference key, and every other key that is not itself a bake result is a
target.  Objects that share a pair and a parent (or that an earlier bake made one character) are
baked as one character, the first by name holding the slider.  Prints one line per object (or
character), 'file: object: OK|FAILED|SKIPPED ...'; a file that cannot
be opened or saved is reported and the next one processed.  Files are saved in place (or into
OUTDIR); a JSON summary goes to --summary (default OUTDIR/FOLDER bake_summary.json).  Exit code
1 if any object or file failed (no --python-exit-code needed), 2 on bad arguments.  Uses the
add-on from --addon DIR (a folder holding the unpacked bdinterp_blender/), else the installed
add-on, else addon/ of this checkout.
"""

import argparse
import glob
import json
import os
import sys
import traceback

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def import_addon(folder=None):
    if folder:
        sys.path.insert(0, os.path.abspath(folder))
    try:
        import bdinterp_blender
        return bdinterp_blender
    except ImportError:
        pass
    import addon_utils  # Blender 4.2+: installed as an extension, bl_ext.<repo>.bdinterp_blender
    names = [m.__name__ for m in addon_utils.modules() if m.__name__.split(".")[-1] == "bdinterp_blender"]
    if names and addon_utils.enable(names[0], default_set=False, handle_error=lambda exc: None):
        return sys.modules[names[0]]
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


def bake_pair(objs, source, target, addon, args):
    """(line, summary, failed) of baking source -> target of one object or a character (a list)."""
    try:
        r = addon.bake(objs, source=source, target=target, count=args.count, easing=args.easing)
        return ("%s -> %s: %d keys, max K %.4g (inputs %.4g)"
                % (source, target, len(r.keys), r.max_distortion, r.input_distortion),
                dict(r.summary(), status="OK"), False)
    except (ValueError, RuntimeError) as exc:
        skip = args.skip_nonplanar and "not planar" in str(exc)
        return ("%s -> %s: %s: %s" % (source, target, "skipped" if skip else "FAILED", exc),
                {"source": source, "target": target, "error": str(exc),
                 "status": "SKIPPED" if skip else "FAILED"}, not skip)


def bake_object(obj, addon, args, pair_list=None):
    """(status 'OK'/'FAILED'/'SKIPPED', text, per-pair summaries) of baking obj's pairs (or
    `pair_list`; obj may be a list: a character)."""
    lines, out, failed = [], [], False
    for source, target in pairs(obj, addon) if pair_list is None else pair_list:
        line, summary, fail = bake_pair(obj, source, target, addon, args)
        lines.append(line)
        out.append(summary)
        failed |= fail
    if failed:
        status = "FAILED"
    elif out and all(p["status"] == "SKIPPED" for p in out) or not out:
        status = "SKIPPED"
    else:
        status = "OK"
    return status, "; ".join(lines) or "no target keys", out


def characters(objs, addon):
    """{(source, target): [objects]}: the pairs that several objects with one parent share, or
    that an earlier bake recorded as one character (its slider's owner: that bake decides); each
    is baked as one character."""
    groups = {}
    for obj in objs:
        for source, target in pairs(obj, addon):
            record = addon.keys.playback.find(obj, source, target)
            owner = record.record.get("owner") if record is not None else None
            group = ("owner", owner) if owner else \
                ("parent", obj.parent.name) if obj.parent is not None else None
            if group is not None:
                groups.setdefault(group + (source, target), []).append(obj)
    return {k[2:]: v for k, v in groups.items() if len(v) > 1}


def suitable(obj):
    return obj.type == 'MESH' and obj.data.shape_keys is not None and len(obj.data.shape_keys.key_blocks) >= 2


def bake_file(path, addon, args):
    """Bake every suitable object of the open file `path`, save it; the file's summary dict."""
    name = os.path.basename(path)
    result = {"file": path, "objects": [], "status": "OK"}
    objs = sorted((o for o in bpy.data.objects if suitable(o)), key=lambda o: o.name)
    together = characters(objs, addon)
    units = [(objs_, [pair], " + ".join(o.name for o in objs_)) for pair, objs_ in together.items()]
    units += [(obj, [p for p in pairs(obj, addon) if obj not in together.get(p, ())], obj.name)
              for obj in objs]
    for unit, pair_list, label in units:
        if not pair_list and not isinstance(unit, list) and pairs(unit, addon):
            continue  # every pair of this object was baked with its character
        status, text, summaries = bake_object(unit, addon, args, pair_list)
        print("%s: %s: %s %s" % (name, label, status, text), flush=True)
        result["objects"].append({"object": label, "status": status, "pairs": summaries})
        if status == "FAILED":
            result["status"] = "FAILED"
    out = os.path.join(args.out, name) if args.out else path
    bpy.ops.wm.save_as_mainfile(filepath=out)
    result["saved"] = out
    return result


def blend_files(paths):
    files = []
    for p in paths:
        p = os.path.abspath(p)  # Blender's operators resolve relative paths differently
        files += sorted(glob.glob(os.path.join(p, "*.blend"))) if os.path.isdir(p) else [p]
    return files


def parse(argv):
    ap = argparse.ArgumentParser(prog="bake_folder.py")
    ap.add_argument("paths", nargs="*", help="folders and/or .blend files (default: the open file)")
    ap.add_argument("--count", type=int, default=8)
    ap.add_argument("--easing", default="LINEAR", choices=["LINEAR", "EASE_IN", "EASE_OUT", "EASE_IN_OUT"])
    ap.add_argument("--out", help="save baked files here instead of in place")
    ap.add_argument("--skip-nonplanar", action="store_true",
                    help="skip (instead of failing on) objects whose keys are not planar")
    ap.add_argument("--summary", help="JSON summary file (default: bake_summary.json beside the output)")
    ap.add_argument("--addon", help="folder holding an unpacked bdinterp_blender add-on")
    args = ap.parse_args(argv)
    args.out = os.path.abspath(args.out) if args.out else None
    return args


def run(args):
    """Bake every file; returns the summary dict."""
    addon = import_addon(args.addon)
    opened = bpy.data.filepath
    files = blend_files(args.paths) if args.paths else ([opened] if opened else [])
    summary = {"files": [], "failed": 0, "ok": 0, "skipped": 0}
    if args.out:
        os.makedirs(args.out, exist_ok=True)
    for path in files:
        try:
            if path != bpy.data.filepath:
                bpy.ops.wm.open_mainfile(filepath=path)
            result = bake_file(path, addon, args)
        except Exception as exc:  # noqa: BLE001 -- report this file, go on with the next
            print("%s: FAILED: %s" % (os.path.basename(path), str(exc).strip().splitlines()[-1]), flush=True)
            result = {"file": path, "status": "FAILED", "error": traceback.format_exc(), "objects": []}
        summary["files"].append(result)
        for o in result["objects"]:
            summary[o["status"].lower()] += 1
        if result["status"] == "FAILED" and not result["objects"]:
            summary["failed"] += 1
    return summary


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse(argv)  # bad arguments: argparse exits with 2
    summary = run(args)
    files = summary["files"]
    if not files:
        print("bake_folder: no .blend files in %s" % (" ".join(args.paths) or "(no file open)"))
    where = args.summary or os.path.join(args.out or (os.path.dirname(files[0]["file"]) if files else "."),
                                         "bake_summary.json")
    with open(os.path.abspath(where), "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=1)
    print("bake_folder: %d ok, %d failed, %d skipped; summary %s"
          % (summary["ok"], summary["failed"], summary["skipped"], os.path.abspath(where)), flush=True)
    # Blender exits with a --python script's SystemExit code; an uncaught exception would give 0.
    sys.exit(1 if summary["failed"] or not files else 0)


main()
