"""The public interpolation functions: the precomputing Interpolator, frames(), interpolate(), blend()."""
from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import _core
from . import _validate
from . import keyframes as _keyframes
from .constants import INT_MAX, MAX_ITERATIONS, METHODS, PLANAR_TOLERANCE, REFINEMENT, THREADS, TOLERANCE


@dataclass
class AnchorPath:
    """A trajectory for the anchor of a two-shape interpolation.

    At time ts[k] (strictly increasing) the anchor point (the area-weighted centroid, or `vertex`) is
    at positions[k] ((k, 2) plane or (k, 3) space coordinates, like the shapes) and turned by
    angles[k] radians (counter-clockwise) relative to the source. The path is corrected by the linear
    function of t that makes it pass through the source's and the target's own anchors at t = 0 and
    1, so the inputs are always reproduced exactly.
    """
    ts: np.ndarray
    positions: np.ndarray
    angles: np.ndarray
    vertex: Optional[int] = None

    def to_core(self, plane):
        """The validated _core.Anchor of this path (positions in plane coordinates)."""
        ts = _validate.times(self.ts, "anchor path ts")
        if ts.size == 0 or np.any(np.diff(ts) <= 0):
            raise ValueError(f"anchor path ts must be non-empty and strictly increasing, got "
                             f"{ts.tolist()[:6]}")
        pos = _validate.coordinates(self.positions, "anchor path positions")
        angles = _validate.times(self.angles, "anchor path angles")
        if pos.shape[0] != ts.size or angles.size != ts.size:
            raise ValueError(f"anchor path: {ts.size} ts, {pos.shape[0]} positions and "
                             f"{angles.size} angles; they must have one entry each per time")
        if pos.shape[1] == 3:
            if plane is None:
                raise ValueError("anchor path positions are 3D but the shapes are 2D")
            pos = plane.to_plane(pos, "anchor path", tolerance=np.inf)
        elif plane is not None:
            raise ValueError("anchor path positions must be 3D like the shapes")
        # The range is the core's to check (InvalidInputError at the vertex).
        vertex = -1 if self.vertex is None else _validate.integer(
            self.vertex, "anchor path vertex", -INT_MAX, INT_MAX)
        return _core.Anchor.along(_core.AnchorPath(ts.tolist(), np.ascontiguousarray(pos),
                                                   angles.tolist()), vertex)


def _core_anchor(anchor, plane):
    if anchor is None or (isinstance(anchor, str) and anchor == "auto"):
        return _core.Anchor.centroid()
    if isinstance(anchor, (int, np.integer)) and not isinstance(anchor, (bool, np.bool_)):
        # The range is the core's to check (InvalidInputError at the vertex); only a C int fits.
        return _core.Anchor.at_vertex(_validate.integer(anchor, "anchor vertex", -INT_MAX, INT_MAX))
    if isinstance(anchor, AnchorPath):
        return anchor.to_core(plane)
    raise ValueError(f"anchor must be None, 'auto', a vertex index or an AnchorPath, got {anchor!r}")


def _joint_links(joints, plane):
    """The core's joint_links of a sequence of (parent vertex, child vertex, point) links, points
    ((2,) or, for 3D shapes, (3,)) mapped into the plane; ValueError naming the link."""
    links = []
    for k, link in enumerate(joints):
        try:
            parent, child, point = link
        except (TypeError, ValueError):
            raise ValueError(f"joints[{k}] must be (parent vertex, child vertex, point), got {link!r}") from None
        point = _validate.coordinates(np.reshape(_validate.real_array(point, f"joints[{k}] point"), (1, -1)),
                                      f"joints[{k}] point")
        if (point.shape[1] == 3) != (plane is not None):
            raise ValueError(f"joints[{k}] point must be {'3D' if plane is not None else '2D'} like the shapes")
        if plane is not None:
            point = plane.to_plane(point, f"joints[{k}] point", tolerance=np.inf)
        links.append((_validate.integer(parent, f"joints[{k}] parent vertex", -INT_MAX, INT_MAX),
                      _validate.integer(child, f"joints[{k}] child vertex", -INT_MAX, INT_MAX), point[0]))
    return links


