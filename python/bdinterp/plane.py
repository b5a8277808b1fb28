"""The plane of planar 3D input: one fit, one tolerance, both directions of the projection."""
from dataclasses import dataclass

import numpy as np

from .constants import PLANAR_TOLERANCE
from .errors import invalid


@dataclass(frozen=True)
class Plane:
    """A right-handed orthonormal frame of a plane in space.

    origin (3,), axes (2, 3) with rows e1, e2, normal (3,) = e1 x e2. Plane coordinates (u, v) of a
    point p are ((p - origin) . e1, (p - origin) . e2), so a face that winds counter-clockwise in
    plane coordinates winds counter-clockwise seen from the side the normal points to.
    """
    origin: np.ndarray
    axes: np.ndarray
    normal: np.ndarray

    @classmethod
    def fit(cls, points, faces=None):
        """The least-squares plane of points (n, 3) (through their mean).

        The normal is e1 x e2 (the SVD alone leaves its sign arbitrary, which is what made two fits
        disagree on handedness). With faces (m, 3), the frame is turned over if needed so that the
        faces' total signed area in plane coordinates is positive (the side they face).
        """
        points = np.asarray(points, dtype=np.float64)
        origin = points.mean(axis=0)
        _, _, vt = np.linalg.svd(points - origin, full_matrices=False)
        plane = cls(origin, vt[:2].copy(), np.cross(vt[0], vt[1]))
        if faces is not None and total_signed_area(plane.to_plane(points, "points", np.inf),
                                                   faces) < 0:
            plane = plane.flipped()
        return plane

    def flipped(self):
        """The same plane seen from the other side (e2 and the normal negated)."""
        return Plane(self.origin, np.array([self.axes[0], -self.axes[1]]), -self.normal)

    def distance(self, points):
        """(n,) unsigned distances of points (n, 3) from the plane."""
        return np.abs((np.asarray(points, dtype=np.float64) - self.origin) @ self.normal)

    def farthest(self, points):
        """(vertex farthest from the plane, its distance, the points' largest extent): the three
        numbers every planarity check (tolerance x extent) and its message use."""
        off = self.distance(points)
        size = max(float(np.ptp(points, axis=0).max()), np.finfo(float).tiny)
        worst = int(np.argmax(off))
        return worst, float(off[worst]), size

    def contains(self, points, tolerance=PLANAR_TOLERANCE):
        """True if every point (n, 3) is within tolerance x the points' largest extent of the plane."""
        _, off, size = self.farthest(np.asarray(points, dtype=np.float64))
        return off <= tolerance * size

    def to_plane(self, points, name, tolerance=PLANAR_TOLERANCE, shape=None):
        """Plane coordinates (n, 2) of points (n, 3).

        If a point is farther from the plane than tolerance x the points' largest extent
        (tolerance=np.inf: project without checking): InvalidInputError at `shape` (when the points
        are that shape) and the worst vertex, else a ValueError naming `name` and the vertex.
        """
        points = np.asarray(points, dtype=np.float64)
        if np.isfinite(tolerance):
            worst, off, size = self.farthest(points)
            if off > tolerance * size:
                detail = (f"not planar: {off:.3g} off the plane of the base shape (tolerance "
                          f"{tolerance:g} x size {size:.3g} = {tolerance * size:.3g})")
                if shape is not None:
                    raise invalid(detail, shape=shape, vertex=worst)
                raise ValueError(f"{name}, vertex {worst}: {detail}")
        return np.ascontiguousarray((points - self.origin) @ self.axes.T)

    def to_space(self, uv):
        """3D points (..., 3) of plane coordinates uv (..., 2)."""
        return self.origin + np.asarray(uv) @ self.axes


def total_signed_area(uv, faces):
    """Sum of the signed areas (> 0: counter-clockwise) of faces (m, 3) over points uv (n, 2)."""
    f = np.asarray(faces)
    a = uv[f[:, 1]] - uv[f[:, 0]]
    b = uv[f[:, 2]] - uv[f[:, 0]]
    return 0.5 * float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))
