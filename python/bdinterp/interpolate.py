"""The public interpolation functions: one-off calls and the precomputing Interpolator."""
from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import _core
from . import _validate

METHODS = ("bdi", "arap", "linear")


@dataclass
class AnchorPath:
    """A trajectory for the anchor of a two-shape interpolation.

    At time ts[k] the anchor point (the area-weighted centroid, or `vertex`) is at positions[k]
    ((k, 2) plane or (k, 3) space coordinates) and turned by angles[k] radians relative to the source.
    The path is corrected by the linear function of t that makes it pass through the source's and the
    target's own anchors at t = 0 and 1, so the inputs are always reproduced exactly.
    """
    ts: np.ndarray
    positions: np.ndarray
    angles: np.ndarray
    vertex: Optional[int] = None


def _anchor_arguments(anchor, num_vertices, plane):
    if anchor is None or (isinstance(anchor, str) and anchor == "auto"):
        return {}
    if isinstance(anchor, (int, np.integer)) and not isinstance(anchor, bool):
        if not 0 <= anchor < num_vertices:
            raise ValueError(f"anchor vertex {anchor} out of range [0, {num_vertices})")
        return {"anchor_vertex": int(anchor)}
    if isinstance(anchor, AnchorPath):
        pos = np.asarray(anchor.positions, dtype=np.float64)
        ts = np.asarray(anchor.ts, dtype=np.float64).ravel()
        angles = np.asarray(anchor.angles, dtype=np.float64).ravel()
        if pos.ndim != 2 or pos.shape[1] not in (2, 3):
            raise ValueError(f"anchor path positions must be (k, 2) or (k, 3), got {pos.shape}")
        if pos.shape[1] == 3:
            if plane is None:
                raise ValueError("anchor path positions are 3D but the shapes are 2D")
            pos = plane.to_plane(pos, "anchor path", tolerance=np.inf)
        elif plane is not None:
            raise ValueError("anchor path positions must be 3D like the shapes")
        out = {"path_t": ts.tolist(), "path_positions": np.ascontiguousarray(pos),
               "path_angles": angles.tolist()}
        if anchor.vertex is not None:
            out["anchor_vertex"] = int(anchor.vertex)
        return out
    raise ValueError(f"anchor must be None, 'auto', a vertex index or an AnchorPath, got {anchor!r}")


class Interpolator:
    """Bounded-distortion in-betweens of k shapes with one connectivity, precomputed once.

    shapes: sequence of k (n, 2) or (n, 3) arrays (3D: planar, in one plane); faces: (m, 3) ints.
    anchor: None/"auto" (blend the area-weighted centroid and the mean rotation), a vertex index
    (the paper's mode), or an AnchorPath (two shapes). base: the shape the maps start from.
    tol: convergence tolerance on max |2 pi - angle sum|; threads: cores to use (frames() splits
    a sequence over them, a single frame its loops; 0 = all cores, 1 = sequential). Not
    thread-safe: use one Interpolator per thread.
    """

    def __init__(self, shapes, faces, *, anchor=None, base=0, tol=1e-10, max_iterations=50,
                 threads=0):
        shapes2d, self._plane = _validate.planar_shapes(shapes, base)
        self._n = shapes2d[0].shape[0]
        self._k = len(shapes2d)
        f = _validate.faces(faces, self._n)
        kwargs = _anchor_arguments(anchor, self._n, self._plane)
        self._core = _core.Interpolator(shapes2d, f, base=base, tolerance=tol,
                                        max_iterations=max_iterations, **kwargs)
        self.threads = threads

    def _out(self, uv):
        return uv if self._plane is None else self._plane.to_space(uv)

    def at(self, t):
        """The in-between at t (two shapes); (n, d) like the inputs."""
        return self._out(self._core.at(float(t)))

    def blend(self, weights):
        """The bounded-distortion blend for weights (k,) summing to 1; (n, d)."""
        w = np.asarray(weights, dtype=np.float64).ravel()
        return self._out(self._core.blend(w))

    def frames(self, ts):
        """In-betweens for a sequence of t (two shapes), each warm-started from the previous: (len(ts), n, d)."""
        ts = np.asarray(ts, dtype=np.float64).ravel()
        out = np.empty((ts.size * self._n, 2))
        self._core.frames_into(ts.tolist(), out)
        return self._out(out.reshape(ts.size, self._n, 2))

    @property
    def threads(self):
        """Threads used by frames() and by each frame (0 = one per core, 1 = sequential)."""
        return self._core.threads

    @threads.setter
    def threads(self, n):
        if int(n) < 0:
            raise ValueError(f"threads must be >= 0, got {n}")
        self._core.threads = int(n)

    @property
    def stats(self):
        """Statistics of the last at()/blend() (or of all frames of the last frames()): iterations,
        residual (max |2 pi - angle sum|), broken_triangles, max_broken_triangles, flatness,
        pieces, factorizations, chord_steps, seconds, hole_closure (per hole: the translation
        period of the flat metric around it relative to the hole's perimeter)."""
        return self._core.stats

    def folded_faces(self, shape):
        """(j,) indices of the faces of input `shape` that are folded (reversed) relative to the
        base shape, ascending; empty for the base. An input folded on more than half of a piece's
        faces is a mirror image and is refused with a ValueError when the Interpolator is made."""
        if not 0 <= int(shape) < self._k:
            raise ValueError(f"shape {shape} out of range [0, {self._k})")
        return np.asarray(self._core.folded_faces(int(shape)), dtype=np.int64)


def interpolate(source, target, faces, t, *, anchor=None, method="bdi"):
    """The in-between of `source` and `target` ((n, 2) or planar (n, 3)) at t; same shape as source.

    method: "bdi" (bounded distortion, the default), "arap" (Alexa et al. 2000 with unwrapped
    rotations) or "linear" (vertex blend).
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if method == "bdi":
        return Interpolator([source, target], faces, anchor=anchor).at(t)
    (s, g), plane = _validate.planar_shapes([source, target])
    f = _validate.faces(faces, s.shape[0])
    if anchor is not None:
        raise ValueError(f"anchor is not supported with method={method!r}")
    if method == "linear":
        uv = _core.linear_interpolate(s, g, float(t))
    else:
        uv = _core.ArapInterpolator(s, g, f).at(float(t))
    return uv if plane is None else plane.to_space(uv)


def blend(shapes, faces, weights, *, anchor=None, base=0):
    """The bounded-distortion blend of k shapes with weights (k,) summing to 1 (paper Sec. 5)."""
    return Interpolator(shapes, faces, anchor=anchor, base=base).blend(weights)
