"""In-betweens of drawn strokes (e.g. Grease Pencil) that turn instead of cutting corners.

Two keys of a drawing are lists of strokes, paired by order as Blender's own Interpolate pairs
them.  A pair with other point counts (or repeated points) is resampled by arc length at the
points of the stroke with more of them, so that one key stays exactly as drawn.  Each pair
becomes a thin band of triangles around the stroke, with the same triangles in both keys; all
bands go through one Interpolator as the pieces of one mesh, and the in-between's stroke is the
band's centre row.  A stroke that is a rigid motion of its partner therefore moves rigidly, a bent
one bends with the method's bounded distortion.  Strokes that meet (touch or cross within
`touch`) at the same points of both keys are joined there by the core's joints: a tree from the
stroke that turns least, each child hanging from its parent at the meeting point
(docs/JOINTS.md, given joints).  A stroke's end that is at the same place in both keys (a tail's
root, a shoulder) hangs likewise from a still triangle there, so it stays.  A closed stroke
(cyclic, or drawn round until its ends meet in both keys) gets a ring band, so it stays closed.
Every other per-point value (radius, opacity, colour) is blended linearly; so is the distance of
3D points from the strokes' plane.  Strokes left over when the keys' counts differ are refused, or
on request fade out (key a's) or in (key b's) where they are drawn.
"""
from collections import deque

import numpy as np

from . import _stroke_geometry as geo
from .interpolate import Interpolator
from .plane import Plane

TOUCH = 1e-3    # default meeting distance, relative to the size of the first key
UNPAIRED = ("error", "fade")   # what becomes of strokes left over when the keys' counts differ


class Stroke:
    """A stroke: points (n, 2) or (n, 3), cyclic (its last point joined to its first, as Grease
    Pencil's cyclic strokes) and per-point values by name (arrays (n,) or (n, k))."""

    __slots__ = ("points", "cyclic", "attributes")

    def __init__(self, points, cyclic=False, **attributes):
        self.points = np.asarray(points, dtype=np.float64)
        self.cyclic = bool(cyclic)
        self.attributes = {k: np.asarray(v, dtype=np.float64) for k, v in attributes.items()}

    def __repr__(self):
        return f"Stroke({len(self.points)} points, {sorted(self.attributes)})"

    @property
    def length(self):
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())


def _as_stroke(s):
    return s if isinstance(s, Stroke) else Stroke(s)


def _check(stroke, name):
    """ValueError naming the stroke when it cannot be interpolated."""
    p = stroke.points
    if p.ndim != 2 or p.shape[1] not in (2, 3):
        raise ValueError(f"{name}: points must be (n, 2) or (n, 3), got shape {p.shape}")
    if len(p) < 2:
        raise ValueError(f"{name}: a stroke needs at least 2 points, it has {len(p)}")
    bad = np.flatnonzero(~np.isfinite(p).all(axis=1))
    if len(bad):
        raise ValueError(f"{name}: point {bad[0]} is not finite ({p[bad[0]].tolist()})")
    if stroke.length <= 0:
        raise ValueError(f"{name}: the stroke has zero length (all its {len(p)} points at one place)")
    for key, v in stroke.attributes.items():
        if len(v) != len(p) or not np.isfinite(v).all():
            raise ValueError(f"{name}: attribute {key!r} must hold one finite value per point "
                             f"({len(p)}), got shape {v.shape}")


def pair_strokes(strokes_a, strokes_b, where="strokes", keys=("key a", "key b"), unpaired="error"):
    """(pairs, strokes of key a left over, strokes of key b left over): the strokes of two keys
    paired by order (as Blender pairs them), each checked.  When the counts differ: unpaired
    "error", a ValueError naming `where`, the keys and the strokes left over; "fade", the strokes
    past the shorter key's count are left over (to fade out or in)."""
    if unpaired not in UNPAIRED:
        raise ValueError(f"unpaired must be one of {UNPAIRED}, got {unpaired!r}")
    a, b = [_as_stroke(s) for s in strokes_a], [_as_stroke(s) for s in strokes_b]
    if len(a) != len(b) and unpaired == "error":
        more, extra = (keys[0], a) if len(a) > len(b) else (keys[1], b)
        left = list(range(min(len(a), len(b)), len(extra)))
        raise ValueError(f"{where}: {keys[0]} has {len(a)} strokes and {keys[1]} has {len(b)}: "
                         f"strokes {left} of {more} have no partner")
    if not a and not b:
        raise ValueError(f"{where}: there are no strokes to interpolate")
    dims = {s.points.shape[-1] if s.points.ndim == 2 else None for s in a + b}
    for key, strokes in zip(keys, (a, b)):
        for k, s in enumerate(strokes):
            _check(s, f"{where}: stroke {k} of {key}")
    if len(dims) != 1:
        raise ValueError(f"{where}: every stroke must be 2D, or every one 3D")
    for k, (sa, sb) in enumerate(zip(a, b)):
        if sorted(sa.attributes) != sorted(sb.attributes):
            raise ValueError(f"{where}: stroke {k} has attributes {sorted(sa.attributes)} in {keys[0]} "
                             f"but {sorted(sb.attributes)} in {keys[1]}")
    n = min(len(a), len(b))
    return list(zip(a, b)), a[n:], b[n:]