def _options(base, tol, max_iterations, threads, strict, folds=True, joints=True, plane=None,
             refinement=REFINEMENT):
    o = _core.InterpolatorOptions()
    o.base = base
    o.tolerance = _validate.positive(tol, "tol")
    o.refinement = _validate.real(refinement, "refinement")
    o.max_iterations = _validate.integer(max_iterations, "max_iterations", low=1)
    # The range [0, MAX_THREADS] is the core's to check (one layer); here: an int that fits a C int.
    o.threads = _validate.integer(threads, "threads", -INT_MAX, INT_MAX)
    if not isinstance(joints, (bool, np.bool_)):
        if isinstance(joints, str) or not hasattr(joints, "__len__") or not len(joints):
            raise ValueError(f"joints must be True, False or a non-empty sequence of (parent vertex, "
                             f"child vertex, point), got {joints!r}")
        o.joint_links, joints = _joint_links(joints, plane), True
    for name, value in (("strict", strict), ("folds", folds), ("joints", joints)):
        if not isinstance(value, (bool, np.bool_)):
            raise ValueError(f"{name} must be True or False, got {value!r}")
    o.strict, o.folds, o.joints = bool(strict), bool(folds), bool(joints)
    return o


class Interpolator:
    """Bounded-distortion in-betweens of k shapes with one connectivity, precomputed once.

    shapes: sequence of k (n, 2) or (n, 3) arrays (3D: planar, in the plane of shapes[base]); faces:
    (m, 3) ints. anchor: None/"auto" (per piece, what does not move, else the centroid, moved on
    the geodesic of the rigid motions, docs/JOINTS.md), a vertex index (the paper's mode), or an
    AnchorPath (two shapes). base: the shape the maps start
    from. tol: convergence tolerance on max |2 pi - angle sum| (radians, > 0); max_iterations: Newton
    steps before SolverError (>= 1); threads: cores to use (frames() splits a sequence over them, a
    single frame its loops; 0 = all cores, frames() at most one per 4 frames; 1 = sequential). strict: a frame that fails the
    self-check (non-finite, broken triangles or a layout that does not close, see FrameStats
    converged/warnings) raises SolverError instead of being returned with stats.converged False.
    folds: inputs with folded faces (folded_faces) are solved without their fold region, which is
    filled in so that the folded keys are reached (docs/FOLDS.md); False: the paper's method on the
    whole mesh (folded keys are then missed). joints: True, pieces (loose parts) that overlap in the
    base shape (or come within the pins' reach) and turn against each other about a pin in or near
    both, or are glued, or slide (no relative turn, or a pivot the rig translates), stay joined: a
    tree of the best joints rooted at the still pieces (else the piece whose own motion is best a
    turn about a point inside it), each child placed by its parent's in-between and turned by its
    blended rotation relative to it (docs/JOINTS.md; stats.joints counts them, joints() lists them,
    joint_roots() the roots); a sequence of (parent vertex, child vertex, point) links: that tree as
    given (e.g. an armature's bones; each piece by any of its vertices, point in the base shape like
    the shapes' coordinates; parent vertex -1: the child's piece is a root whose point travels on
    the chord between the shapes, as a root bone's offset does); False:
    every piece is placed on its own. planarity: for 3D shapes, how far (relative to a shape's
    largest extent) a vertex may lie off its piece's plane; layers: the Layers of 3D shapes the
    caller has fitted already (e.g. Layers.fit with its own planarity), used without a second fit.
    refinement (in [0, 1]): below tol, steps go on towards tol * refinement while they halve the
    residual, so that a frame does not depend on the frames solved before it (to ~1e-13 of the
    size); 1 stops at tol: a frame then depends on the ones before it by up to ~1e-11 of the size
    (measured on a 100k-vertex grid), and a warm frame of 100k vertices takes about 0.6 of the time
    (the add-on's live pose grids, whose positions Blender keeps in float32).

    Thread-safe: calls from several threads on one Interpolator are serialised (a per-object lock,
    taken with the GIL released); each returns what it would have returned alone.
    """

    def __init__(self, shapes, faces, *, anchor=None, base=0, tol=TOLERANCE,
                 max_iterations=MAX_ITERATIONS, threads=THREADS, strict=False, folds=True,
                 joints=True, planarity=PLANAR_TOLERANCE, layers=None, refinement=REFINEMENT):
        planarity = _validate.positive(planarity, "planarity")
        shapes2d, self._plane, self._layers = _validate.planar_shapes(
            shapes, base, planarity, mesh_faces=faces, layers=layers)
        self._n = shapes2d[0].shape[0]
        self._k = len(shapes2d)
        f = _validate.faces(faces, self._n)
        options = _options(base, tol, max_iterations, threads, strict, folds, joints, self._plane,
                           refinement)
        self._core = _core.Interpolator(shapes2d, f, _core_anchor(anchor, self._plane),
                                        options)
        self._size = _keyframes.size(shapes)

    @property
    def plane(self):
        """The Plane of 3D input (results are mapped back into it), or None for 2D input."""
        return self._plane

    @property
    def layers(self):
        """The Layers of 3D input (each loose part's depth along the plane's normal), or None."""
        return self._layers

    def _out(self, uv, weights):
        return uv if self._layers is None else self._layers.to_space(uv, weights)

    def at(self, t):
        """The in-between at t (two shapes; finite, may lie outside [0, 1]); (n, d) like the inputs."""
        t = _validate.real(t, "t")
        return self._out(self._core.at(t), [1 - t, t])

    def blend(self, weights):
        """The bounded-distortion blend for weights (k,) summing to 1; (n, d)."""
        w = _validate.times(weights, "weights")
        if w.size != self._k:
            raise ValueError(f"weights must have one entry per shape ({self._k}), got {w.size}")
        return self._out(self._core.blend(w), w)

    def frames(self, ts):
        """In-betweens for a sequence of t (two shapes), each warm-started from the previous:
        (len(ts), n, d)."""
        ts = _validate.times(ts)
        out = np.empty((ts.size * self._n, 2))
        self._core.frames_into(ts.tolist(), out)
        uv = out.reshape(ts.size, self._n, 2)
        if self._layers is None:
            return uv
        return np.stack([self._out(x, [1 - t, t]) for x, t in zip(uv, ts)]) if ts.size else \
            np.empty((0, self._n, 3))

    @property
    def size(self):
        """The diagonal of the larger input shape's bounding box (what keyframes' tolerance scales)."""
        return self._size

    def keyframes(self, tolerance, t0=0.0, t1=1.0):
        """The fewest factors (sorted, t0 and t1 included) such that the linear blend of the
        frames at consecutive factors stays within tolerance x size of the exact in-between at
        every factor between them (two shapes; checked densely, refined where not): where to put
        keys for a runtime that blends them linearly."""
        if self._k != 2:
            raise ValueError(f"keyframes needs two shapes, this Interpolator has {self._k}")
        return _keyframes.keyframes(self, tolerance, t0, t1)

    @property
    def threads(self):
        """Threads used by frames() and by each frame (0 = one per core, 1 = sequential)."""
        return self._core.threads

    @property
    def stats(self):
        """FrameStats of the last at()/blend() (or of all frames of the last frames()): attributes
        (and keys) iterations (the most Newton steps of one convex solve), convex_solves (one
        per piece, more where holes' periods are closed), residual (max |2 pi - angle sum|),
        broken_triangles, max_broken_triangles, line_search_steps, flatness, pieces,
        factorizations, chord_steps, seconds, converged (the self-check passed), warnings (why
        not), hole_closure (per hole: the translation period of the flat metric around it relative
        to the hole's perimeter), fold_faces and fold_free_vertices (the size of the fold region
        and of its filled-in vertices, docs/FOLDS.md; 0 when no input folds), joints, threads (the
        threads that ran: frames()'s workers, a thread each, or the most one loop of a frame ran on)."""
        return self._core.stats

    def joints(self):
        """The joints between pieces (parents first): dicts with parent and child (each piece by its
        lowest vertex), point ((2,) or, for 3D input, (3,) on the child's plane in the base shape),
        kind ("pin": the child turns about the point, inside both pieces or just outside within
        the pins' reach, against its parent in every input; "glued": it moves with its parent;
        "slide": it moves against its parent at an overlap point, without turning or about a pivot
        the keys translate; "given": a link of joints=[...]), pin (both pieces carry the point to
        one place in every input, to 0.1 % of the size) and fit (that largest gap over the inputs,
        for "glued" and "slide" the largest relative motion, relative to the size). Empty with
        joints=False; joint_roots() gives each tree's root."""
        out = self._core.joints()
        for j in out:
            if self._layers is not None:
                base = self._core.options.base
                depth = self._layers.depth[base, self._layers.labels[j["child"]]]
                j["point"] = self._plane.to_space(j["point"]) + depth * self._plane.normal
        return out

    def joint_roots(self):
        """The root of every tree of joints (a piece in no joint is a tree of its own): dicts with
        piece (its lowest vertex), reason ("anchor": it holds the vertex anchor; "still"; "travels":
        it moves without turning; "turns": its own motion is the best turn about a point inside or
        near it of its tree; "given": no given link holds it; "path": a link with parent vertex -1
        gives its path), point (for "turns", the fixed point of its own motion in the base shape;
        2D, in the plane's coordinates for 3D input) and rank (for "turns": that point's distance
        outside the piece over the pins' reach times the piece's size, plus its largest turn / pi).
        Empty with joints=False."""
        return self._core.joint_roots()

    @property
    def joints_seconds(self):
        """Wall-clock seconds the joints took when this Interpolator was made (the tree found or the
        given links checked, each joint's sites and offsets); 0 with joints=False. For benchmarks
        (scripts/bench_joint_tree.py)."""
        return self._core.joints_seconds

    def folded_faces(self, shape):
        """(j,) indices of the faces of input `shape` that are folded (reversed) relative to the
        base shape, ascending; empty for the base. An input folded on more than half of a piece's
        faces is a mirror image and is refused with a ValueError when the Interpolator is made."""
        if not 0 <= int(shape) < self._k:
            raise ValueError(f"shape {shape} out of range [0, {self._k})")
        return np.asarray(self._core.folded_faces(int(shape)), dtype=np.int64)


