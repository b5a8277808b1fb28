"""Joints between the pieces of a cut-out character, taken from the armature that moves them.

A piece's bone is the bone whose vertex group holds most of the piece's weight (an Armature
modifier's), else the bone the object is parented to. A piece hangs from the piece of the nearest
ancestor bone that has one, pinned at the head of the bone below that ancestor, in the source key;
pieces whose bones meet only at bones without a piece are joined through them, and the root piece
follows its bone's path (reads bpy data, never writes it; docs/JOINTS.md).
"""

from .mesh_io import BakeError, group_weights

MODES = ("auto", "bones", "pins", "off")


def joint_mode(joints):
    """'auto', 'bones', 'pins' or 'off' of bake(..., joints=) (any case; True: 'auto', False:
    'off'); BakeError otherwise."""
    if isinstance(joints, bool) or type(joints).__name__ == "bool_":
        return "auto" if joints else "off"
    if isinstance(joints, str) and joints.lower() in MODES:
        return joints.lower()
    raise BakeError("joints must be 'auto', 'bones', 'pins' or 'off', got %r" % (joints,))


class Member:
    """One object of the solved mesh: its vertices begin at `offset`; `source` (n, 3) is its
    source key in its local coordinates; `to_solved` maps (k, 3) local points into the solved
    mesh's coordinates; `reference` reads its reference key ((n, 3) local) when needed."""

    def __init__(self, obj, offset, source, to_solved, reference):
        self.obj, self.offset, self.source = obj, offset, source
        self.to_solved, self.reference = to_solved, reference


def core_joints(mode, members, labels):
    """(bdinterp's joints argument, where they came from) for `mode`: False for 'off', True for
    'pins' (found from the keys), the bones' links [(parent vertex, child vertex, point)] for
    'bones' (BakeError naming a piece with no bone), and for 'auto' the bones' links where every
    piece has a bone of one armature, else True. labels (n,): the piece of each solved vertex."""
    if mode in ("off", "pins"):
        return mode == "pins", ""
    try:
        arm, bones = piece_bones(members, labels)
    except BakeError:
        if mode == "bones":
            raise
        return True, ""
    # no piece under another: each on its own path
    return links(arm, bones, members, labels) or False, "bones of %r" % arm.name


def piece_bones(members, labels):
    """(armature object, [(bone name, member, its local vertex indices)] per piece) or BakeError
    naming the first piece with no bone, or the second armature."""
    import numpy as np
    out, arm = [], None
    for m in members:
        weights = group_weights(m.obj)[0]
        local = labels[m.offset:m.offset + len(m.source)]
        for p in np.unique(local):
            rows = np.flatnonzero(local == p)
            found = _bone_of(m.obj, weights, rows)
            if found is None:
                raise BakeError("%s: the piece of vertex %d has no bone (no vertex group of an "
                                "Armature modifier's bone, no parent bone)" % (m.obj.name, rows[0]))
            if arm is not None and found[0] != arm:
                raise BakeError("%s: the piece of vertex %d is moved by armature %r, others by %r"
                                % (m.obj.name, rows[0], found[0].name, arm.name))
            arm = found[0]
            out.append((found[1], m, rows))
    return arm, out


def _bone_of(obj, weights, rows):
    """(armature object, bone name) moving obj's vertices `rows`, or None."""
    totals = weights[rows].sum(axis=0)
    for mod in obj.modifiers:
        arm = getattr(mod, "object", None)
        if mod.type != 'ARMATURE' or arm is None or not mod.use_vertex_groups:
            continue
        named = [(totals[g.index], g.name) for g in obj.vertex_groups
                 if g.name in arm.data.bones and totals[g.index] > 0]
        if named:
            return arm, max(named)[1]
    parent = obj.parent
    if obj.parent_type == 'BONE' and parent is not None and parent.type == 'ARMATURE' \
            and obj.parent_bone in parent.data.bones:
        return parent, obj.parent_bone
    return None


