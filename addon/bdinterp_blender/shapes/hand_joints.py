"""Parents set by hand in the joint tree (Object.bdi.joint_parent; docs/JOINTS.md).

A joint tree (the bones' links, or the joints the core found from the keys) becomes given links
with each hand-set piece hanging from the piece set: [(parent vertex, child vertex, point)], the
core's `joints=` argument. No bpy here, so the rules are tested without Blender; numpy is imported
inside the functions (enabling the add-on should not cost its import).
"""

from .mesh_io import BakeError
from .rig import rigid_motion

# A relative turn (radians) below which a hand-set joint has no pivot: it sits at the child's centre.
TURN_LEAST = 1e-3


def found_links(solver):
    """[(parent vertex, child vertex, point)] of every joint an Interpolator found (its tree)."""
    import numpy as np
    return [(int(j["parent"]), int(j["child"]), np.asarray(j["point"], dtype=np.float64))
            for j in solver.joints()]


def apply(links, hand_set, labels, shapes):
    """`links` (the tree: at most one link per child piece, parent vertex -1 for a root's path)
    with every (child vertex, parent vertex, names) of `hand_set` put in: the child's piece hangs
    from the parent's, at the point of the tree's link between the two (either way round) if it
    has one, else at the fixed point of the child's motion against the parent (pivot()).
    Where the new link closes a cycle, the link into the child's subtree on the way up from the
    parent is dropped (that piece becomes a root): the tree is re-hung as set. Two hand-set links
    that make a cycle are a BakeError naming both pieces. labels (n,): each vertex's piece."""
    import numpy as np
    by_child = {int(labels[c]): (int(p), int(c), pt) for p, c, pt in links}
    points = {frozenset((int(labels[p]), int(labels[c]))): pt for p, c, pt in links if p >= 0}
    fixed = {}
    for child, parent, names in hand_set:
        cp, pp = int(labels[child]), int(labels[parent])
        if cp == pp:
            raise BakeError("%s: its joint parent %s is the same piece" % names)
        below = _below(by_child, labels, pp, cp)
        if below is not None:
            if below in fixed:
                raise BakeError("%s and %s: their joint parents make a cycle"
                                % (names[0], fixed[below][0]))
            del by_child[below]
        point = points.get(frozenset((cp, pp)))
        if point is None:
            point = pivot(shapes, labels == cp, labels == pp)
        by_child[cp] = (int(parent), int(child), np.asarray(point, dtype=np.float64))
        fixed[cp] = names
    return list(by_child.values())


def _below(by_child, labels, piece, top):
    """The piece just below `top` on the way up from `piece` to its root, None if top is not on it."""
    seen = set()
    while piece in by_child and piece not in seen:
        seen.add(piece)
        parent = by_child[piece][0]
        if parent < 0:
            return None
        up = int(labels[parent])
        if up == top:
            return piece
        piece = up
    return None


def pivot(shapes, child, parent):
    """The point (3,) of the base shape that the child's and the parent's rigid motions carry to
    one place in the input that turns the child most against the parent (the relative motion's
    fixed point, nearest the child's centre), or the child's centre where no input turns it by
    TURN_LEAST. shapes: (k, n, 3), the base first; child, parent: (n,) masks of the pieces."""
    import numpy as np
    base = np.asarray(shapes[0], dtype=np.float64)
    centre = base[child].mean(axis=0)
    best, point = TURN_LEAST, centre
    for X in shapes[1:]:
        Rc, dc = rigid_motion(base[child], X[child])
        Rp, dp = rigid_motion(base[parent], X[parent])
        turn = np.arccos(np.clip((np.trace(Rp.T @ Rc) - 1) / 2, -1.0, 1.0))
        if turn > best:  # (Rp - Rc) x = dc - dp: the point both carry alike
            A, b = Rp - Rc, dc - dp - (Rp - Rc) @ centre
            best, point = turn, centre + np.linalg.lstsq(A, b, rcond=1e-9)[0]
    return point

