"""Where each layer of a cut-out painting turns (no bpy): the pieces form a tree by overlap, rooted
at the largest piece; a piece's pivot is the middle of its overlap with its parent (the shoulder
of an upper arm, the elbow of a forearm), and a piece that overlaps none, or the root, turns about
the middle of its bounding box. Canvas pixels, y downwards."""

MIN_OVERLAP = 4  # pixels two layers must share to count as joined


def _overlap(a, b):
    """(pixels, (x, y) their middle) that the masks a and b, each (x, y, mask (h, w) bool),
    share."""
    import numpy as np
    (xa, ya, ma), (xb, yb, mb) = a, b
    x0, y0 = max(xa, xb), max(ya, yb)
    x1, y1 = min(xa + ma.shape[1], xb + mb.shape[1]), min(ya + ma.shape[0], yb + mb.shape[0])
    if x1 <= x0 or y1 <= y0:
        return 0, None
    both = (ma[y0 - ya:y1 - ya, x0 - xa:x1 - xa] & mb[y0 - yb:y1 - yb, x0 - xb:x1 - xb])
    rows, cols = np.nonzero(both)
    if len(rows) < MIN_OVERLAP:
        return 0, None
    return len(rows), (x0 + cols.mean() + 0.5, y0 + rows.mean() + 0.5)


def _centre(mask):
    """The middle of a mask's opaque pixels' bounding box (the whole mask if none is)."""
    import numpy as np
    x, y, m = mask
    rows, cols = np.nonzero(m)
    if not len(rows):
        return x + m.shape[1] / 2.0, y + m.shape[0] / 2.0
    return x + (cols.min() + cols.max() + 1) / 2.0, y + (rows.min() + rows.max() + 1) / 2.0


def pivots(masks):
    """(parents, points): per mask (x, y, opaque (h, w) bool) its parent's index (None: the root,
    or a piece that overlaps no other) and its pivot (x, y) in canvas pixels (see tree)."""
    n = len(masks)
    shared = {(i, j): _overlap(masks[i], masks[j]) for i in range(n) for j in range(i + 1, n)}
    parents, points = tree([int(m[2].sum()) for m in masks], shared)
    return parents, [p if p is not None else _centre(m) for p, m in zip(points, masks)]


def tree(sizes, shared):
    """(parents, points) of pieces of `sizes` that share {(i, j), i < j: (how much, where)}: each
    piece's parent (None: a root) and where it joins it (None for a root). Breadth first from the
    largest piece (of each island), so that a piece hangs from the neighbour nearest the root (of
    those, the one it shares most with)."""
    n = len(sizes)
    shared = dict(shared)
    shared.update({(j, i): v for (i, j), v in list(shared.items())})
    parents, points = [None] * n, [None] * n
    seen = set()
    for root in sorted(range(n), key=lambda i: -sizes[i]):
        if root in seen:
            continue  # a piece of another island: the largest of each is its root
        seen.add(root)
        level = [root]
        while level:
            nxt = {}
            for j in range(n):
                if j in seen:
                    continue
                best = max(level, key=lambda i: shared[i, j][0])
                if shared[best, j][0]:
                    nxt[j] = best
            for j, i in nxt.items():
                parents[j], points[j] = i, shared[i, j][1]
            seen.update(nxt)
            level = list(nxt)
    return parents, points