def links(arm, bones, members, labels):
    """[(parent vertex, child vertex, point)]: each piece under the piece of its bone's nearest
    ancestor that has one (pieces of one bone: under the largest), pinned at the head of the
    bone just below that ancestor, mapped into the source key. Pieces with no such ancestor whose
    bones meet at a bone without a piece (a hip, a root) hang from the one of them whose bone lies
    nearest that bone, at the head of their own bone (the offset between them, which a rig that
    translates the hip changes, is blended); that piece follows its top bone's path: a link with
    parent -1 at the head of its own bone."""
    owner = {}
    for k, (bone, _, rows) in sorted(enumerate(bones), key=lambda e: -len(e[1][2])):
        owner.setdefault(bone, k)
    out, tops = [], {}
    for k, (bone, member, rows) in enumerate(bones):
        below, up = arm.data.bones[bone], arm.data.bones[bone].parent
        if owner[bone] != k:
            up = below
        while up is not None and up.name not in owner:
            below, up = up, up.parent
        if up is None:  # a root among the pieces: grouped by the top bone of its chain
            tops.setdefault(below.name, []).append(k)
            continue
        out.append(_link(arm, bones, owner[up.name], k, below))
    for group in tops.values():
        main = min(group, key=lambda k: (len(arm.data.bones[bones[k][0]].parent_recursive),
                                         -len(bones[k][2]), k))
        out.append(_link(arm, bones, None, main, arm.data.bones[bones[main][0]]))
        out += [_link(arm, bones, main, k, arm.data.bones[bones[k][0]]) for k in group if k != main]
    return out


def _link(arm, bones, parent, child, bone):
    """(parent piece's first vertex, or -1 for a root's path; child's; the head of `bone` in the
    child's source key, in the solved mesh's coordinates)."""
    _, member, rows = bones[child]
    point = member.to_solved(_head_in_source(arm, bone, member, rows))[0]
    first = -1 if parent is None else int(bones[parent][1].offset + bones[parent][2][0])
    return (first, int(member.offset + rows[0]), point)


def _head_in_source(arm, bone, member, rows):
    """(1, 3) the bone's head in the member's local coordinates of its source key: the rest head
    for a deforming bone (the keys are the undeformed mesh), the posed head for a parent bone,
    carried by the piece's rigid motion from the reference key to the source where they differ."""
    import numpy as np
    obj = member.obj
    if obj.parent_type == 'BONE' and obj.parent == arm:
        head = arm.pose.bones[bone.name].head
    else:
        head = bone.head_local
    to_local = np.linalg.inv(np.array(obj.matrix_world)) @ np.array(arm.matrix_world)
    point = to_local[:3, :3] @ np.array(head) + to_local[:3, 3]
    ref = member.reference()[rows]
    src = member.source[rows]
    if np.abs(ref - src).max() > 0:
        point = _rigid_fit(ref, src, point)
    return point[None, :]


def rigid_motion(A, B):
    """(R (3, 3), t (3,)): the rotation and translation that best map points A onto B (Kabsch)."""
    import numpy as np
    a, b = A.mean(axis=0), B.mean(axis=0)
    U, _, Vt = np.linalg.svd((A - a).T @ (B - b))
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    R = Vt.T @ D @ U.T
    return R, b - R @ a


def _rigid_fit(A, B, p):
    """p carried by the rotation and translation that best map points A onto B (Kabsch)."""
    R, t = rigid_motion(A, B)
    return R @ p + t


def hand_set(members, labels):
    """[(child vertex, parent vertex, (child's name, parent's name))] of the members whose joint
    parent is set by hand (Object.bdi.joint_parent): each object's largest piece under the
    parent object's largest piece. BakeError for a parent that is not one of the members."""
    names = {m.obj.name: m for m in members}
    out = []
    for m in members:
        parent = getattr(getattr(m.obj, "bdi", None), "joint_parent", None)
        if parent is None:
            continue
        if parent.name not in names:
            raise BakeError("%s: its joint parent %r is not part of the character (%s): select it "
                            "too, or set the parent to Automatic"
                            % (m.obj.name, parent.name, ", ".join(sorted(names))))
        out.append((_largest_piece(m, labels), _largest_piece(names[parent.name], labels),
                    (repr(m.obj.name), repr(parent.name))))
    return out


def _largest_piece(member, labels):
    """The solved mesh's first vertex of the member's piece with the most vertices."""
    import numpy as np
    local = np.asarray(labels[member.offset:member.offset + len(member.source)])
    pieces, first, counts = np.unique(local, return_index=True, return_counts=True)
    return int(member.offset + first[np.argmax(counts)])
