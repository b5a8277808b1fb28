"""Warm frames of a piece with holes where users are: inside Blender, a text-to-mesh "8" (Blender's text tool,
subdivided twice and cleaned up: two holes, ~4.6k vertices) against a Blender grid of about the same
vertex count, under the same kind of bend; warm slider frames (t = 0.30 .. 0.70 after 0.29), meshes
taking turns. Refuses to compare unlike things: the "8" must be one piece with two holes and the
grid one disk, neither taking the fold path (FrameStats.fold_faces == 0).

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
    """A bend in both directions at the mesh's own scale (half its width as the unit), so that areas
    change by less than 1.6x (no fold seeds, docs/FOLDS.md) and the blended metric is not flat (a
    bend along x alone is exactly flat on a grid: zero Newton steps)."""
    unit = np.ptp(V[:, 0]) / 2
    x, y = (V - V.min(axis=0)).T / unit
    T = V.copy()
    T[:, 0] += 0.15 * unit * np.sin(np.pi * y)
    T[:, 1] += 0.3 * unit * np.sin(np.pi * x)
    return T


def smallest_angle(V, F):
    """The smallest corner angle of the triangles, in degrees."""
    P = V[F]
    cosines = []
    for c in range(3):
        a, b = P[:, (c + 1) % 3] - P[:, c], P[:, (c + 2) % 3] - P[:, c]
        cosines.append((a * b).sum(1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1))
    return np.degrees(np.arccos(np.clip(np.max(cosines), -1, 1)))


def glyph_8():
    """Blender's text "8" as a mesh, subdivided twice; the fill's slivers (3285 faces under 1 degree,
    which a bend flips) evened out by beautify-fill and smoothing of the inner vertices."""
    bpy.ops.object.text_add()
    bpy.context.object.data.body = "8"
    bpy.context.object.data.resolution_u = 48
    bpy.ops.object.convert(target='MESH')
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.remove_doubles(threshold=1e-5)
    bpy.ops.mesh.quads_convert_to_tris(quad_method='BEAUTY', ngon_method='BEAUTY')
    bpy.ops.mesh.subdivide(number_cuts=2)
    for _ in range(10):
        bpy.ops.mesh.select_all(action='SELECT')
        bpy.ops.mesh.beautify_fill()
        bpy.ops.mesh.select_all(action='DESELECT')
        bpy.ops.mesh.select_non_manifold(use_wire=False, use_boundary=True, use_multi_face=False,
                                         use_non_contiguous=False, use_verts=False)
        bpy.ops.mesh.select_all(action='INVERT')
        bpy.ops.mesh.vertices_smooth(factor=0.5, repeat=5)
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.beautify_fill()
    bpy.ops.object.mode_set(mode='OBJECT')
    return triangles(bpy.context.object)


def check_kind(name, stats, holes):
    """Exits unless the frame took the path compared: one piece, `holes` holes, no fold region."""
    kind = (stats["pieces"], len(stats["hole_closure"]), stats["fold_faces"])
    if kind != (1, holes, 0):
        sys.exit("%s: pieces, holes, fold faces = %s, not (1, %d, 0)" % (name, kind, holes))


def main():
    threads = int(os.environ.get("BDINTERP_THREADS", "0"))
    V8, F8 = glyph_8()
    side = max(2, int(round(np.sqrt(len(V8)))) - 1)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side, y_subdivisions=side, size=1.0)
    cases = {"text 8": (V8, F8, 2), "grid": triangles(bpy.context.object) + (0,)}
    times = {name: [] for name in cases}
    steps = {name: [] for name in cases}
    for _ in range(6):
        for name, (V, F, holes) in cases.items():
            interp = bdinterp.Interpolator([V, target(V)], F, threads=threads)
            interp.at(0.29)
            check_kind(name, interp.stats, holes)
            for t in np.arange(0.30, 0.705, 0.01):
                s = time.perf_counter()
                interp.at(t)
                times[name].append(time.perf_counter() - s)
                steps[name].append(interp.stats["iterations"])
    w8, wg = np.median(times["text 8"]), np.median(times["grid"])
    print("Blender %s, threads=%d: text 8 %d vertices (smallest angle %.1f deg) %.3f ms %.2f Newton steps, "
          "grid %d vertices %.3f ms %.2f Newton steps, ratio %.2f (means: %.2f)"
          % (bpy.app.version_string, threads, len(V8), smallest_angle(V8, F8), 1e3 * w8, np.mean(steps["text 8"]),
             len(cases["grid"][0]), 1e3 * wg, np.mean(steps["grid"]), w8 / wg,
             np.mean(times["text 8"]) / np.mean(times["grid"])))


main()
