"""Which triangle of a layered mesh holds each of many points, with a uniform grid of buckets.

The points and triangles are projected into the mesh's common plane; each triangle goes into the
grid cells its bounding box covers, each point is tested only against the triangles of its own
cell.  A point inside a triangle is always found (the triangle's box covers the point's cell);
a point outside every triangle of its cell (drawn beside the mesh) takes the triangle it is
least outside of among the `NEAREST` triangles whose centroids are nearest (mathutils.kdtree).
Sorting the (cell, triangle) pairs makes it O((points + triangles) log), where testing every
point against every triangle was O(points x triangles).  numpy only: Blender bundles no scipy.
"""

NEAREST = 8     # triangles (nearest centroids) tried for a point outside the mesh
INSIDE = -1e-9  # smallest barycentric coordinate of a point counted as inside its triangle


def plane_basis(normals):
    """(3, 2) orthonormal basis of the plane whose normal is the sum of `normals` (m, 3)."""
    import numpy as np
    plane = normals.sum(axis=0)
    plane /= np.linalg.norm(plane)
    u = np.cross(plane, [1.0, 0.0, 0.0] if abs(plane[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    return np.stack([u, np.cross(plane, u)], axis=1)


class Triangles:
    """Triangles (m, 3, 2) in the plane, with what a point's barycentric coordinates need."""

    def __init__(self, corners):
        import numpy as np
        self.a = corners[:, 0]
        edges = np.stack([corners[:, 1] - self.a, corners[:, 2] - self.a], axis=2)  # (m, 2, 2)
        det = edges[:, 0, 0] * edges[:, 1, 1] - edges[:, 0, 1] * edges[:, 1, 0]
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)  # a degenerate triangle: far outside
        self.inv = np.stack([np.stack([edges[:, 1, 1], -edges[:, 0, 1]], axis=1),
                             np.stack([-edges[:, 1, 0], edges[:, 0, 0]], axis=1)], axis=1) / det[:, None, None]
        self.lo, self.hi = corners.min(axis=1), corners.max(axis=1)
        self.centroids = corners.mean(axis=1)

    def barycentric(self, points, tris):
        """(k, 3) barycentric coordinates of points (k, 2) in triangles tris (k,)."""
        import numpy as np
        l12 = np.einsum("kij,kj->ki", self.inv[tris], points - self.a[tris])
        return np.concatenate([1.0 - l12.sum(axis=1, keepdims=True), l12], axis=1)


def _best(pairs_point, pairs_tri, lam, count):
    """Per point (count of them): the pair whose smallest coordinate is largest: (tri (count,),
    lam (count, 3), found (count,) bool).  pairs_point is sorted."""
    import numpy as np
    tri, bary, found = np.zeros(count, dtype=np.int64), np.zeros((count, 3)), np.zeros(count, bool)
    if len(pairs_point):
        order = np.lexsort((-lam.min(axis=1), pairs_point))
        first = order[np.r_[True, pairs_point[order][1:] != pairs_point[order][:-1]]]
        points = pairs_point[first]
        tri[points], bary[points], found[points] = pairs_tri[first], lam[first], True
    return tri, bary, found


def _cells(tris, points):
    """(cell of each triangle's box as sorted (cell ids, triangles), cell id of each point)."""
    import numpy as np
    size = np.median((tris.hi - tris.lo).max(axis=1))
    size = size if size > 0 else max(float((tris.hi - tris.lo).max()), 1e-12)
    origin = np.minimum(tris.lo.min(axis=0), points.min(axis=0))
    i0 = np.floor((tris.lo - origin) / size).astype(np.int64)
    i1 = np.floor((tris.hi - origin) / size).astype(np.int64)
    rows = int(max(i1[:, 1].max(), np.floor((points[:, 1] - origin[1]) / size).max())) + 1
    width, count = i1[:, 0] - i0[:, 0] + 1, (i1[:, 0] - i0[:, 0] + 1) * (i1[:, 1] - i0[:, 1] + 1)
    tri = np.repeat(np.arange(len(count)), count)
    k = np.arange(len(tri)) - np.repeat(np.cumsum(count) - count, count)
    w = np.repeat(width, count)
    cell = (np.repeat(i0[:, 0], count) + k % w) * rows + np.repeat(i0[:, 1], count) + k // w
    order = np.argsort(cell, kind="stable")
    cp = np.floor((points - origin) / size).astype(np.int64)
    return (cell[order], tri[order]), cp[:, 0] * rows + cp[:, 1]


def _nearest(tris, points):
    """(tri, barycentric) of each point among its NEAREST triangles by centroid: the triangle it
    is least outside of."""
    import numpy as np
    from mathutils.kdtree import KDTree
    tree = KDTree(len(tris.centroids))
    for i, c in enumerate(tris.centroids):
        tree.insert((c[0], c[1], 0.0), i)
    tree.balance()
    k = min(NEAREST, len(tris.centroids))
    cand = np.array([[i for _, i, _ in tree.find_n((p[0], p[1], 0.0), k)] for p in points])
    pairs_point = np.repeat(np.arange(len(points)), k)
    lam = tris.barycentric(points[pairs_point], cand.ravel())
    tri, bary, _ = _best(pairs_point, cand.ravel(), lam, len(points))
    return tri, bary


def locate_2d(points, corners):
    """(triangle (p,), barycentric (p, 3)) of points (p, 2) among triangles corners (m, 3, 2)."""
    import numpy as np
    tris = Triangles(corners)
    (cells, cell_tris), point_cells = _cells(tris, points)
    start = np.searchsorted(cells, point_cells, "left")
    count = np.searchsorted(cells, point_cells, "right") - start
    pairs_point = np.repeat(np.arange(len(points)), count)
    pick = np.repeat(start, count) + np.arange(len(pairs_point)) - np.repeat(np.cumsum(count) - count, count)
    pairs_tri = cell_tris[pick]
    lam = tris.barycentric(points[pairs_point], pairs_tri)
    tri, bary, found = _best(pairs_point, pairs_tri, lam, len(points))
    outside = np.flatnonzero(~found | (bary.min(axis=1) < INSIDE))
    if len(outside):
        near, near_bary = _nearest(tris, points[outside])
        better = ~found[outside] | (near_bary.min(axis=1) > bary[outside].min(axis=1))
        tri[outside[better]], bary[outside[better]] = near[better], near_bary[better]
    return tri, bary