def _faded(stroke, weight):
    """A stroke left over, as drawn, its opacity times weight."""
    attrs = dict(stroke.attributes)
    attrs["opacity"] = weight * attrs.get("opacity", np.ones(len(stroke.points)))
    return Stroke(stroke.points, cyclic=stroke.cyclic, **attrs)


def resample(points, count, **attributes):
    """A polyline (n, d) resampled to `count` points evenly spaced along its arc length, and its
    per-point attributes at the same places (a dict).  ValueError for fewer than 2 points, a
    count below 2 or a zero length."""
    p = np.asarray(points, dtype=np.float64)
    if int(count) != count or count < 2:
        raise ValueError(f"count must be an integer >= 2, got {count!r}")
    _check(Stroke(p, **attributes), "resample")
    f = geo.arc_fractions(p)
    u = np.linspace(0.0, 1.0, int(count))
    keep = np.concatenate([[True], np.diff(f) > 0])   # repeated points add no arc length
    return geo.sample(p[keep], f[keep], u), {k: geo.sample(np.asarray(v, float)[keep], f[keep], u)
                                              for k, v in attributes.items()}


def _plane_of(pairs, plane, where):
    """The plane of 3D strokes: given, else fitted through all points of both keys."""
    if plane is not None:
        return plane
    pts = np.concatenate([s.points for pair in pairs for s in pair])
    sv = np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)
    if sv[1] <= 1e-9 * sv[0]:
        raise ValueError(f"{where}: the strokes lie on one line, which fixes no plane; pass plane=")
    return Plane.fit(pts)


def _turn(pa, pb):
    """Angle of the best rigid rotation taking the points pa onto pb (paired rows)."""
    a, b = pa - pa.mean(axis=0), pb - pb.mean(axis=0)
    return float(np.arctan2(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]), np.sum(a * b)))


