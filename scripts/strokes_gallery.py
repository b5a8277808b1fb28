#!/usr/bin/env python3
"""docs/gallery/strokes_compare.png: the drawn arm and tail of examples/strokes/drawn.py, Blender's
own Interpolate Sequence against bdinterp's, with the stroke length kept at the middle in-between.

Two steps (Blender's tool runs only inside Blender 4.3+; the picture is drawn with the host's
matplotlib):

    blender -b --factory-startup --python scripts/strokes_gallery.py -- blender OUT.json
    PYTHONPATH=python /usr/bin/python3 scripts/strokes_gallery.py picture OUT.json [PNG]

The first writes the keys as Blender stores them and Blender's middle in-between (flip off, and
its default "auto"); the second interpolates the same keys with bdinterp.strokes (what the
add-on's operator runs) and draws both, printing the lengths kept.
"""
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "examples", "strokes"))
import drawn  # noqa: E402

FRAMES, MIDDLE = (1, 13), 7
DRAWINGS = {"arm": drawn.arm_key, "tail": drawn.tail_key}


def in_blender(out):
    import bpy
    import gp_strokes as gps
    result = {"blender": bpy.app.version_string}
    for name, key in DRAWINGS.items():
        entry = {}
        for flip in ('NONE', 'AUTO'):
            obj = gps.gp_object(name, {FRAMES[0]: key(0), FRAMES[1]: key(1)})
            gps.blender_interpolate(obj, FRAMES[0], step=(FRAMES[1] - FRAMES[0]) // 2, flip=flip)
            for frame, label in ((FRAMES[0], "a"), (FRAMES[1], "b"), (MIDDLE, "blender_" + flip.lower())):
                entry[label] = [{k: v.tolist() for k, v in s.items()} for s in gps.strokes_at(obj, frame)]
            bpy.data.objects.remove(obj)
        result[name] = entry
    with open(out, "w") as f:
        json.dump(result, f)


def kept(strokes, keys):
    return [drawn.length(s) / drawn.length(k) for s, k in zip(strokes, keys)]


def picture(src, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from bdinterp.strokes import Stroke, StrokeInterpolator
    data = json.load(open(src))
    fig, axes = plt.subplots(2, 2, figsize=(10, 9))
    for row, name in enumerate(DRAWINGS):
        entry = data[name]
        pts = {k: [np.array(s["points"], dtype=float) for s in v] for k, v in entry.items()}
        keys = [[Stroke(p, radius=np.array(s["radius"])) for p, s in zip(pts[k], entry[k])] for k in "ab"]
        ours = [s.points for s in StrokeInterpolator(*keys).at(0.5)]
        results = (("Blender's Interpolate Sequence (flip off)", pts["blender_none"]), ("bdinterp", ours))
        every = np.concatenate([p for k in ("a", "b", "blender_none") for p in pts[k]] + ours)
        lo, hi = every.min(axis=0) - 0.2, every.max(axis=0) + 0.2
        for ax, (label, middle) in zip(axes[row], results):
            ax.set_xlim(lo[0], hi[0]), ax.set_ylim(lo[2], hi[2])
            for k, colour in (("a", "0.6"), ("b", "0.3")):
                for p in pts[k]:
                    ax.plot(p[:, 0], p[:, 2], color=colour, lw=2)
            for p in middle:
                ax.plot(p[:, 0], p[:, 2], color="tab:red" if label != "bdinterp" else "tab:blue", lw=3)
            lost = [100 * (1 - k) for k in kept(middle, pts["a"])]
            ax.set_title(f"{name}: {label}\nlength lost half way: " + ", ".join(f"{x:.0f} %" for x in lost),
                         fontsize=10)
            ax.set_aspect("equal")
            ax.axis("off")
            print(f"{name}, {label}: length kept half way {[round(k, 4) for k in kept(middle, pts['a'])]}")
        print(f"{name}, Blender's default (flip auto): length kept half way "
              f"{[round(k, 4) for k in kept(pts['blender_auto'], pts['a'])]}")
    fig.suptitle(f"Keys in grey (light: frame {FRAMES[0]}, dark: frame {FRAMES[1]}), the middle in-between "
                 f"(frame {MIDDLE}) in colour; Blender {data['blender']}", fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=90)


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    if args[0] == "blender":
        in_blender(args[1])
    else:
        picture(args[1], args[2] if len(args) > 2 else os.path.join(ROOT, "docs", "gallery", "strokes_compare.png"))
