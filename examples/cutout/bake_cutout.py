"""Bake the cut-out character in Blender as one object and as seven objects, with BDI, ARAP and
the linear blend, and print how far its joints open.

    blender --background --factory-startup --python-exit-code 1 \\
        --python examples/cutout/bake_cutout.py -- [--out out/cutout] [--count 19]

Writes OUT/cutout_one.blend and OUT/cutout_seven.blend (the BDI bakes: drag the slider
'Pose.bdi' of 'Character' or of 'Torso') and prints one line per bake and a JSON line
('JSON:{...}': the largest joint opening relative to the character's size, per case and method).
"""

import argparse
import json
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "blender"))

import addon_loader  # noqa: E402
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402

METHODS = ("bdi", "arap", "linear")


def build(case, pieces):
    """A new file holding the character as one object or seven: (objects, their piece ranges)."""
    bpy.ops.wm.read_homefile(use_empty=True)
    if case == "one":
        obj, ranges = cb.one_object(pieces)
        return [obj], ranges
    return cb.seven_objects(pieces), None


def bake_case(addon, case, pieces, joints, count, out):
    """{method: largest joint opening} of `case` ('one' or 'seven'); the BDI bake saved in out."""
    size, found = cb.size_of(pieces), {}
    for method in reversed(METHODS):  # BDI last: its bake is the one saved
        objs, ranges = build(case, pieces)
        result = addon.bake(objs if len(objs) > 1 else objs[0], target=cb.TARGET, count=count,
                            method=method)
        opening = cb.openings(objs, ranges, joints, size, cb.baked(objs[0]))
        worst = max(opening, key=opening.get)
        found[method] = opening[worst]
        print("%s object%s, %s: %s; largest joint opening %.3g %% of the size (%s - %s)"
              % (case, "" if case == "one" else "s", method, result.message,
                 100 * opening[worst], *worst))
    if out:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "cutout_%s.blend" % case))
    return found


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="bake_cutout.py")
    ap.add_argument("--out", default=None, help="folder for cutout_one.blend, cutout_seven.blend")
    ap.add_argument("--count", type=int, default=19, help="in-betweens (default 19: t = 0.05 ...)")
    args = ap.parse_args(argv)
    if args.out:
        os.makedirs(args.out, exist_ok=True)
    addon = addon_loader.enable()
    pieces, joints = cc.character()
    found = {case: bake_case(addon, case, pieces, joints, args.count, args.out)
             for case in ("one", "seven")}
    print("JSON:" + json.dumps(found))


if __name__ == "__main__":
    main()
