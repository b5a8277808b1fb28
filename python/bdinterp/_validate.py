"""Input checks and plane handling shared by the public functions.

Everything the compiled core needs is turned into C-contiguous float64 (n, 2) and int32 (m, 3)
arrays here; arrays that already have that layout are passed through without a copy.
"""
from dataclasses import dataclass

import numpy as np

# Relative out-of-plane tolerance for 3D input: Blender stores float32 coordinates, whose rounding
# moves a rotated planar mesh off its plane by ~1e-7 of its size.
PLANAR_TOLERANCE = 1e-5


def coordinates(x, name):
    """Returns `x` as a float64 (n, 2) or (n, 3) array; ValueError naming `name` otherwise."""
    a = np.asarray(x, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] not in (2, 3):
        raise ValueError(f"{name} must be an (n, 2) or (n, 3) array of coordinates, got shape {a.shape}")
    if a.shape[0] == 0:
        raise ValueError(f"{name} has no vertices")
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if bad.size:
        raise ValueError(f"{name}: vertex {bad[0]} has a non-finite coordinate")
    return a


def faces(f, num_vertices):
    """Returns faces as a C-contiguous int32 (m, 3) array after checking the index range."""
    a = np.asarray(f)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"faces must be an (m, 3) array of vertex indices, got shape {a.shape}")
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"faces must be an integer array, got dtype {a.dtype}")
    if a.size:
        low, high = a.min(), a.max()
        if low < 0 or high >= num_vertices:
            bad = np.flatnonzero(((a < 0) | (a >= num_vertices)).any(axis=1))[0]
            raise ValueError(f"face {bad} has a vertex index out of range [0, {num_vertices}): "
                             f"{a[bad].tolist()}")
    return np.ascontiguousarray(a, dtype=np.int32)


@dataclass(frozen=True)
class Plane:
    """An orthonormal frame (origin, axes rows e1, e2, normal) of the plane of planar 3D input."""
    origin: np.ndarray
    axes: np.ndarray  # (2, 3)
    normal: np.ndarray

    @classmethod
    def fit(cls, points):
        origin = points.mean(axis=0)
        _, _, vt = np.linalg.svd(points - origin, full_matrices=False)
        # Right-handed (e1, e2, normal): the SVD's third row may be -e1 x e2, and two fits of
        # opposite handedness would mirror one shape's plane coordinates against the other's.
        return cls(origin, vt[:2].copy(), np.cross(vt[0], vt[1]))

    def to_plane(self, points, name, tolerance=PLANAR_TOLERANCE):
        """Plane coordinates (n, 2) of 3D `points`; ValueError if a point is off the plane."""
        rel = points - self.origin
        off = np.abs(rel @ self.normal)
        size = max(float(np.ptp(points, axis=0).max()), np.finfo(float).tiny)
        worst = int(np.argmax(off))
        if off[worst] > tolerance * size:
            raise ValueError(
                f"{name} is not planar: vertex {worst} is {off[worst]:.3g} off the plane of the base "
                f"shape (tolerance {tolerance:g} x size {size:.3g} = {tolerance * size:.3g})")
        return np.ascontiguousarray(rel @ self.axes.T)

    def to_space(self, uv):
        """3D points of plane coordinates uv (..., 2)."""
        return self.origin + uv @ self.axes


def planar_shapes(shapes, base=0, tolerance=PLANAR_TOLERANCE):
    """Validates k shapes of equal size; returns (list of (n, 2) arrays, Plane or None).

    2D shapes pass through unchanged (no copy when already C-contiguous float64). 3D shapes must all
    lie in the plane of shapes[base]; their plane coordinates are returned with that plane.
    """
    if isinstance(shapes, np.ndarray) and shapes.ndim == 3:
        shapes = list(shapes)
    shapes = [coordinates(s, f"shape {i}") for i, s in enumerate(shapes)]
    if not shapes:
        raise ValueError("need at least one shape")
    if not 0 <= base < len(shapes):
        raise ValueError(f"base shape index {base} out of range [0, {len(shapes)})")
    n, d = shapes[0].shape
    for i, s in enumerate(shapes):
        if s.shape != (n, d):
            raise ValueError(f"shape {i} has shape {s.shape}, shape 0 has {(n, d)}")
    if d == 2:
        return [np.ascontiguousarray(s) for s in shapes], None
    plane = Plane.fit(shapes[base])
    return [plane.to_plane(s, f"shape {i}", tolerance) for i, s in enumerate(shapes)], plane
