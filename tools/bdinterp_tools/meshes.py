"""Deterministic test and example meshes.

Every generator returns ``(V, F)`` with

- ``V``: (n, 2) float64 vertex positions,
- ``F``: (m, 3) int32 faces, counter-clockwise (positive signed area),

and every vertex used by some face.  Meshes are built from a jittered,
randomly rotated hexagonal point set (so edges are not aligned with the
axes) plus evenly spaced boundary samples, triangulated by Delaunay.  The
same ``seed`` always gives the same mesh.

The sampling helpers (:func:`sample_polygon`, :func:`polygon_contains`) use
numpy only, so Blender's Python (which has no scipy) can load this file
directly to mesh an outline with its own constrained Delaunay mesher.
"""

import numpy as np

__all__ = [
    "disk", "rectangle", "polygon", "refine", "disk_sequence",
    "sample_polygon", "polygon_contains", "lattice_spacing",
    "resample_closed", "boundary_edges", "signed_areas", "circle_outline",
    "rectangle_outline", "MAPS", "MAP_DOMAIN", "apply_map", "map_jacobian",
    "blended_distortion",
]

# Jitter and boundary clearance in units of the point spacing h: enough
# randomness to break lattice symmetry, small enough that Delaunay gives
# no slivers.
_JITTER = 0.2
_CLEARANCE = 0.6


def signed_areas(V, F):
    """Signed areas (m,) of faces F (m,3) over vertices V (n,2); > 0 = CCW."""
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    a = V[F[:, 1]] - V[F[:, 0]]
    b = V[F[:, 2]] - V[F[:, 0]]
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def near_faces(F, seed, rings=2):
    """Boolean (m,) mask of the faces F (m,3) within `rings` vertex-sharing steps of the faces of
    the boolean mask `seed` (m,): "a `rings`-face neighbourhood" (two rings around
    the folds)."""
    F = np.asarray(F)
    near = np.asarray(seed, bool).copy()
    for _ in range(rings):
        touched = np.zeros(F.max() + 1, bool)
        touched[F[near].ravel()] = True
        near = touched[F].any(axis=1)
    return near


def boundary_edges(F):
    """Directed boundary edges (k,2) of faces F (m,3): edges in one face only.

    For a CCW mesh the edges run counter-clockwise around the outside.
    """
    F = np.asarray(F)
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    key = np.sort(e, axis=1)
    _, inv, count = np.unique(key, axis=0, return_inverse=True,
                              return_counts=True)
    return e[count[inv.ravel()] == 1]


def circle_outline(n, center=(0.0, 0.0), radius=1.0):
    """(n,2) CCW points on a circle."""
    a = 2.0 * np.pi * np.arange(n) / n
    return np.asarray(center, float) + radius * np.c_[np.cos(a), np.sin(a)]


