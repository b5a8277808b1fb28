"""A Grease Pencil face drawn on the cut-out character's head, bound to it: the head turns (slider
keyframed 0 -> 1 over frames 1-48) and the eyes and mouth ride along (Blender 4.3 or later).

    blender --background --factory-startup --python-exit-code 1 \\
        --python examples/cutout/gp_face.py -- [--out out/gp_face.blend]

Open the file and play it, or drag the slider 'Pose.bdi' of 'Character'.  Prints 'JSON:{...}'
with how far the face moved and how far it is from where its triangles put it (0: it rides).
"""

import json
import math
import os
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "blender"))

import addon_loader  # noqa: E402
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402

ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = ARGS[ARGS.index("--out") + 1] if "--out" in ARGS else os.path.join("out", "gp_face.blend")


def face_strokes(head):
    """Two eyes (small circles) and a mouth (an arc) inside the head's box, 1 mm in front."""
    lo, hi = head.min(axis=0), head.max(axis=0)
    c, r = (lo + hi) / 2, (hi - lo) / 2
    z = hi[2] + 0.001
    ring = [(math.cos(a), math.sin(a)) for a in np.linspace(0, 2 * math.pi, 13)]
    eyes = [[(c[0] + sx * 0.4 * r[0] + 0.12 * r[0] * x, c[1] + 0.3 * r[1] + 0.12 * r[0] * y, z)
             for x, y in ring] for sx in (-1, 1)]
    mouth = [(c[0] + 0.5 * r[0] * math.cos(a), c[1] - 0.2 * r[1] + 0.3 * r[1] * math.sin(a), z)
             for a in np.linspace(math.pi * 1.15, math.pi * 1.85, 9)]
    return eyes + [mouth]


def main():
    addon = addon_loader.enable()
    bpy.ops.wm.read_homefile(use_empty=True)
    obj, ranges = cb.one_object(cc.character()[0])
    addon.bake(obj, target=cb.TARGET, count=9)
    slider = cb.TARGET + ".bdi"
    for frame, value in ((1, 0.0), (48, 1.0)):
        obj[slider] = value
        obj.keyframe_insert('["%s"]' % slider, frame=frame)
    head = cb.world(obj, cb.read(obj, "Basis"))[list(ranges["Head"])]
    coll = bpy.data.grease_pencils_v3 if hasattr(bpy.data, "grease_pencils_v3") else bpy.data.grease_pencils
    gp = coll.new("Face")
    drawing = gp.layers.new("Lines").frames.new(1).drawing
    strokes = face_strokes(head)
    drawing.add_strokes([len(s) for s in strokes])
    for stroke, points in zip(drawing.strokes, strokes):
        for p, co in zip(stroke.points, points):
            p.position, p.radius = co, 0.01
    face = bpy.data.objects.new("Face", gp)
    bpy.context.scene.collection.objects.link(face)
    drawn = np.array([tuple(p.position) for s in drawing.strokes for p in s.points])
    addon.bind_drawing(face, obj)
    bpy.context.scene.frame_set(48)
    moved = np.array([tuple(p.position) for s in gp.layers[0].frames[0].drawing.strokes for p in s.points])
    os.makedirs(os.path.dirname(os.path.abspath(OUT)), exist_ok=True)
    bpy.context.scene.frame_set(1)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(OUT))
    print("JSON:" + json.dumps({"points": len(drawn), "moved": float(np.abs(moved - drawn).max()),
                                "file": os.path.abspath(OUT)}), flush=True)


main()
