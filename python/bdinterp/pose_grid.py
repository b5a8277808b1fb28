"""Pose parameters: poses at the nodes of a grid of parameter values, blended with bounded distortion.

A group's parameters (1 to 3, e.g. head angle X and Y) span a grid; each node names a pose (a key).
A point of the parameters maps to multilinear weights on the corners of its cell, as Live2D and
Inochi2D do: convex, clamped outside the grid; a parameter that wraps (an angle on a circle) joins its
last value to its first, one period on. The shape shown is the core's blend of the poses with those
weights, so it is exact at every node, continuous in the point, and no face's conformal distortion
exceeds the largest of the poses' (the paper's section 5).

Several groups act together without a pose for every combination. The core blends squared edge
lengths linearly, so adding each group's difference from the rest pose,
    l2 = l2_rest + sum_g (l2_g(w_g) - l2_rest),
is the core's blend with the weights sum_g w_g - (G - 1) e_rest (they sum to 1; the rest's weight
may be negative). Where it is negative the blend extrapolates, outside the paper's guarantee: the
frame is then measured (worst K, flipped faces) and reported, and where the core refuses it (a face
whose blended lengths break the triangle inequality) or it flips faces, the weights are moved toward
a convex blend until it does not.
"""
import itertools
import numbers

import numpy as np

from .distortion import conformal_distortion, flipped_faces
from .interpolate import Interpolator

# Bisection steps between a convex blend and a refused extrapolated one (2**-8 of the way).
FALLBACK_STEPS = 8


class Parameter:
    """One parameter: its node values (strictly increasing) and whether it wraps.

    wrap: the values lie on a circle of length `period` (default 360, degrees), so that the last
    node's cell reaches the first node one period on; otherwise a point outside the values is
    clamped to the first or last."""

    def __init__(self, name, values, wrap=False, period=None):
        self.name = str(name)
        v = np.asarray(values, dtype=float).ravel()
        if v.size < 2 or not np.all(np.isfinite(v)) or np.any(np.diff(v) <= 0):
            raise ValueError(f"parameter {self.name!r}: values must be at least two finite numbers "
                             f"in increasing order, got {list(values)!r}")
        self.values, self.wrap = v, bool(wrap)
        self.period = None
        if self.wrap:
            self.period = 360.0 if period is None else float(period)
            if not np.isfinite(self.period) or self.period <= v[-1] - v[0]:
                raise ValueError(f"parameter {self.name!r}: period {period!r} must be larger than "
                                 f"the values' span {v[-1] - v[0]:g}")
        elif period is not None:
            raise ValueError(f"parameter {self.name!r}: a period needs wrap=True")

    @property
    def span(self):
        """The length of the parameter's range: its period if it wraps, else last - first value."""
        return self.period if self.wrap else self.values[-1] - self.values[0]

    def cell(self, x):
        """(i0, i1, t): x lies t of the way from node i0 to node i1 (weights 1 - t and t)."""
        v, x = self.values, float(x)
        if not np.isfinite(x):
            raise ValueError(f"parameter {self.name!r}: value must be finite, got {x!r}")
        if self.wrap:
            x = v[0] + (x - v[0]) % self.period
            if x >= v[-1]:
                return len(v) - 1, 0, (x - v[-1]) / (v[0] + self.period - v[-1])
        x = min(max(x, v[0]), v[-1])
        i = min(int(np.searchsorted(v, x, side="right")) - 1, len(v) - 2)
        return i, i + 1, (x - v[i]) / (v[i + 1] - v[i])

    def index(self, value):
        """The node index of `value` (matched to 1e-9 of the span); ValueError if none."""
        near = np.flatnonzero(np.abs(self.values - float(value)) <= 1e-9 * self.span)
        if near.size != 1:
            raise ValueError(f"parameter {self.name!r} has no value {value!r} "
                             f"(its values: {self.values.tolist()})")
        return int(near[0])


def _parameters(params):
    items = params.items() if hasattr(params, "items") else [(p.name, p) for p in params]
    out = [p if isinstance(p, Parameter) else Parameter(name, p) for name, p in items]
    if not 1 <= len(out) <= 3:
        raise ValueError(f"a pose grid has 1 to 3 parameters, got {len(out)}")
    if len({p.name for p in out}) != len(out):
        raise ValueError(f"parameter names repeat: {[p.name for p in out]}")
    return out


