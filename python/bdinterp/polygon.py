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


def _cross(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _is_ear(uv, ring, i):
    """Corner ring[i] of the counter-clockwise ring is convex and no other ring vertex lies in its
    triangle (on the boundary counts as inside, so no triangle gets a vertex on an edge)."""
    a, b, c = (uv[ring[(i + d) % len(ring)]] for d in (-1, 0, 1))
    if _cross(a, b, c) <= 0:
        return False
    for j in ring:
        p = uv[j]
        if j in (ring[i - 1], ring[i], ring[(i + 1) % len(ring)]) or (p == a).all() or \
                (p == b).all() or (p == c).all():
            continue
        if _cross(a, b, p) >= 0 and _cross(b, c, p) >= 0 and _cross(c, a, p) >= 0:
            return False
    return True


def triangulate(indices, points):
    """Triangles (list of index triples, in the polygon's winding) of the polygon whose corners are
    `indices` into points (n, 2 or 3).

    Ear clipping: each step cuts off the first convex corner (from the second on) whose triangle
    holds no other corner, so a simple polygon, convex or not, gives k - 2 triangles that all wind
    like the polygon (a convex polygon gives the fan from its first corner). If no ear is found
    (a self-intersecting or degenerate polygon) the remaining corners are fanned.
    """
    if len(indices) == 3:
        return [tuple(indices)]
    P = np.asarray(points, dtype=np.float64)[list(indices)]
    uv = _in_plane(np.c_[P, np.zeros(len(P))] if P.shape[1] == 2 else P)
    ring = list(range(len(indices)))
    out = []
    while len(ring) > 3:
        ear = next((i for i in range(1, len(ring) + 1) if _is_ear(uv, ring, i % len(ring))), None)
        if ear is None:
            break
        i = ear % len(ring)
        out.append((ring[i - 1], ring[i], ring[(i + 1) % len(ring)]))
        del ring[i]
    out += [(ring[0], ring[k], ring[k + 1]) for k in range(1, len(ring) - 1)]
    return [tuple(indices[j] for j in tri) for tri in out]
