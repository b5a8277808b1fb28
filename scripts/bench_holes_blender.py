"""Issue #21 point 1 where users are: inside Blender, a text-to-mesh "8" (Blender's text tool,
subdivided twice: two holes, ~4.6k vertices) against a Blender grid of about the same vertex count,
the same kind of target; warm slider frames (t = 0.30 .. 0.70 after 0.29), meshes taking turns.

    BDINTERP_PATH=DIR [BDINTERP_THREADS=N] blender --background --factory-startup --python scripts/bench_holes_blender.py

DIR holds the bdinterp package for Blender's Python (python/ for 3.4 on Debian 12; an unpacked
cp313 / cp314 wheel of the extension zip inside the Debian 13 / unstable chroots).
"""
import os
import sys
import time

import bmesh
import bpy
import numpy as np

sys.path.insert(0, os.environ["BDINTERP_PATH"])
import bdinterp  # noqa: E402


def triangles(obj):
    """(V #V x 2, F #F x 3) of a mesh object, triangulated by bmesh."""
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.triangulate(bm, faces=bm.faces)
    V = np.array([v.co[:2] for v in bm.verts])
    F = np.array([[v.index for v in f.verts] for f in bm.faces])
    bm.free()
    return V, F


def target(V):
    """A smooth shear, stretch and bend over the mesh's normalised coordinates."""
    x, y = V[:, 0] / np.ptp(V[:, 0]), V[:, 1] / np.ptp(V[:, 1])
    return np.stack([1.2 * x + 0.5 * y * y, 0.8 * y + 0.2 * x + 0.4 * np.sin(np.pi * x)], axis=1)


def glyph_8():
    bpy.ops.object.text_add()
    bpy.context.object.data.body = "8"
    bpy.context.object.data.resolution_u = 48
    bpy.ops.object.convert(target='MESH')
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.remove_doubles(threshold=1e-5)
    bpy.ops.mesh.subdivide(number_cuts=2)
    bpy.ops.object.mode_set(mode='OBJECT')
    return triangles(bpy.context.object)


def main():
    threads = int(os.environ.get("BDINTERP_THREADS", "0"))
    V8, F8 = glyph_8()
    side = max(2, int(round(np.sqrt(len(V8)))) - 1)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side, y_subdivisions=side, size=1.0)
    cases = {"text 8": (V8, F8), "grid": triangles(bpy.context.object)}
    times = {name: [] for name in cases}
    for _ in range(6):
        for name, (V, F) in cases.items():
            interp = bdinterp.Interpolator([V, target(V)], F, threads=threads)
            interp.at(0.29)
            for t in np.arange(0.30, 0.705, 0.01):
                s = time.perf_counter()
                interp.at(t)
                times[name].append(time.perf_counter() - s)
    w8, wg = np.median(times["text 8"]), np.median(times["grid"])
    print("Blender %s, threads=%d: text 8 %d vertices %.3f ms, grid %d vertices %.3f ms, ratio %.2f"
          % (bpy.app.version_string, threads, len(V8), 1e3 * w8, len(cases["grid"][0]), 1e3 * wg, w8 / wg))


main()
