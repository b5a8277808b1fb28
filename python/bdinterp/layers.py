"""Layered pieces: the loose parts of a 3D mesh in parallel planes, each at its own
depth along the common normal (a cut-out character's draw order), solved in one plane and put back
at their depths."""
from dataclasses import dataclass

import numpy as np

from . import _core
from .constants import PLANAR_TOLERANCE
from .errors import invalid
from .plane import Plane


def piece_labels(num_vertices, faces):
    """(n,) the piece of every vertex as the Interpolator splits the mesh (faces joined through
    shared edges), numbered 0, 1, ... in order of each piece's lowest vertex; a vertex in no face
    is a piece of its own. InvalidInputError for a bad index or a non-manifold mesh."""
    faces = np.ascontiguousarray(np.asarray(faces).reshape(-1, 3), dtype=np.int32)
    return _core.piece_labels(faces, int(num_vertices)).astype(np.int64)


@dataclass(frozen=True)
class Layers:
    """A plane shared by parallel pieces and each piece's depth in every input shape.

    plane: the common Plane (its normal is the pieces' common normal); labels (n,): the piece of
    each vertex; depth (k, p): the signed offset of piece j of shape i along the normal (the median
    of its vertices' offsets from plane.origin).
    """
    plane: Plane
    labels: np.ndarray
    depth: np.ndarray

    @classmethod
    def fit(cls, shapes, faces, base=0, tolerance=PLANAR_TOLERANCE):
        """The layers of k shapes (n, 3) with faces (m, 3): the least-squares normal of planes
        parallel through each piece of shapes[base] (pieces centred on their own means, one SVD),
        oriented so that the faces wind counter-clockwise. InvalidInputError at the shape and the
        worst vertex if a vertex is farther than tolerance x the shape's largest extent from its
        piece's plane (a piece not planar or not parallel)."""
        shapes = [np.asarray(s, dtype=np.float64) for s in shapes]
        labels = piece_labels(len(shapes[base]), faces)
        B = shapes[base]
        means = np.zeros((labels.max() + 1, 3))
        np.add.at(means, labels, B)
        means /= np.bincount(labels)[:, None]
        # pieces moved onto one plane through their common mean: Plane's fit of parallel planes
        plane = Plane.fit(B - means[labels] + B.mean(axis=0), faces)
        depth = np.stack([cls._depths(plane, labels, X, i, tolerance)
                          for i, X in enumerate(shapes)])
        return cls(plane, labels, depth)

    @staticmethod
    def _depths(plane, labels, X, shape, tolerance):
        """(p,) the depth of every piece of X, the shape `shape`; InvalidInputError as in fit() for a
        vertex off its plane."""
        off = (X - plane.origin) @ plane.normal
        order = np.argsort(labels, kind="stable")
        cuts = np.flatnonzero(np.diff(labels[order])) + 1
        depth = np.array([np.median(off[g]) for g in np.split(order, cuts)])
        miss = np.abs(off - depth[labels])
        worst = int(np.argmax(miss))
        size = max(float(np.ptp(X, axis=0).max()), np.finfo(float).tiny)
        if miss[worst] > tolerance * size:
            raise invalid(
                f"not planar: {miss[worst]:.3g} off the plane of its piece, which must be parallel "
                f"to the plane of the base shape's pieces (tolerance {tolerance:g} x size {size:.3g} "
                f"= {tolerance * size:.3g})", shape=shape, vertex=worst)
        return depth

    def check(self, shapes):
        """ValueError unless these Layers fit k shapes (n, 3): n labels, one depth row per shape."""
        n, k = len(shapes[0]), len(shapes)
        if len(self.labels) != n or self.depth.shape[0] != k:
            raise ValueError(f"layers are of {self.depth.shape[0]} shapes of {len(self.labels)} "
                             f"vertices, not of {k} shapes of {n}")
        return self

    def to_plane(self, shapes):
        """[(n, 2)] plane coordinates of shapes (n, 3) (depths dropped; checked by fit())."""
        return [self.plane.to_plane(X, "", np.inf) for X in shapes]

    def to_space(self, uv, weights):
        """3D points (n, 3) of plane coordinates uv (n, 2), every piece at the weights' blend
        (k,) of its depths in the inputs (its own depth when all inputs share it)."""
        d = np.asarray(weights, dtype=np.float64) @ self.depth
        out = np.asarray(uv) @ self.plane.axes
        # Each piece's offset (origin + depth x normal) once, added per vertex: a quarter of
        # the time of adding origin and depth x normal vertex by vertex (a live update at 100k).
        offset = self.plane.origin + d[:, None] * self.plane.normal
        out += offset[0] if len(offset) == 1 else offset[self.labels]
        return out
