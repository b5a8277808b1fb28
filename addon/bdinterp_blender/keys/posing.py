"""A pose of a cut-out character in one step (a target key on every piece), and the joints a pose
tears apart (reported before a bake).

A character's objects are its pieces, one each (as the layered import makes them). Two pieces
are joined where they overlap in the source key; they form a tree from the largest piece
(pivots.tree), each piece joined to its parent. A joint tears when no point of the overlap is
carried to one place by both pieces' motions (each piece's best rigid motion from the source to
the target key)."""

from . import character
from ..shapes import mesh_io, pivots, rig
from ..shapes.mesh_io import BakeError

TORN = 0.02  # a joint is torn when its pieces part by more than this x the smaller one's size


def free_name(objs, base="Pose"):
    """base, or 'base 2', 'base 3' ...: the first that none of objs has as a shape key."""
    taken = {kb.name for o in objs if o.data.shape_keys for kb in o.data.shape_keys.key_blocks}
    name, n = base, 1
    while name in taken:
        n += 1
        name = "%s %d" % (base, n)
    return name


def add_pose(objs, name=None):
    """A key `name` (default: free_name) on every mesh of objs, equal to its reference key (Basis
    made where missing), made active and chosen as each one's target; returns the name.
    BakeError, nothing changed, if objs holds no mesh or one has the key already."""
    objs = [o for o in (objs if isinstance(objs, (list, tuple)) else [objs])
            if o is not None and o.type == 'MESH']
    if not objs:
        raise BakeError("select the character's pieces (mesh objects) first")
    name = name or free_name(objs)
    has = [o.name for o in objs if o.data.shape_keys and name in o.data.shape_keys.key_blocks]
    if has:
        raise BakeError("%s already has a key %r: choose another name" % (", ".join(has), name))
    for obj in objs:
        if obj.data.shape_keys is None:
            obj.shape_key_add(name="Basis", from_mix=False)
        # value 0 (Blender 5 makes new keys 1): a value set by hand keeps the slider off the key
        obj.shape_key_add(name=name, from_mix=False).value = 0.0
        obj.active_shape_key_index = len(obj.data.shape_keys.key_blocks) - 1
        if hasattr(obj, "bdi"):  # the settings exist while the add-on is registered
            obj.bdi.target = name
    return name


def _inside(points, co, faces):
    """Bool (m,): which points (m, 2) lie in one of the triangles co[faces] (plane coordinates)."""
    import numpy as np
    out = np.zeros(len(points), bool)
    a, b, c = co[faces[:, 0]], co[faces[:, 1]], co[faces[:, 2]]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    det = np.where(np.abs(det) < 1e-30, 1e-30, det)
    for start in range(0, len(points), 256):  # blocks: memory ~ 256 x triangles
        p = points[start:start + 256, None, :]
        dx, dy = p[..., 0] - a[:, 0], p[..., 1] - a[:, 1]
        u = (dx * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * dy) / det
        v = ((b[:, 0] - a[:, 0]) * dy - dx * (b[:, 1] - a[:, 1])) / det
        out[start:start + 256] = ((u >= 0) & (v >= 0) & (u + v <= 1)).any(axis=1)
    return out


class _Piece:
    """A member's source and target in world coordinates, its triangles and its rigid motion."""

    def __init__(self, obj, source, target, axes):
        import numpy as np
        key = obj.data.shape_keys.key_blocks
        self.name = obj.name
        self.source = character.to_world(obj, mesh_io.read_co(key[source or obj.data.shape_keys
                                                                  .reference_key.name]))
        self.target = character.to_world(obj, mesh_io.read_co(key[target]))
        self.faces = mesh_io.triangles(obj.data)[0]
        self.flat = self.source[:, axes]
        self.size = float(np.linalg.norm(np.ptp(self.source, axis=0)))
        self.R, self.t = rig.rigid_motion(self.source, self.target)


def _shared(a, b):
    """(how many vertices of a and b lie in the other, those points (k, 3)) in the source."""
    import numpy as np
    pa = a.source[_inside(a.flat, b.flat, b.faces)]
    pb = b.source[_inside(b.flat, a.flat, a.faces)]
    points = np.concatenate([pa, pb])
    return len(points), points


def _parting(a, b, points):
    """How far the motions of a and b carry the overlap's nearest point apart."""
    import numpy as np
    M, c = a.R - b.R, a.t - b.t
    fixed = np.linalg.lstsq(M, -c, rcond=None)[0]  # where the two motions agree (a turn's centre)
    fixed = np.clip(fixed, points.min(0), points.max(0))
    candidates = np.vstack([points, fixed])
    return float(np.linalg.norm(candidates @ M.T + c, axis=1).min())


def torn_joints(objs, target, source=None):
    """[(piece, its parent, distance)] of the joints of the character objs (those with the key
    `target`) that the pose source -> target tears apart, furthest first; world units."""
    import numpy as np
    members = character.members(objs, target)
    if len(members) < 2:
        return []
    everything = np.concatenate([character.to_world(o, mesh_io.read_co(o.data.shape_keys.reference_key))
                                 for o in members])
    axes = list(np.argsort(np.ptp(everything, axis=0))[1:])  # the picture's plane: widest two
    pieces = [_Piece(o, source, target, axes) for o in members]
    shared = {(i, j): _shared(pieces[i], pieces[j])
              for i in range(len(pieces)) for j in range(i + 1, len(pieces))}
    parents, _ = pivots.tree([len(p.faces) * p.size for p in pieces],
                             {k: (n, pts) for k, (n, pts) in shared.items()})
    out = []
    for i, j in enumerate(parents):
        if j is None:
            continue
        points = shared[min(i, j), max(i, j)][1]
        apart = _parting(pieces[i], pieces[j], points)
        if apart > TORN * min(pieces[i].size, pieces[j].size):
            out.append((pieces[i].name, pieces[j].name, apart))
    return sorted(out, key=lambda item: -item[2])


def describe(torn, limit=3):
    """Plain words for torn_joints' list."""
    parts = ["%r comes off %r by %.3g" % (a, b, d) for a, b, d in torn[:limit]]
    more = " and %d more" % (len(torn) - limit) if len(torn) > limit else ""
    return "; ".join(parts) + more
