"""Build examples/letter_8/{source,target}.obj: the digit 8, a piece with two holes.

Run from the repository root::

    /usr/bin/python3 examples/letter_8/make_letter_8.py

The outline is the union of two unit circles (centres (0, +-0.9)), the holes are circles of radius
0.42 at (0, +-0.95); boundary points are spaced like the jittered interior lattice
(tools/bdinterp_tools/meshes.py) and the Delaunay triangles inside the outline and outside both holes are kept.
The target leans the 8 like an italic glyph and twists it: every point turns about the origin by
0.35 y radians, x is stretched by 1.15 and sheared by 0.25 y. No target triangle is flipped.
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))

from bdinterp import io  # noqa: E402
from bdinterp_tools import meshes  # noqa: E402

N_VERTICES = 1500
SEED = 8
HOLES = [((0.0, 0.95), 0.42), ((0.0, -0.95), 0.42)]


def outline(step):
    """(n,2) CCW outline of the union of the two circles, points about `step` apart."""
    a = np.arctan2(0.9, np.sqrt(1 - 0.81))  # the waist: where the circles cross
    k = int(np.ceil((np.pi + 2 * a) / step))
    top = np.linspace(-a, np.pi + a, k, endpoint=False)  # each arc ends at the next one's start
    bottom = np.linspace(np.pi - a, 2 * np.pi + a, k, endpoint=False)
    return np.vstack([np.c_[np.cos(top), 0.9 + np.sin(top)], np.c_[np.cos(bottom), -0.9 + np.sin(bottom)]])


def mesh(n_approx=N_VERTICES, seed=SEED):
    from scipy.spatial import Delaunay
    h = meshes.lattice_spacing(outline(0.01), n_approx)
    P = outline(h)
    B, X, h = meshes.sample_polygon(P, n_approx, seed, resample=False)
    rings = []
    for (cx, cy), r in HOLES:
        X = X[np.hypot(X[:, 0] - cx, X[:, 1] - cy) > r + 0.6 * h]
        k = int(np.ceil(2 * np.pi * r / h))
        t = np.linspace(0, 2 * np.pi, k, endpoint=False)
        rings.append(np.c_[cx + r * np.cos(t), cy + r * np.sin(t)])
    V = np.vstack([B, *rings, X])
    F = Delaunay(V).simplices.astype(np.int64)
    c = V[F].mean(axis=1)
    keep = meshes.polygon_contains(P, c)
    for (cx, cy), r in HOLES:
        keep &= np.hypot(c[:, 0] - cx, c[:, 1] - cy) > r
    F = F[keep]
    flip = meshes.signed_areas(V, F) < 0
    F[flip] = F[flip][:, [0, 2, 1]]
    used = np.unique(F)
    remap = np.full(len(V), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return V[used], remap[F]


def pose(V):
    x, y = V[:, 0], V[:, 1]
    a = 0.35 * y
    xr, yr = np.cos(a) * x - np.sin(a) * y, np.sin(a) * x + np.cos(a) * y
    return np.c_[1.15 * xr + 0.25 * yr, yr]


def main():
    V, F = mesh()
    Y = pose(V)
    io.write_obj(os.path.join(HERE, "source.obj"), V, F, comment="bdinterp example 'letter_8': source")
    io.write_obj(os.path.join(HERE, "target.obj"), Y, F, comment="bdinterp example 'letter_8': target")
    loops = len(meshes.boundary_edges(F))
    flipped = np.count_nonzero(meshes.signed_areas(Y, F) <= 0)
    print(f"letter_8: {len(V)} vertices, {len(F)} faces, {loops} boundary edges, {flipped} flipped in target")


main()
