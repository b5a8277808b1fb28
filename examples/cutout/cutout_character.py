"""The cut-out character of examples/cutout, built the way an animator builds one:
seven loose pieces (torso, head, two eyes, upper arm, forearm, hand) as quad grids and n-gons,
overlapping where they are pinned, each at its own small depth for draw order. The key 'Pose'
raises the arm by 150 degrees at the shoulder, bends the elbow by 90 degrees and tilts the head
by 30 degrees: every piece moves rigidly, about pins shared by both keys.

numpy only: examples/make_examples.py writes examples/cutout/*.obj from it, the Blender tests
(tests/blender/test_cutout.py) and examples/cutout/bake_cutout.py build objects from it.
"""

from collections import namedtuple

import numpy as np

Piece = namedtuple("Piece", "name source target polygons")   # source/target (n, 3), polygons
Joint = namedtuple("Joint", "parent child point")             # piece names, (2,) in the source

DEPTH = 0.01  # between neighbouring layers (the character is 5.5 high)
NECK, SHOULDER, ELBOW, WRIST = (0.0, 2.85), (1.25, 2.65), (1.25, 1.05), (1.25, -0.68)
EYES = ((-0.3, 3.6), (0.3, 3.6))
ARM_UP, ELBOW_BEND, HEAD_TILT = 150.0, 90.0, 30.0  # degrees, counter-clockwise


def grid(x0, x1, y0, y1, nx, ny, keep=None):
    """Quad grid over [x0, x1] x [y0, y1]: (verts (n, 2), quads); keep(cx, cy) selects the cells
    (their corners only are kept, renumbered)."""
    xs, ys = np.meshgrid(np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1))
    verts = np.stack([xs.ravel(), ys.ravel()], axis=1)
    quads = [(j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i)
             for j in range(ny) for i in range(nx)]
    if keep is not None:
        quads = [q for q in quads if keep(*verts[list(q)].mean(axis=0))]
    used = np.unique(np.ravel(quads))
    new = np.full(len(verts), -1)
    new[used] = np.arange(len(used))
    return verts[used], [tuple(int(new[v]) for v in q) for q in quads]


def ngon(centre, radius, sides, squash=0.7):
    """One n-gon face: an ellipse's corners (an eye)."""
    a = np.linspace(0, 2 * np.pi, sides, endpoint=False)
    verts = np.stack([centre[0] + radius * np.cos(a), centre[1] + squash * radius * np.sin(a)], axis=1)
    return verts, [tuple(range(sides))]


def turn(degrees, pivot):
    """The rigid motion p -> R (p - pivot) + pivot, as a function of (n, 2) points."""
    a = np.radians(degrees)
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    pivot = np.asarray(pivot, dtype=float)
    return lambda p: (np.asarray(p) - pivot) @ R.T + pivot


def motions():
    """Each piece's rigid motion source -> target."""
    head = turn(HEAD_TILT, NECK)
    upper = turn(ARM_UP, SHOULDER)
    lower = lambda p: upper(turn(ELBOW_BEND, ELBOW)(p))  # noqa: E731 -- bent, then raised with it
    return {"Torso": lambda p: np.asarray(p, dtype=float), "Head": head, "EyeL": head,
            "EyeR": head, "UpperArm": upper, "Forearm": lower, "Hand": lower}


def shapes2d():
    """{name: (verts (n, 2), polygons)} of the pieces in the source, in draw order (back first)."""
    return {
        # the torso's shoulders reach out over the top of the arm (x in [-1.5, 1.5] above 2.4)
        "Torso": grid(-1.5, 1.5, 0.0, 3.0, 15, 15, keep=lambda x, y: abs(x) < 1.0 or y > 2.4),
        "Head": grid(-0.8, 0.8, 2.65, 4.25, 7, 8),  # vertices off the torso's diagonals
        "EyeL": ngon(EYES[0], 0.16, 10),
        "EyeR": ngon(EYES[1], 0.16, 10),
        "UpperArm": grid(1.05, 1.45, 0.9, 2.85, 2, 10),
        "Forearm": grid(1.07, 1.43, -0.8, 1.2, 2, 10),
        "Hand": grid(1.03, 1.47, -1.3, -0.55, 2, 4),
    }


def character():
    """([Piece], [Joint]): the pieces at depths 0, DEPTH, 2 DEPTH, ... (z, in draw order) and the
    pins between them."""
    moves, pieces = motions(), []
    for layer, (name, (verts, polys)) in enumerate(shapes2d().items()):
        z = np.full((len(verts), 1), layer * DEPTH)
        pieces.append(Piece(name, np.hstack([verts, z]), np.hstack([moves[name](verts), z]), polys))
    joints = [Joint("Torso", "Head", NECK), Joint("Head", "EyeL", EYES[0]),
              Joint("Head", "EyeR", EYES[1]), Joint("Torso", "UpperArm", SHOULDER),
              Joint("UpperArm", "Forearm", ELBOW), Joint("Forearm", "Hand", WRIST)]
    return pieces, [Joint(j.parent, j.child, np.array(j.point, dtype=float)) for j in joints]


def one_mesh(pieces):
    """The pieces as one mesh: (source (n, 3), target (n, 3), polygons, {name: vertex range})."""
    offsets = np.cumsum([0] + [len(p.source) for p in pieces])
    polys = [tuple(int(v + o) for v in f) for p, o in zip(pieces, offsets) for f in p.polygons]
    ranges = {p.name: range(int(a), int(b)) for p, a, b in zip(pieces, offsets[:-1], offsets[1:])}
    return (np.concatenate([p.source for p in pieces]), np.concatenate([p.target for p in pieces]),
            polys, ranges)


def fan(polygons):
    """(m, 3) triangles of convex polygons (the .obj files of the example are triangle meshes)."""
    return np.array([(f[0], f[i], f[i + 1]) for f in polygons for i in range(1, len(f) - 1)])


def carried(point, X0, tris):
    """(triangle index, barycentric coordinates (3,)) of the first of tris (m, 3) that holds the
    2D point in X0 (its first two coordinates); ValueError if none does."""
    for i, (a, b, c) in enumerate(tris):
        m = np.column_stack([X0[b, :2] - X0[a, :2], X0[c, :2] - X0[a, :2]])
        u, v = np.linalg.solve(m, np.asarray(point) - X0[a, :2])
        if min(u, v, 1 - u - v) >= -1e-12:
            return i, np.array([1 - u - v, u, v])
    raise ValueError("no triangle holds %s" % (point,))


def joint_openings(X0, frames, tris_of, joints, size):
    """{(parent, child): the largest distance in the picture plane (x, y; the depths apart) over
    frames (k, n, 3) between where the parent's and the child's triangles (tris_of[name]: (m, 3)
    vertex indices into X0) carry the pin, relative to size}: how far the joint opens, measured
    without the solver."""
    out = {}
    for j in joints:
        ends = []
        for name in (j.parent, j.child):
            i, w = carried(j.point, X0, tris_of[name])
            ends.append((tris_of[name][i], w))
        (tp, wp), (tc, wc) = ends
        gap = [np.linalg.norm(wp @ X[tp, :2] - wc @ X[tc, :2]) for X in frames]
        out[(j.parent, j.child)] = max(gap) / size
    return out
