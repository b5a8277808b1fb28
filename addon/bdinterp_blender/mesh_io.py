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


def read_raw(kb):
    """kb's coordinates as Blender stores them: float32 (n*3,)."""
    import numpy as np
    co = np.empty(len(kb.data) * 3, dtype=np.float32)
    kb.data.foreach_get("co", co)
    return co


def read_co(kb):
    return read_raw(kb).reshape(-1, 3).astype(float)


def write_co(kb, co):
    import numpy as np
    kb.data.foreach_set("co", np.ascontiguousarray(co, dtype=np.float32).ravel())


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


def project_planar(shapes, names, rel_tol):
    """Project every shape onto the plane of shapes[0] (bdinterp.Plane, the package's one fit and
    tolerance definition); BakeError if a key is farther from it than rel_tol x its largest extent,
    saying by how much.

    Projecting here makes this (user-set) tolerance the one that counts: the core then sees
    exactly planar input (Blender's float32 coordinates are only planar to ~1e-7).
    """
    import numpy as np
    from .core import load_core
    plane = load_core().Plane.fit(shapes[0])
    bad, out = [], []
    for co, name in zip(shapes, names):
        worst, off, size = plane.farthest(co)
        if off > rel_tol * size:
            bad.append("%r is off by %.6g (vertex %d; tolerance %g x size %.4g = %.3g)"
                       % (name, off, worst, rel_tol, size, rel_tol * size))
        out.append(plane.to_space(plane.to_plane(co, name, np.inf)))
    if bad:
        raise BakeError("shape keys are not planar: %s" % "; ".join(bad))
    return out


def anchor_vertex_of_group(obj, group_name):
    """The vertex of `group_name` with the largest weight (lowest index on ties)."""
    group = obj.vertex_groups.get(group_name)
    if group is None:
        raise BakeError("no vertex group named %r" % group_name)
    best, best_w = None, -1.0
    for v in obj.data.vertices:  # vertex groups have no foreach access
        for g in v.groups:
            if g.group == group.index and g.weight > best_w:
                best, best_w = v.index, g.weight
    if best is None:
        raise BakeError("vertex group %r is empty" % group_name)
    return best