class PoseGrid:
    """A group of parameters and the pose at each node of their grid.

    params: mapping name -> values (or Parameter), or a sequence of Parameter, 1 to 3 of them.
    keys: mapping node -> pose key (any hashable, e.g. a shape key's name); a node is a tuple of
    parameter values in the parameters' order (a number for one parameter). Nodes may be missing
    (missing() lists them; require_complete() refuses them; fill_weights() makes one from its
    neighbours). rest: the key of the rest pose (the group's neutral shape)."""

    def __init__(self, params, keys, name="grid", rest=None):
        self.name, self.rest = str(name), rest
        self.params = _parameters(params)
        self.shape = tuple(p.values.size for p in self.params)
        self.nodes = {}
        for node, key in keys.items():
            values = (node,) if isinstance(node, numbers.Real) else tuple(node)
            if len(values) != len(self.params):
                raise ValueError(f"grid {self.name!r}: node {node!r} needs {len(self.params)} "
                                 f"values ({', '.join(p.name for p in self.params)})")
            index = tuple(p.index(x) for p, x in zip(self.params, values))
            if index in self.nodes:
                raise ValueError(f"grid {self.name!r}: node {node!r} is given twice")
            self.nodes[index] = key

    def node_values(self, index):
        """The parameter values of the node at `index` (a tuple of ints)."""
        return tuple(float(p.values[i]) for p, i in zip(self.params, index))

    def describe(self, index):
        """How messages name a node: "(angle_x=-30, angle_y=0)"."""
        return "(%s)" % ", ".join("%s=%g" % (p.name, x)
                                  for p, x in zip(self.params, self.node_values(index)))

    def missing(self):
        """The indices of the nodes without a pose, in grid order."""
        return [i for i in itertools.product(*map(range, self.shape)) if i not in self.nodes]

    def require_complete(self):
        """ValueError naming the first node without a pose (and how many there are)."""
        gaps = self.missing()
        if gaps:
            more = " and %d more" % (len(gaps) - 1) if len(gaps) > 1 else ""
            raise ValueError(f"grid {self.name!r}: node {self.describe(gaps[0])}{more} has no pose")

    def keys(self):
        """The distinct pose keys of the grid, in grid order."""
        return list(dict.fromkeys(self.nodes[i] for i in sorted(self.nodes)))

    def corners(self, point):
        """[(node index, weight)] of the cell of `point` (a value per parameter, or a mapping
        name -> value; a parameter left out stays at its rest node's value, else its first value):
        the multilinear weights, >= 0, summing to 1."""
        cells = [p.cell(x) for p, x in zip(self.params, self._point(point))]
        out = {}
        for corner in itertools.product((0, 1), repeat=len(cells)):
            w = np.prod([t if c else 1 - t for c, (_, _, t) in zip(corner, cells)])
            index = tuple(c[1] if b else c[0] for b, c in zip(corner, cells))
            out[index] = out.get(index, 0.0) + float(w)
        return list(out.items())

    def _point(self, point):
        if hasattr(point, "items"):
            unknown = set(point) - {p.name for p in self.params}
            if unknown:
                raise ValueError(f"grid {self.name!r} has no parameter {sorted(unknown)[0]!r}")
            home = self.rest_values()
            return [point.get(p.name, x) for p, x in zip(self.params, home)]
        values = [point] if isinstance(point, numbers.Real) else list(point)
        if len(values) != len(self.params):
            raise ValueError(f"grid {self.name!r}: a point needs {len(self.params)} values, "
                             f"got {len(values)}")
        return values

    def rest_values(self):
        """The parameter values of the rest pose's node (the first node if the rest is not one)."""
        for index, key in sorted(self.nodes.items()):
            if key == self.rest:
                return self.node_values(index)
        return tuple(float(p.values[0]) for p in self.params)

    def weights(self, point):
        """{pose key: weight} at `point` (corners(), merged where nodes share a pose); every
        corner with weight > 0 must have a pose (ValueError naming it)."""
        out = {}
        for index, w in self.corners(point):
            if w == 0.0:
                continue
            if index not in self.nodes:
                raise ValueError(f"grid {self.name!r}: node {self.describe(index)} has no pose")
            key = self.nodes[index]
            out[key] = out.get(key, 0.0) + w
        return out

    def fill_weights(self, index):
        """{pose key: weight} that makes the missing node `index` from its row and column
        neighbours: along each parameter with a pose on both sides, their linear interpolation
        at the node's value; the mean over those parameters. Without any, the parallelogram of
        two neighbours and their common diagonal node (an extrapolation). ValueError if neither."""
        estimates = [e for e in (self._between(index, a) for a in range(len(self.shape))) if e]
        if not estimates:
            estimates = self._parallelograms(index)[:1]
        if not estimates:
            raise ValueError(f"grid {self.name!r}: node {self.describe(index)} has no pose and no "
                             "neighbours to make one from")
        out = {}
        for est in estimates:
            for key, w in est.items():
                out[key] = out.get(key, 0.0) + w / len(estimates)
        return out

    def _between(self, index, axis):
        p, n = self.params[axis], self.shape[axis]
        sides = []
        for step in (-1, 1):
            for k in range(1, n):
                j = index[axis] + step * k
                if p.wrap:
                    j %= n
                elif not 0 <= j < n:
                    break
                other = index[:axis] + (j,) + index[axis + 1:]
                if other in self.nodes:
                    sides.append((j, step * k))
                    break
        if len(sides) != 2 or sides[0][0] == sides[1][0]:
            return None
        x = self._axis_value(p, index[axis], 0)
        (ja, sa), (jb, sb) = sides
        xa, xb = self._axis_value(p, ja, sa), self._axis_value(p, jb, sb)
        t = (x - xa) / (xb - xa)
        key = lambda j: self.nodes[index[:axis] + (j,) + index[axis + 1:]]  # noqa: E731
        return {key(ja): 1 - t, key(jb): t} if key(ja) != key(jb) else {key(ja): 1.0}

    @staticmethod
    def _axis_value(p, j, step):
        """The value of node j reached `step` nodes from the start, unwrapped around the circle."""
        x = float(p.values[j])
        if p.wrap and step:
            origin = j - step
            if step > 0 and j < origin:
                x += p.period
            elif step < 0 and j > origin:
                x -= p.period
        return x

    def _parallelograms(self, index):
        out = []
        for a, b in itertools.combinations(range(len(self.shape)), 2):
            for da, db in itertools.product((-1, 1), repeat=2):
                na = self._step(index, a, da)
                nb = self._step(index, b, db)
                diag = self._step(na, b, db) if na is not None else None
                if None not in (na, nb, diag) and all(i in self.nodes for i in (na, nb, diag)):
                    out.append(_merge([(self.nodes[na], 1.0), (self.nodes[nb], 1.0),
                                       (self.nodes[diag], -1.0)]))
        return out

    def _step(self, index, axis, d):
        j, n = index[axis] + d, self.shape[axis]
        if self.params[axis].wrap:
            j %= n
        elif not 0 <= j < n:
            return None
        return index[:axis] + (j,) + index[axis + 1:]