def rectangle_outline(w, h, origin=(0.0, 0.0)):
    """(4,2) CCW corners of the axis-aligned rectangle [0,w]x[0,h] + origin."""
    return np.asarray(origin, float) + np.array(
        [[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])


def _polygon_area(P):
    x, y = P[:, 0], P[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def polygon_contains(P, X):
    """Boolean (k,) mask: which points X (k,2) lie inside polygon P (n,2).

    Even-odd ray casting; P is a closed outline without repeated last point.
    """
    P = np.asarray(P, float)
    X = np.asarray(X, float)
    a, b = P, np.roll(P, -1, axis=0)
    x, y = X[:, None, 0], X[:, None, 1]
    crosses = (a[None, :, 1] > y) != (b[None, :, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
        xc = a[:, 0] + (y - a[:, 1]) * slope
    return np.count_nonzero(crosses & (x < xc), axis=1) % 2 == 1


def _distance_to_outline(P, X):
    """Distance (k,) from points X (k,2) to the closed polyline P (n,2)."""
    a, b = P, np.roll(P, -1, axis=0)
    d = b - a
    rel = X[:, None, :] - a[None, :, :]
    s = np.clip(np.sum(rel * d, axis=2) / np.sum(d * d, axis=1), 0.0, 1.0)
    foot = a[None, :, :] + s[:, :, None] * d[None, :, :]
    return np.min(np.linalg.norm(X[:, None, :] - foot, axis=2), axis=1)


def lattice_spacing(P, n_approx):
    """Point spacing h giving about n_approx lattice points inside outline P.

    A hexagonal lattice of spacing h has 2 / (sqrt(3) h^2) points per area.
    """
    return np.sqrt(2.0 * abs(_polygon_area(np.asarray(P, float)))
                   / (np.sqrt(3.0) * n_approx))


def resample_closed(P, h):
    """Points evenly spaced by arc length (spacing <= h) along closed P (n,2).

    For finely sampled curved outlines; corners of P may be cut by < h/2.
    """
    P = np.asarray(P, float)
    seg = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1)
    s = np.r_[0.0, np.cumsum(seg)]
    k = max(3, int(np.ceil(s[-1] / h)))
    u = np.arange(k) * s[-1] / k
    Q = np.vstack([P, P[:1]])
    return np.c_[np.interp(u, s, Q[:, 0]), np.interp(u, s, Q[:, 1])]


def _resample_outline(P, h):
    """Points along closed polyline P, spacing <= h, keeping P's corners."""
    out = []
    for a, b in zip(P, np.roll(P, -1, axis=0)):
        k = max(1, int(np.ceil(np.linalg.norm(b - a) / h)))
        s = np.arange(k)[:, None] / k
        out.append(a + s * (b - a))
    return np.concatenate(out)


def sample_polygon(P, n_approx, seed=0, *, resample=True):
    """Boundary and interior sample points of polygon P for meshing.

    Parameters
    ----------
    P : (n,2) closed outline (no repeated last point), either orientation.
    n_approx : wanted total number of points (approximate).
    seed : random seed (lattice rotation, offset and jitter).
    resample : if True, insert points on long outline segments so that the
        boundary spacing matches the interior spacing; if False, P is used
        as the boundary as it is (it must already be finely sampled).

    Returns
    -------
    B : (b,2) boundary points in outline order.
    I : (k,2) interior points, each at least 0.6 h from the outline.
    h : the point spacing used.
    """
    P = np.asarray(P, dtype=np.float64)
    if P.ndim != 2 or P.shape[1] != 2 or len(P) < 3:
        raise ValueError(f"outline must be (n>=3, 2), got {P.shape}")
    if n_approx < 3:
        raise ValueError(f"n_approx must be >= 3, got {n_approx}")
    h = lattice_spacing(P, n_approx)
    B = _resample_outline(P, h) if resample else P
    rng = np.random.default_rng(seed)
    lo, hi = P.min(axis=0), P.max(axis=0)
    R = np.linalg.norm(hi - lo)
    k = int(np.ceil(R / h)) + 2
    i, j = np.meshgrid(np.arange(-k, k + 1), np.arange(-k, k + 1))
    lattice = np.c_[(i + 0.5 * (j % 2)).ravel(),
                    (j * np.sqrt(3.0) / 2.0).ravel()] * h
    ang = rng.uniform(0.0, np.pi / 3.0)
    rot = np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
    X = lattice @ rot.T + 0.5 * (lo + hi) + rng.uniform(-h, h, 2)
    r = _JITTER * h * np.sqrt(rng.uniform(size=len(X)))
    phi = rng.uniform(0.0, 2.0 * np.pi, len(X))
    X += np.c_[r * np.cos(phi), r * np.sin(phi)]
    X = X[np.all((X > lo) & (X < hi), axis=1)]
    X = X[polygon_contains(P, X)]
    X = X[_distance_to_outline(B, X) >= _CLEARANCE * h]
    return B, X, h


def _delaunay(X, inside=None, outline=None):
    """Delaunay triangulation of X as CCW int32 faces, dropping degenerate
    faces and, if ``outline`` is given, faces whose centroid is outside it."""
    from scipy.spatial import Delaunay  # scipy only where triangulating
    F = Delaunay(X).simplices.astype(np.int32)
    area = signed_areas(X, F)
    F[area < 0] = F[area < 0][:, [0, 2, 1]]
    scale = np.ptp(X, axis=0).max() ** 2
    keep = np.abs(area) > 1e-12 * scale
    if outline is not None:
        keep &= polygon_contains(outline, X[F].mean(axis=1))
    return _compact(X, F[keep])


def _compact(V, F):
    """Drop vertices used by no face; renumber faces to match."""
    used = np.unique(F)
    remap = np.full(len(V), -1, dtype=np.int32)
    remap[used] = np.arange(len(used), dtype=np.int32)
    return np.ascontiguousarray(V[used]), remap[F]


def polygon(P, n_approx=500, seed=0):
    """Mesh (V, F) of a *convex* polygon P (n,2) with about n_approx vertices.

    Non-convex outlines need a constrained mesher (the character example
    uses Blender's); Delaunay of the samples would fill concavities.
    """
    B, I, _ = sample_polygon(P, n_approx, seed)
    return _delaunay(np.concatenate([B, I]))


def disk(n_approx=500, seed=0, *, center=(0.0, 0.0), radius=1.0):
    """Mesh (V, F) of the disk |x - center| <= radius, ~n_approx vertices."""
    if radius <= 0:
        raise ValueError(f"radius must be > 0, got {radius}")
    # Boundary spacing ~ interior spacing h: 2 pi r / h points on the circle.
    h = lattice_spacing(circle_outline(64, center, radius), n_approx)
    P = circle_outline(max(8, int(round(2.0 * np.pi * radius / h))),
                       center, radius)
    B, I, _ = sample_polygon(P, n_approx, seed, resample=False)
    return _delaunay(np.concatenate([B, I]))


def rectangle(w, h, n_approx=500, seed=0, *, origin=(0.0, 0.0)):
    """Mesh (V, F) of [0,w]x[0,h] + origin with ~n_approx vertices."""
    if w <= 0 or h <= 0:
        raise ValueError(f"rectangle sides must be > 0, got {w} x {h}")
    return polygon(rectangle_outline(w, h, origin), n_approx, seed)


def refine(V, F, snap=None):
    """Midpoint (1-to-4) subdivision: every edge is halved.

    Parameters
    ----------
    V : (n,d) vertices; F : (m,3) faces.
    snap : optional callable (k,d) -> (k,d) applied to the new vertices on
        boundary edges (e.g. project onto a circle so the domain converges).

    Returns
    -------
    V2 : (n + #edges, d), the first n rows equal V.
    F2 : (4m, 3) int32, same orientation as F.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F)
    e = np.concatenate([F[:, [1, 2]], F[:, [2, 0]], F[:, [0, 1]]])
    key = np.sort(e, axis=1)
    uniq, inv, count = np.unique(key, axis=0, return_inverse=True,
                                 return_counts=True)
    inv = inv.ravel()
    mid = 0.5 * (V[uniq[:, 0]] + V[uniq[:, 1]])
    if snap is not None:
        on_boundary = count == 1
        mid[on_boundary] = snap(mid[on_boundary])
    m = len(F)
    # Midpoint opposite corner k of face f has index n + inv[k*m + f].
    a, b, c = (len(V) + inv[k * m:(k + 1) * m] for k in range(3))
    i, j, k = F[:, 0], F[:, 1], F[:, 2]
    F2 = np.concatenate([np.c_[i, c, b], np.c_[c, j, a], np.c_[b, a, k],
                         np.c_[a, b, c]]).astype(np.int32)
    return np.concatenate([V, mid]), F2


def disk_sequence(levels, n0=100, seed=0, *, center=(0.0, 0.0), radius=1.0):
    """Refinement sequence of disk meshes: list of ``levels`` (V, F) pairs.

    Level 0 is ``disk(n0, seed, ...)``; each next level is :func:`refine` of
    the previous one with new boundary vertices projected onto the circle, so
    edge lengths halve and the vertex count grows about 4x per level.
    """
    c = np.asarray(center, float)

    def to_circle(X):
        d = X - c
        return c + radius * d / np.linalg.norm(d, axis=1, keepdims=True)

    meshes = [disk(n0, seed, center=center, radius=radius)]
    for _ in range(levels - 1):
        meshes.append(refine(*meshes[-1], snap=to_circle))
    return meshes


# ---------------------------------------------------------------------------
# Analytic maps with known continuous distortion (paper Sec. 4.3).
#
# Each map is phi = alpha * m(z) + beta * conj(m(z)) with a Moebius map
# m(z) = (a z + b) / (c z + d), so phi_z = alpha m' and phi_zbar =
# beta conj(m'): a Teichmueller map of constant dilatation |beta / alpha|
# (beta = 0: conformal).  The three of Fig. 6 are written in this form:
#   phi1 = 2z/(z-5) + (2/3) conj(z)/(conj(z)-5):  m + conj(m)/3,
#          m = 2z/(z-5)
#   phi2 = 20/(2z-5) + 12/(2conj(z)-5):  m + 0.6 conj(m),  m = 20/(2z-5)
#   phi3 = 3(4z+5)/(3z+1) + (4conj(z)+5)/(3conj(z)+1):  3m + conj(m),
#          m = (4z+5)/(3z+1)
# "mobius" is the conformal map m of phi3.  Their poles (5, 2.5, -1/3) lie
# outside MAP_DOMAIN, the disk the examples and the convergence test use.
# ---------------------------------------------------------------------------

MAPS = {
    "phi1": (1.0, 1.0 / 3.0, (2.0, 0.0, 1.0, -5.0)),
    "phi2": (1.0, 0.6, (0.0, 20.0, 2.0, -5.0)),
    "phi3": (3.0, 1.0, (4.0, 5.0, 3.0, 1.0)),
    "mobius": (1.0, 0.0, (4.0, 5.0, 3.0, 1.0)),
}

# center, radius of a disk away from every pole above (distance >= 1.6).
MAP_DOMAIN = ((1.0, 1.0), 1.0)


def _map_parts(name):
    try:
        alpha, beta, (a, b, c, d) = MAPS[name]
    except KeyError:
        raise ValueError(f"unknown map '{name}'; known: "
                         f"{', '.join(MAPS)}") from None
    return alpha, beta, a, b, c, d


def apply_map(name, X):
    """Image (n,2) of points X (n,2) under the named map of ``MAPS``."""
    alpha, beta, a, b, c, d = _map_parts(name)
    X = np.asarray(X, dtype=np.float64)
    z = X[:, 0] + 1j * X[:, 1]
    m = (a * z + b) / (c * z + d)
    w = alpha * m + beta * np.conj(m)
    return np.c_[w.real, w.imag]


def map_jacobian(name, X):
    """Jacobians (n,2,2) of the named map at points X (n,2)."""
    alpha, beta, a, b, c, d = _map_parts(name)
    X = np.asarray(X, dtype=np.float64)
    z = X[:, 0] + 1j * X[:, 1]
    dm = (a * d - b * c) / (c * z + d) ** 2
    fz, fzbar = alpha * dm, beta * np.conj(dm)
    # d phi = fz dz + fzbar dzbar, so d/dx = fz + fzbar, d/dy = i (fz - fzbar).
    dx, dy = fz + fzbar, 1j * (fz - fzbar)
    return np.stack([np.c_[dx.real, dy.real], np.c_[dx.imag, dy.imag]],
                    axis=1)


def blended_distortion(name, X, t):
    """Continuous distortion K_t (n,) of the blended metric at points X.

    M_t = (1 - t) I + t J^T J with J the map's Jacobian; K_t is
    sqrt(lambda_max / lambda_min) of M_t (paper Sec. 4.3).  The conformal
    rescaling of the method does not change it, so it is the exact limit of
    the discrete per-face distortion under refinement.
    """
    J = map_jacobian(name, X)
    M = (1.0 - t) * np.eye(2) + t * np.einsum("nki,nkj->nij", J, J)
    lam = np.linalg.eigvalsh(M)
    return np.sqrt(lam[:, 1] / lam[:, 0])
