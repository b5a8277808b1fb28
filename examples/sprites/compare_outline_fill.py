"""The sprites' meshes against an outline-only fill (COA Tools 2's Automesh approach: the contour
filled by Blender's bmesh.ops.triangle_fill, no interior vertices), on the same outline: the
boundary loops of mesh_from_image's mesh. Prints a Markdown table. Runs inside Blender:

    PYTHONPATH=python blender --background --factory-startup --python examples/sprites/compare_outline_fill.py
"""
import pathlib
import sys

import bmesh
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parents[1] / "tools"), str(HERE.parents[1] / "python")]

import bdinterp  # noqa: E402
from bdinterp_tools.sprites import SPRITES  # noqa: E402


def smallest_angle(points):
    """Smallest angle (degrees) of triangles given as (m, 3, 2) arrays."""
    out = []
    for k in range(3):
        u, w = points[:, (k + 1) % 3] - points[:, k], points[:, (k + 2) % 3] - points[:, k]
        cos = (u * w).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return float(np.min(out))


def outline_fill(mesh):
    """triangle_fill (beauty) of the mesh's boundary edges: (faces' points, interior vertices)."""
    F = mesh.faces
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    e, count = np.unique(e, axis=0, return_counts=True)
    boundary = e[count == 1]
    bm = bmesh.new()
    verts = {i: bm.verts.new((*mesh.vertices[i], 0.0)) for i in np.unique(boundary)}
    edges = [bm.edges.new((verts[a], verts[b])) for a, b in boundary]
    bmesh.ops.triangle_fill(bm, use_beauty=True, use_dissolve=False, edges=edges)
    tris = np.array([[v.co[:2] for v in f.verts] for f in bm.faces if len(f.verts) == 3])
    interior = sum(1 for v in bm.verts if not v.is_boundary)
    bm.free()
    return tris, interior


def main():
    print("| sprite | mesh_from_image: interior vertices | smallest angle | outline-only fill: "
          "interior vertices | smallest angle |")
    print("|---|---:|---:|---:|---:|")
    for name, draw in SPRITES.items():
        mesh = bdinterp.mesh_from_image(draw())
        F = mesh.faces
        e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
        e, count = np.unique(e, axis=0, return_counts=True)
        interior = len(mesh.vertices) - len(np.unique(e[count == 1]))
        tris, fill_interior = outline_fill(mesh)
        print(f"| {name} | {interior} | {smallest_angle(mesh.vertices[F]):.1f}° | {fill_interior} | "
              f"{smallest_angle(tris):.1f}° |")


main()