def _merge(pairs):
    out = {}
    for key, w in pairs:
        out[key] = out.get(key, 0.0) + w
    return out


def combine(group_weights, rest):
    """The weights of groups acting together: sum_g w_g - (G - 1) e_rest, i.e. each group's blended
    squared edge lengths added to the rest's as a difference from it (they still sum to 1)."""
    out = {rest: 1.0}
    for weights in group_weights:
        out = _merge(list(out.items()) + list(weights.items()) + [(rest, -1.0)])
    return out


class Blend:
    """A blend of pose parameters: shape (n, d); weights {key: weight} as blended; asked (the
    weights the points asked for); guaranteed (weights all >= 0: the paper's bound holds);
    k_max (the largest conformal distortion of a face relative to the rest, None if not measured),
    k_bound (the largest of the poses'), flipped (faces flipped relative to the rest, None if not
    measured); scale: 1 if blended as asked, else how far from a convex blend toward the asked
    weights the shown one lies (the asked one was refused by the core or flipped faces)."""

    def __init__(self, shape, weights, asked, k_bound, k_max=None, flipped=None, scale=1.0):
        self.shape, self.weights, self.asked = shape, weights, asked
        self.k_bound, self.k_max, self.flipped, self.scale = k_bound, k_max, flipped, scale
        self.guaranteed = all(w >= 0 for w in weights.values())

    def report(self):
        """One line: how the blend relates to the guarantee."""
        if self.guaranteed:
            return "convex blend: K <= %.4g (the poses' largest)" % self.k_bound
        text = "extrapolated blend: worst K %.4g (poses' largest %.4g), %d flipped faces" % (
            self.k_max, self.k_bound, self.flipped)
        return text if self.scale == 1.0 else text + "; moved %.3g of the way from a convex " \
            "blend (the combination asked for was refused)" % self.scale


