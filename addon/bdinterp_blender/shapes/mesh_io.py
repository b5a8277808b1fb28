"""Mesh and shape-key data <-> numpy (foreach_get/foreach_set; never per-vertex Python loops).

numpy is imported inside the functions: enabling the add-on should not cost its import.
"""


class BakeError(ValueError):
    """Invalid input for a bake/blend/live request; the message is meant for the user."""


def key_of(obj):
    if obj is None or obj.type != 'MESH':
        raise BakeError("%s is not a mesh" % (obj.name if obj else "No object"))
    key = obj.data.shape_keys
    if key is None or len(key.key_blocks) < 2:
        raise BakeError("%s has no shape keys to interpolate (needs at least two)" % obj.name)
    if obj.mode == 'EDIT':
        raise BakeError("%s is in Edit Mode; switch to Object Mode first" % obj.name)
    return key


def key_block(key, name):
    """The key block called `name` ('' or None: the reference key)."""
    if not name:
        return key.reference_key
    kb = key.key_blocks.get(name)
    if kb is None:
        raise BakeError("no shape key named %r" % name)
    return kb


def points(kb):
    """kb's points for foreach_get/foreach_set: ShapeKey.points where Blender has it (4.1 on),
    which copies the array whole (0.1 ms at 100k vertices against 5-7 ms through kb.data, which
    goes point by point; mesh keys only, as here)."""
    return getattr(kb, "points", None) or kb.data


def read_raw(kb):
    """kb's coordinates as Blender stores them: float32 (n*3,)."""
    import numpy as np
    pts = points(kb)
    co = np.empty(len(pts) * 3, dtype=np.float32)
    pts.foreach_get("co", co)
    return co


def read_co(kb):
    return read_raw(kb).reshape(-1, 3).astype(float)


def group_weights(obj):
    """(weights (n, groups), member (n, groups) bool) of obj's vertex groups: the weight of each
    vertex in each group, and whether it is in the group at all (a member may weigh 0).  Vertex
    groups have no foreach access: one pass streams every (vertex, group, weight) into one numpy
    array (collecting them in a list of tuples first took twice as long), numpy puts the weights
    in place."""
    import numpy as np
    from itertools import chain
    vertices = obj.data.vertices
    W = np.zeros((len(vertices), max(1, len(obj.vertex_groups))))
    member = np.zeros(W.shape, dtype=bool)
    flat = np.fromiter(chain.from_iterable((i, g.group, g.weight) for i, v in enumerate(vertices)
                                           for g in v.groups), dtype=np.float64).reshape(-1, 3)
    rows, cols = flat[:, 0].astype(np.int64), flat[:, 1].astype(np.int64)
    W[rows, cols], member[rows, cols] = flat[:, 2], True
    return W, member


def mask_weights(obj, kb):
    """(n,) the weights of kb's vertex-group mask (its Vertex Group field), or None without one."""
    if not kb.vertex_group:
        return None
    group = obj.vertex_groups.get(kb.vertex_group)
    if group is None:  # Blender ignores a mask naming no group: the key shows unmasked
        return None
    return group_weights(obj)[0][:, group.index]


def read_shown(obj, kb, raw):
    """kb's shape as Blender shows it with kb alone at value 1, float64 (n, 3), from its stored
    coordinates `raw` (float32 (n*3,)): reference + w (key - relative) per vertex, w the weight of
    its vertex-group mask (1 without one). Only then is a masked key, or one relative to another
    key, interpolated to where Blender shows it (its stored coordinates are shown nowhere)."""
    co = raw.reshape(-1, 3).astype(float)
    ref, rel = kb.id_data.reference_key, kb.relative_key
    w = mask_weights(obj, kb)
    if kb == ref or (w is None and rel == ref):
        return co
    delta = co - read_co(rel)
    return read_co(ref) + (delta if w is None else w[:, None] * delta)


def write_co(kb, co):
    import numpy as np
    points(kb).foreach_set("co", np.ascontiguousarray(co, dtype=np.float32).ravel())


def triangles(mesh):
    """(faces (m,3) int64, polygon index of each triangle (m,)).

    Blender's loop triangles tessellate quads and (concave) n-gons; they are runtime data, so
    the mesh itself is not changed.
    """
    import numpy as np
    mesh.calc_loop_triangles()
    m = len(mesh.loop_triangles)
    if m == 0:
        raise BakeError("%s has no faces" % mesh.name)
    faces = np.empty(m * 3, dtype=np.int32)
    poly = np.empty(m, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", faces)
    mesh.loop_triangles.foreach_get("polygon_index", poly)
    return faces.reshape(-1, 3).astype(np.int64), poly.astype(np.int64)


def project_layers(shapes, faces, rel_tol):
    """(bdinterp.Layers, shapes) with every piece (loose part) of every shape put exactly into its
    plane: the planes parallel to the common plane of shapes[0]'s pieces (bdinterp.Layers, the
    package's one fit and tolerance definition), each piece at its own depth in each shape (draw
    order). ValueError naming the shape, the vertex and its piece if a vertex is farther than
    rel_tol x the shape's largest extent from its piece's plane (also a piece whose plane is not
    parallel).

    Projecting here makes this (user-set) tolerance the one that counts: the core then sees
    exactly layered input (Blender's float32 coordinates are only planar to ~1e-7).
    """
    import numpy as np
    from ..core import load_core
    layers = load_core().Layers.fit(shapes, faces, base=0, tolerance=rel_tol)
    uv = layers.to_plane(shapes)
    return layers, [layers.to_space(x, np.eye(len(shapes))[i]) for i, x in enumerate(uv)]


def anchor_vertex_of_group(obj, group_name):
    """The vertex of `group_name` with the largest weight (lowest index on ties)."""
    group = obj.vertex_groups.get(group_name)
    if group is None:
        raise BakeError("no vertex group named %r" % group_name)
    import numpy as np
    W, member = group_weights(obj)
    weights = np.where(member[:, group.index], W[:, group.index], -1.0)
    if not member[:, group.index].any():
        raise BakeError("vertex group %r is empty" % group_name)
    return int(np.argmax(weights))  # the first of the largest