class StrokeInterpolator:
    """Bounded-distortion in-betweens of two keys of a drawing (module docstring).

    strokes_a, strokes_b: sequences of Stroke (or (n, d) point arrays), paired by order; plane: the
    Plane of 3D strokes (None: fitted); touch: how close (in the shapes' units) two strokes must
    come in both keys, at the same points of each, to be joined there (None: 1e-3 of the first
    key's size); joints: False, every stroke on its own path (for comparison); threads as
    Interpolator's; where, keys: how errors name the drawing and its keys; unpaired: "error" (a
    count mismatch is a ValueError) or "fade" (the strokes left over stay as drawn and fade out,
    or in, with t).  Attributes: joints
    [(parent stroke, child stroke, point)], still [(stroke, point)] (ends kept in place), size.
    """

    def __init__(self, strokes_a, strokes_b, *, plane=None, touch=None, joints=True, threads=0,
                 where="strokes", keys=("key a", "key b"), unpaired="error"):
        pairs, *self._left_over = pair_strokes(strokes_a, strokes_b, where, keys, unpaired)
        self.joints, self.still, self._pairs, self._offsets, self._interp = [], [], [], [], None
        self.plane = self.size = self.touch = None
        if pairs:
            self._solver(pairs, plane, touch, joints, threads, where, keys)

    def _solver(self, pairs, plane, touch, joints, threads, where, keys):
        """The bands of the pairs, their joints and still ends, and the Interpolator."""
        d = pairs[0][0].points.shape[1]
        self.plane = _plane_of(pairs, plane, where) if d == 3 else None
        self._pairs = [self._paired(sa, sb) for sa, sb in pairs]
        ca, cb = [p["a"] for p in self._pairs], [p["b"] for p in self._pairs]
        allpts = np.concatenate(ca)
        self.size = float(np.linalg.norm(allpts.max(axis=0) - allpts.min(axis=0)))
        self.touch = TOUCH * self.size if touch is None else float(touch)
        for p in self._pairs:   # a ring: cyclic, or drawn round until its ends meet in both keys
            p["closed"] = p["cyclic"] or (len(p["a"]) >= 4 and all(
                np.linalg.norm(p[k][0] - p[k][-1]) <= self.touch for k in "ab"))
        xa, xb, faces = self._bands(where, keys)
        n, offset = len(self._pairs), sum(len(x) for x in xa)
        ends = still_ends(ca, cb, self.touch)
        tree = self._tree(geo_meetings(ca, cb, self.touch) + [(n + g, k, p) for g, (k, p) in enumerate(ends)]) \
            if joints else []
        self.joints = [j for j in tree if j[0] < n]
        self.still = [(c, point) for p, c, point in tree if p >= n]
        ground = {}   # a still triangle at each still end, which the stroke hangs from
        for c, point in self.still:
            tri = point + 1e-3 * self.size * np.array([[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]])
            xa.append(tri), xb.append(tri), faces.append(np.array([[0, 1, 2]]) + offset)
            ground[c], offset = offset, offset + 3
        links = [(self._offsets[p] if p < n else ground[c], self._offsets[c], point) for p, c, point in tree]
        self._interp = Interpolator([np.concatenate(xa), np.concatenate(xb)], np.concatenate(faces),
                                    joints=links or False, threads=threads)

    def _bands(self, where, keys):
        """The bands' vertices in each key and their faces, one list entry per stroke (a ring's
        repeated last point left out); sets each band's first vertex in self._offsets."""
        ring = [p["closed"] for p in self._pairs]
        ca = [p["a"][:-1] if r else p["a"] for p, r in zip(self._pairs, ring)]
        cb = [p["b"][:-1] if r else p["b"] for p, r in zip(self._pairs, ring)]
        try:
            bands = geo.fit_bands(ca, cb, ring)
        except ValueError as e:
            raise ValueError(f"{where}: " + str(e).replace("key a", keys[0]).replace("key b", keys[1])) from None
        xa, xb, faces, self._offsets = [], [], [], []
        offset = 0
        for va, vb, f in bands:
            xa.append(va), xb.append(vb), faces.append(f + offset)
            self._offsets.append(offset)
            offset += len(va)
        return xa, xb, faces

    def _paired(self, sa, sb):
        """The pair in plane coordinates at common points: a, b (m, 2), the attributes and the
        heights above the plane of each key at those points; a cyclic pair with its first point
        repeated at the end (so that arc lengths count the closing segment)."""
        out = {"cyclic": sa.cyclic and sb.cyclic}
        again = (lambda v: np.concatenate([v, v[:1]])) if out["cyclic"] else (lambda v: v)  # noqa: E731
        for key, s in (("a", sa), ("b", sb)):
            p = again(s.points)
            if self.plane is not None:
                out["h" + key] = (p - self.plane.origin) @ self.plane.normal
                p = self.plane.to_plane(p, "strokes", tolerance=np.inf)
            out[key], out["attr" + key] = p, {n: again(v) for n, v in s.attributes.items()}
        corr = geo.correspondence(out["a"], out["b"])
        if corr is not None:
            u = corr[0]
            for key, f in (("a", corr[1]), ("b", corr[2])):
                keep = np.concatenate([[True], np.diff(f) > 0])
                resampled = lambda v: geo.sample(np.asarray(v)[keep], f[keep], u)  # noqa: E731
                out[key] = resampled(out[key])
                out["attr" + key] = {n: resampled(v) for n, v in out["attr" + key].items()}
                if "h" + key in out:
                    out["h" + key] = resampled(out["h" + key])
        return out

    def _tree(self, meetings):
        """Joints (parent, child stroke, point in key a) of a spanning forest of the meetings
        (parents numbered from len(pairs) are still ends), each tree rooted at a still end, else at
        its stroke that turns least between the keys (so that no stroke is carried the long way
        round by one that turns more)."""
        near = {}
        for i, j, point in meetings:
            near.setdefault(i, []).append((j, point))
            near.setdefault(j, []).append((i, point))
        turns = {k: abs(_turn(self._pairs[k]["a"], self._pairs[k]["b"])) if k < len(self._pairs) else -1.0
                 for k in near}
        seen, out = set(), []
        for root in sorted(near, key=lambda k: (turns[k], k)):
            if root in seen:
                continue
            seen.add(root)
            queue = deque([root])
            while queue:
                parent = queue.popleft()
                for child, point in near[parent]:
                    if child not in seen and child < len(self._pairs):   # a still end is only a root
                        seen.add(child)
                        out.append((parent, child, point))
                        queue.append(child)
        return out

    @property
    def stats(self):
        """The Interpolator's FrameStats of the last call (None when no stroke is paired)."""
        return self._interp.stats if self._interp is not None else None

    def frames(self, ts):
        """The in-betweens at every t of ts: a list (per t) of lists of Stroke (the pairs', then
        key a's strokes left over fading out, then key b's fading in)."""
        ts = np.asarray(ts, dtype=np.float64).ravel()
        X = self._interp.frames(ts) if self._interp is not None else [None] * len(ts)
        return [self._strokes(x, t) + [_faded(s, 1 - t) for s in self._left_over[0]]
                + [_faded(s, t) for s in self._left_over[1]] for x, t in zip(X, ts)]

    def at(self, t):
        """The in-between at t: a list of Stroke."""
        return self.frames([t])[0]

    def _strokes(self, x, t):
        out = []
        for pair, offset in zip(self._pairs, self._offsets):
            m = len(pair["a"])
            p = x[offset:offset + m - pair["closed"]]
            if pair["closed"]:    # the ring's last point is its first
                p = np.concatenate([p, p[:1]])
            if self.plane is not None:
                p = self.plane.to_space(p) + ((1 - t) * pair["ha"] + t * pair["hb"])[:, None] * self.plane.normal
            attrs = {n: (1 - t) * v + t * pair["attrb"][n] for n, v in pair["attra"].items()}
            keep = m - pair["cyclic"]    # a cyclic stroke without the repeated point
            out.append(Stroke(p[:keep], cyclic=pair["cyclic"], **{n: v[:keep] for n, v in attrs.items()}))
        return out