class PoseBlender:
    """Groups of pose parameters on one mesh, blended by one precomputed Interpolator.

    shapes: mapping key -> (n, 2) or (n, 3) array (every key the groups name, and rest); faces:
    (m, 3); groups: PoseGrid or a sequence of them (complete, distinct names); rest: the key of the
    rest pose (the base of the blend, and what each group's poses are differences from); options:
    Interpolator's keyword arguments (anchor, joints, tol, threads, ...)."""

    def __init__(self, shapes, faces, groups, rest, **options):
        self.groups = [groups] if isinstance(groups, PoseGrid) else list(groups)
        names = [g.name for g in self.groups]
        if not self.groups or len(set(names)) != len(names):
            raise ValueError(f"pose groups need distinct names, got {names}")
        for g in self.groups:
            g.require_complete()
            g.rest = rest
        keys = [rest] + [k for g in self.groups for k in g.keys() if k != rest]
        self.keys = list(dict.fromkeys(keys))
        absent = [k for k in self.keys if k not in shapes]
        if absent:
            raise ValueError(f"no shape for pose {absent[0]!r}")
        poses = [np.asarray(shapes[k], dtype=float) for k in self.keys]
        self.interpolator = Interpolator(poses, faces, base=0, **options)
        self.faces, self.rest_shape = faces, poses[0]
        flat = [self._flat(p) for p in poses]
        self._rest_flat = flat[0]
        self.k_poses = np.max([conformal_distortion(flat[0], p, faces) for p in flat], axis=0)

    def _flat(self, X):
        """X in the plane coordinates the core works in (3D input: each piece in its layer)."""
        layers, plane = self.interpolator.layers, self.interpolator.plane
        if layers is not None:
            return layers.to_plane([X])[0]
        return plane.to_plane(X, "shape") if plane is not None else X

    def weights(self, points):
        """{key: weight} for points {group name: point} (a group left out stays at rest)."""
        by_name = {g.name: g for g in self.groups}
        unknown = set(points) - set(by_name)
        if unknown:
            raise ValueError(f"no pose group {sorted(unknown)[0]!r} (groups: {sorted(by_name)})")
        return combine([by_name[n].weights(p) for n, p in points.items()], self.keys[0])

    def vector(self, weights):
        """The weights {key: weight} as the Interpolator's (k,) vector (rest first)."""
        return np.array([weights.get(k, 0.0) for k in self.keys])

    def blend(self, points, measure=False):
        """The Blend at points {group name: point}. A convex blend is the paper's (measured only
        with measure=True); an extrapolated one is always measured, and moved toward a convex
        blend where the core refuses it or it flips faces (never an exception for that)."""
        asked = self.weights(points)
        if all(w >= 0 for w in asked.values()):
            shape = self.interpolator.blend(self.vector(asked))
            out = Blend(shape, asked, asked, float(self.k_poses.max()))
            if measure:
                self._measure(out)
            return out
        return self._extrapolated(asked)

    def _measure(self, out):
        flat = self._flat(out.shape)
        out.k_max = float(np.max(conformal_distortion(self._rest_flat, flat, self.faces)))
        out.flipped = int(flipped_faces(self._rest_flat, flat, self.faces))
        return out

    def _try(self, weights, asked, scale):
        try:
            shape = self.interpolator.blend(self.vector(weights))
        except (ValueError, RuntimeError):  # the core's InvalidInput or SolverError
            return None
        out = self._measure(Blend(shape, weights, asked, float(self.k_poses.max()), scale=scale))
        return out if out.flipped == 0 and np.isfinite(out.k_max) else None

    def _extrapolated(self, asked):
        out = self._try(asked, asked, 1.0)
        if out is not None:
            return out
        positive = {k: max(w, 0.0) for k, w in asked.items()}
        total = sum(positive.values())
        convex = {k: w / total for k, w in positive.items()}
        best = self._try(convex, asked, 0.0)
        lo, hi = 0.0, 1.0
        for _ in range(FALLBACK_STEPS):
            mid = (lo + hi) / 2
            mixed = {k: (1 - mid) * convex.get(k, 0.0) + mid * w for k, w in asked.items()}
            found = self._try(mixed, asked, mid)
            if found is not None:
                best, lo = found, mid
            else:
                hi = mid
        return best