def _method(method):
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    return method


def frames(source, target, faces, ts, *, method="bdi", anchor=None, **options):
    """In-betweens of `source` and `target` ((n, 2) or planar (n, 3)) at every t of ts: (len(ts), n, d).

    method: "bdi" (bounded distortion, the default; options are Interpolator's tol, max_iterations,
    threads, strict), "arap" (Alexa et al. 2000 with unwrapped rotations) or "linear" (vertex blend). The
    baselines take no anchor (None or "auto") and no options.
    """
    if _method(method) == "bdi":
        return Interpolator([source, target], faces, anchor=anchor, **options).frames(ts)
    if anchor not in (None, "auto") or options:
        given = ["anchor"] * (anchor not in (None, "auto")) + sorted(options)
        raise ValueError(f"{', '.join(given)} not supported with method={method!r}")
    (s, g), _, layers = _validate.planar_shapes([source, target], mesh_faces=faces)
    f = _validate.faces(faces, s.shape[0])
    ts = _validate.times(ts)
    if method == "linear":
        uv = [_core.linear_interpolate(s, g, t) for t in ts.tolist()]
    else:
        arap = _core.ArapInterpolator(s, g, f)
        uv = [arap.at(t) for t in ts.tolist()]
    if layers is not None:
        return np.stack([layers.to_space(x, [1 - t, t]) for x, t in zip(uv, ts)]) if uv else \
            np.empty((0, s.shape[0], 3))
    return np.stack(uv) if uv else np.empty((0,) + s.shape)


def interpolate(source, target, faces, t, *, anchor=None, method="bdi"):
    """The in-between of `source` and `target` ((n, 2) or planar (n, 3)) at t; same shape as source.

    method: one of bdinterp.METHODS (see frames()).
    """
    t = _validate.real(t, "t")
    if _method(method) == "bdi":
        return Interpolator([source, target], faces, anchor=anchor).at(t)
    return frames(source, target, faces, [t], method=method, anchor=anchor)[0]


def blend(shapes, faces, weights, *, anchor=None, base=0):
    """The bounded-distortion blend of k shapes with weights (k,) summing to 1 (paper Sec. 5)."""
    return Interpolator(shapes, faces, anchor=anchor, base=base).blend(weights)
