"""Geometry behind bdinterp.strokes: arc-length correspondence, the band around a stroke, and
where two strokes meet.  2D arrays throughout (the caller maps 3D strokes into their plane)."""
import numpy as np

# A band this many times narrower than the spacing of its points is given up on: its triangles
# would be too thin for the flattening to measure their angles.
MIN_BAND = 1e-3
SHRINKS = 10        # halvings of the band's width tried before a stroke is called folded


def arc_fractions(points):
    """Cumulative arc length of a polyline as a fraction of its length, (n,)."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    return s / s[-1]


def sample(points, fractions, u):
    """The polyline (and any per-point values in the same rows) at arc-length fractions u."""
    flat = points.reshape(len(points), -1)
    out = np.empty((len(u), flat.shape[1]))
    for c in range(flat.shape[1]):
        out[:, c] = np.interp(u, fractions, flat[:, c])
    return out.reshape((len(u),) + points.shape[1:])


def correspondence(pa, pb):
    """Arc-length fractions (u_a, u_b) at which two strokes are paired point by point: their own
    points when the counts agree and no point repeats (the keys then stay exactly as drawn), else
    the fractions of the stroke with more points (repeated points dropped), for both."""
    fa, fb = arc_fractions(pa), arc_fractions(pb)
    if len(pa) == len(pb) and np.all(np.diff(fa) > 0) and np.all(np.diff(fb) > 0):
        return None
    u = np.unique(fa if len(pa) >= len(pb) else fb)
    return u, fa, fb


def _unit(v):
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


def tangents(points, closed=False):
    """Unit tangent per point of strokes (g, m, 2): the mean of the directions of its segments
    (one at the ends of an open stroke; a closed one also runs from its last point to its first)."""
    d = _unit((np.roll(points, -1, axis=1) - points) if closed else np.diff(points, axis=1))
    before = np.roll(d, 1, axis=1) if closed else d[:, :-1]
    after = d if closed else d[:, 1:]
    inner = before + after
    turned_back = np.linalg.norm(inner, axis=2) < 1e-12
    inner[turned_back] = before[turned_back]
    if closed:
        return _unit(inner)
    t = np.empty_like(points)
    t[:, 0], t[:, -1], t[:, 1:-1] = d[:, 0], d[:, -1], inner
    return _unit(t)


def band_faces(m, offset, closed=False):
    """Triangles of the band of an m-point stroke whose vertices start at offset: centre row
    C_i = offset + i, left row L_i = offset + m + i, right row R_i = offset + 2m + i; an open
    stroke's start tip offset + 3m and end tip offset + 3m + 1, a closed one's ring runs on from
    its last point to its first.  Counter-clockwise for a band built by band_vertices."""
    i = np.arange(m if closed else m - 1)
    n = (i + 1) % m
    C, L, R = offset + i, offset + m + i, offset + 2 * m + i
    Cn, Ln, Rn = offset + n, offset + m + n, offset + 2 * m + n
    strip = np.concatenate([np.stack([R, Rn, Cn], 1), np.stack([R, Cn, C], 1),
                            np.stack([C, Cn, Ln], 1), np.stack([C, Ln, L], 1)])
    if closed:
        return strip
    s, e, last = offset + 3 * m, offset + 3 * m + 1, m - 1
    caps = np.array([[s, offset + 2 * m, offset], [s, offset, offset + m],
                     [offset + 2 * m + last, e, offset + last], [offset + last, e, offset + m + last]])
    return np.concatenate([strip, caps])


def band_vertices(points, half_width, closed=False):
    """The bands' vertices (g, 3m (+ 2), 2) of strokes (g, m, 2) with half widths (g,): the stroke
    itself (so the in-between's centreline is read back exactly), its offsets to the left and
    right, and for an open stroke a tip beyond each end (so the ends are inside the band, where a
    joint at a stroke's end can hold it)."""
    t = tangents(points, closed)
    h = half_width[:, None, None]
    n = np.stack([-t[..., 1], t[..., 0]], axis=2)
    rows = [points, points + h * n, points - h * n]
    if not closed:
        rows += [points[:, :1] - h * t[:, :1], points[:, -1:] + h * t[:, -1:]]
    return np.concatenate(rows, axis=1)


def _signed_areas(X, faces):
    a, b, c = X[:, faces[:, 0]], X[:, faces[:, 1]], X[:, faces[:, 2]]
    return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])


def _fits(va, vb, faces, floor):
    """Per band: no triangle folds (or collapses below floor) in either key."""
    return ((_signed_areas(va, faces) > floor[:, None]).all(axis=1)
            & (_signed_areas(vb, faces) > floor[:, None]).all(axis=1))