def geo_meetings(ca, cb, touch):
    """(stroke i, stroke j, point in key a) for every pair of strokes that come within touch of
    each other in key a and, at the same points of each, in key b: the place where they come
    closest in both together (the midpoint of the two points in key a)."""
    if len(ca) < 2:
        return []
    pairs, owner = geo.near_segments(ca, touch)
    if not len(pairs):
        return []
    out = []
    ends = [np.concatenate([c[:-1] for c in cs]) for cs in (ca, cb)]
    nexts = [np.concatenate([c[1:] for c in cs]) for cs in (ca, cb)]
    i, j = pairs[:, 0], pairs[:, 1]
    d, s, u = geo.segment_distances(ends[0][i], nexts[0][i], ends[0][j], nexts[0][j])
    at = lambda k, seg, f: ends[k][seg] + f[:, None] * (nexts[k][seg] - ends[k][seg])  # noqa: E731
    db = np.linalg.norm(at(1, i, s) - at(1, j, u), axis=1)
    ok = np.flatnonzero((d <= touch) & (db <= touch))
    best = {}
    for k in ok[np.argsort(d[ok] + db[ok], kind="stable")]:
        best.setdefault((int(owner[i[k]]), int(owner[j[k]])), k)
    for (si, sj), k in sorted(best.items()):
        point = 0.5 * (at(0, i[k:k + 1], s[k:k + 1])[0] + at(0, j[k:k + 1], u[k:k + 1])[0])
        out.append((si, sj, point))
    return out


def still_ends(ca, cb, touch):
    """(stroke, point in key a) for every end of a stroke that is at the same place (within touch)
    in both keys: a tail's root, an arm's shoulder, which the in-betweens keep there."""
    return [(k, a[e]) for k, (a, b) in enumerate(zip(ca, cb)) for e in (0, -1)
            if np.linalg.norm(a[e] - b[e]) <= touch]


def interpolate_strokes(strokes_a, strokes_b, ts, **options):
    """The in-betweens of two keys of strokes at every t of ts (StrokeInterpolator's options):
    a list (per t) of lists of Stroke."""
    return StrokeInterpolator(strokes_a, strokes_b, **options).frames(ts)
