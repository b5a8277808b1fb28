"""Grease Pencil v3 drawings from examples/strokes/drawn.py, read back, and Blender's own
Interpolate Sequence on them (Blender 4.3+; used by tests/blender/test_strokes.py and
scripts/strokes_gallery.py)."""
import bpy
import numpy as np


def xz(points):
    """2D drawing coordinates onto Blender's front view (the XZ plane)."""
    p = np.asarray(points, dtype=float)
    return np.stack([p[:, 0], np.zeros(len(p)), p[:, 1]], 1)


def gp_object(name, keys):
    """A Grease Pencil object with one layer `name` and a keyframe per entry of keys
    {frame: [(points (n, 2), radius (n,), opacity (n,))]}, each point set one by one as a script
    draws it; made the active object."""
    coll = bpy.data.grease_pencils_v3 if hasattr(bpy.data, "grease_pencils_v3") else bpy.data.grease_pencils
    gp = coll.new(name)
    layer = gp.layers.new(name)
    for frame, strokes in keys.items():
        d = layer.frames.new(frame).drawing
        d.add_strokes([len(p) for p, _, _ in strokes])
        for s, (p, radius, opacity) in zip(d.strokes, strokes):
            for q, co, r, o in zip(s.points, xz(p), radius, opacity):
                q.position, q.radius, q.opacity = tuple(co), float(r), float(o)
    obj = bpy.data.objects.new(name, gp)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    return obj


def strokes_at(obj, frame):
    """[{points (n, 3), radius (n,), opacity (n,)}] of the first layer's drawing at frame."""
    layer = obj.data.layers[0]
    drawing = next(f.drawing for f in layer.frames if f.frame_number == frame)
    out = []
    for s in drawing.strokes:
        pts = s.points
        out.append({"points": np.array([tuple(p.position) for p in pts], dtype=np.float32),
                    "radius": np.array([p.radius for p in pts], dtype=np.float32),
                    "opacity": np.array([p.opacity for p in pts], dtype=np.float32)})
    return out


def blender_interpolate(obj, frame, step, flip='NONE'):
    """Blender's own Interpolate Sequence from the keyframe at `frame` to the next, every `step`
    frames (edit mode, active layer)."""
    bpy.context.view_layer.objects.active = obj
    obj.data.layers.active = obj.data.layers[0]
    bpy.context.scene.frame_set(frame)
    bpy.ops.object.mode_set(mode='EDIT')
    try:
        assert bpy.ops.grease_pencil.interpolate_sequence(step=step, flip=flip) == {'FINISHED'}
    finally:
        bpy.ops.object.mode_set(mode='OBJECT')
