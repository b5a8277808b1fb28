"""Build examples/letter_e/{source,target}.obj: Blender's text 'e' converted to a mesh (a hole).

Run inside Blender (the glyph is Blender's own, filled by its text mesher)::

    blender --background --factory-startup --python-exit-code 1 \\
        --python examples/letter_e/make_letter_e.py

What an animator gets from Add > Text, 'e', Object > Convert > Mesh, Merge by Distance: the
glyph outline at the default curve resolution filled by Blender's triangulator, no interior
vertices, triangles down to an area / longest edge^2 of 3e-4 (a coarse input, unlike the
Delaunay examples). Centred and scaled to height 2; the target sways it like a letter on a
spring: every point turns about the glyph's foot by 0.4 (y + 1) radians, and x stretches by 1.1.
No target triangle is flipped. The files were made with Debian's Blender 3.4.1 (another Blender's
font or triangulator may give another mesh).
"""

import importlib.util
import os

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")


# bdinterp/io.py by file path: Blender's Python cannot import the bdinterp package (its compiled
# core is built for the system Python); io.py needs numpy only.
_spec = importlib.util.spec_from_file_location(
    "io", os.path.join(ROOT, "python", "bdinterp", "io.py"))
io = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(io)


def glyph(char="e"):
    """(V (n, 2), F (m, 3)) of Blender's filled text glyph, counter-clockwise, height 2."""
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.object.text_add()
    bpy.context.object.data.body = char
    bpy.ops.object.convert(target='MESH')
    obj = bpy.context.object
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.remove_doubles(threshold=1e-5)
    bpy.ops.object.mode_set(mode='OBJECT')
    me = obj.data
    me.calc_loop_triangles()
    V = np.array([v.co[:2] for v in me.vertices], dtype=np.float64)
    F = np.array([t.vertices[:] for t in me.loop_triangles], dtype=np.int64)
    lo, hi = V.min(axis=0), V.max(axis=0)
    V = (V - 0.5 * (lo + hi)) * (2.0 / (hi - lo)[1])
    a, b = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    cw = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0
    F[cw] = F[cw][:, [0, 2, 1]]
    return V, F


def pose(V):
    a = 0.4 * (V[:, 1] + 1.0)
    x, y = V[:, 0], V[:, 1] + 1.0
    return np.c_[1.1 * (np.cos(a) * x - np.sin(a) * y), np.sin(a) * x + np.cos(a) * y - 1.0]


def main():
    V, F = glyph()
    Y = pose(V)
    for name, X in (("source", V), ("target", Y)):
        io.write_obj(os.path.join(HERE, name + ".obj"), X, F,
                     comment="bdinterp example 'letter_e': " + name)
    a, b = Y[F[:, 1]] - Y[F[:, 0]], Y[F[:, 2]] - Y[F[:, 0]]
    flipped = np.count_nonzero(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] <= 0)
    print("letter_e: %d vertices, %d faces, %d flipped in target" % (len(V), len(F), flipped))


main()