def fit_bands(ca, cb, closed):
    """[(vertices in key a, vertices in key b, faces)] of a band per stroke pair (ca[k], cb[k],
    m_k points each; closed[k]: a ring, its last point joined to its first), strokes of one kind
    at a time: as wide as a quarter of the shorter key's mean spacing, halved until no triangle
    folds in either key.  ValueError naming the stroke when none fits (it turns back on itself)."""
    out = [None] * len(ca)
    for m, ring in sorted({(len(p), c) for p, c in zip(ca, closed)}):
        ks = [k for k, (p, c) in enumerate(zip(ca, closed)) if len(p) == m and c == ring]
        A, B = np.stack([ca[k] for k in ks]), np.stack([cb[k] for k in ks])
        spacing = np.minimum(*(np.linalg.norm(np.diff(P, axis=1), axis=2).mean(axis=1) for P in (A, B)))
        faces, h = band_faces(m, 0, ring), 0.25 * spacing
        VA = np.empty((len(ks), 3 * m + (0 if ring else 2), 2))
        VB = np.empty_like(VA)
        todo = np.arange(len(ks))
        for _ in range(SHRINKS):
            va, vb = band_vertices(A[todo], h[todo], ring), band_vertices(B[todo], h[todo], ring)
            ok = _fits(va, vb, faces, 1e-12 * h[todo] * spacing[todo])
            VA[todo[ok]], VB[todo[ok]] = va[ok], vb[ok]
            todo = todo[~ok]
            if not len(todo):
                break
            h[todo] *= 0.5
        if len(todo):
            i = todo[0]
            bad = [np.flatnonzero(_signed_areas(v[i:i + 1], faces)[0] <= 1e-12 * h[i] * spacing[i])
                   for v in (band_vertices(A, h, ring), band_vertices(B, h, ring))]
            key = 0 if len(bad[0]) else 1
            raise ValueError(f"stroke {ks[i]}: key {'ab'[key]}: the stroke turns back on itself near point "
                             f"{int(min(faces[bad[key][0]] % m))} (its band folds even {2 ** SHRINKS} times narrower)")
        for i, k in enumerate(ks):
            out[k] = (VA[i], VB[i], faces)
    return out


def segment_distances(a0, a1, b0, b1):
    """Per row: distance between segments a0-a1 and b0-b1 (k, 2) and the fractions (s, u) along
    each of their closest points."""
    da, db, r = a1 - a0, b1 - b0, b0 - a0
    cross = lambda p, q: p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]  # noqa: E731
    den = cross(da, db)
    ok = np.abs(den) > 1e-300
    s = np.where(ok, cross(r, db) / np.where(ok, den, 1.0), -1.0)
    u = np.where(ok, cross(r, da) / np.where(ok, den, 1.0), -1.0)
    crossing = (s >= 0) & (s <= 1) & (u >= 0) & (u <= 1)
    best = np.full(len(a0), np.inf)
    bs, bu = np.where(crossing, s, 0.0), np.where(crossing, u, 0.0)
    best[crossing] = 0.0
    for p, q0, dq, on_a in ((a0, b0, db, True), (a1, b0, db, True), (b0, a0, da, False),
                            (b1, a0, da, False)):
        f = np.clip(np.einsum("ij,ij->i", p - q0, dq) / np.maximum(np.einsum("ij,ij->i", dq, dq), 1e-300), 0, 1)
        d = np.linalg.norm(q0 + f[:, None] * dq - p, axis=1)
        better = d < best
        best[better] = d[better]
        end = 0.0 if p is a0 or p is b0 else 1.0
        bs[better] = end if on_a else f[better]
        bu[better] = f[better] if on_a else end
    return best, bs, bu


def _spans(n):
    """For runs of lengths n: (index of the run, position within it) of every element."""
    run = np.repeat(np.arange(len(n)), n)
    return run, np.arange(run.size) - np.repeat(np.cumsum(n) - n, n)


def near_segments(points, tolerance):
    """Candidate pairs (i, j) of segments of different strokes that may lie within tolerance of
    each other: those whose bounding boxes, grown by tolerance, share a cell of a uniform grid as
    fine as twice the median segment (a long segment lies in every cell its box covers, so one long
    stroke does not coarsen the grid for all).  points: list of (m_k, 2) polylines.  Returns
    (pairs (p, 2) of global segment indices, the lower stroke's first; owner stroke of every
    segment)."""
    a = np.concatenate([p[:-1] for p in points])
    b = np.concatenate([p[1:] for p in points])
    owner = np.repeat(np.arange(len(points)), [len(p) - 1 for p in points])
    cell = max(float(2.0 * np.median(np.linalg.norm(b - a, axis=1))) + tolerance, 1e-300)
    lo = np.floor((np.minimum(a, b) - tolerance) / cell).astype(np.int64)
    hi = np.floor((np.maximum(a, b) + tolerance) / cell).astype(np.int64)
    origin, size = lo.min(axis=0), hi - lo + 1
    seg, k = _spans(size[:, 0] * size[:, 1])                 # every (segment, cell it covers)
    cx, cy = lo[seg, 0] + k // size[seg, 1] - origin[0], lo[seg, 1] + k % size[seg, 1] - origin[1]
    key = cx * (int(hi[:, 1].max() - origin[1]) + 1) + cy
    order = np.argsort(key, kind="stable")
    seg, key = seg[order], key[order]
    starts = np.flatnonzero(np.concatenate([[True], key[1:] != key[:-1]]))
    group = np.diff(np.concatenate([starts, [len(key)]]))
    member, place = _spans(group)                            # every entry's group and place in it
    later = group[member] - place - 1                        # partners after it in its cell
    i_entry = np.repeat(np.arange(len(key)), later)
    _, step = _spans(later)
    i, j = seg[i_entry], seg[i_entry + step + 1]
    keep = owner[i] != owner[j]
    i, j = i[keep], j[keep]
    swap = owner[i] > owner[j]
    pairs = np.stack([np.where(swap, j, i), np.where(swap, i, j)], 1)
    return (np.unique(pairs, axis=0) if len(pairs) else np.empty((0, 2), np.int64)), owner
