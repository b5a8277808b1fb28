"""Grease Pencil drawings that ride on a bdinterp mesh or character (Blender 4.3+, Grease Pencil v3).

bind_drawing stores, per stroke point, its rest position and radius and the triangle of the
mesh's rest shape (reference key, world space) that holds it (a character of several objects:
their triangles one object after the other, so a point goes to whichever piece holds it):
barycentric coordinates in the mesh's plane (a point outside the mesh: the triangle it is least
outside of, by that triangle's affine map) and the height above the plane.  A handler of the
add-on then writes every point from the evaluated mesh (slider, live mode, baked keys, render),
the radius scaled with the triangle's scale; unbind_drawing writes the rest positions and radii
back.  Everything is stored in point attributes of the drawings, so a saved file keeps working.
"""

import bpy
from bpy.app.handlers import persistent

from ..keys.character import members, to_local, to_world
from ..shapes.mesh_io import BakeError, triangles

BOUND = "bdi_bound_to"   # custom property of the Grease Pencil object: the mesh objects' names
REST, RADIUS, TRI, BARY, HEIGHT = ("bdi_rest_position", "bdi_rest_radius", "bdi_tri", "bdi_bary",
                                   "bdi_height")
ATTRS = ((REST, 'FLOAT_VECTOR'), (RADIUS, 'FLOAT'), (TRI, 'INT'), (BARY, 'FLOAT_VECTOR'),
         (HEIGHT, 'FLOAT'))


def why_not(gp_obj):
    """'' if gp_obj's strokes can be bound, else why not."""
    if bpy.app.version < (4, 3, 0):
        return "binding drawings needs Blender 4.3 or later (Grease Pencil v3)"
    if gp_obj is None or gp_obj.type != 'GREASEPENCIL':
        return "%s is not a Grease Pencil object" % getattr(gp_obj, "name", "No object")
    return ""


def drawings(gp_obj):
    return [f.drawing for layer in gp_obj.data.layers for f in layer.frames if f.drawing is not None]


def read(drawing, name, width):
    import numpy as np
    attr = drawing.attributes[name]
    kind = attr.data_type
    arr = np.empty(len(attr.data) * width, dtype=np.int32 if kind == 'INT' else np.float32)
    attr.data.foreach_get("vector" if width == 3 else "value", arr)
    return arr.reshape(-1, 3) if width == 3 else arr


def write(drawing, name, kind, values):
    import numpy as np
    attr = drawing.attributes.get(name) or drawing.attributes.new(name, kind, 'POINT')
    dtype = np.int32 if kind == 'INT' else np.float32
    attr.data.foreach_set("vector" if kind == 'FLOAT_VECTOR' else "value",
                          np.ascontiguousarray(values, dtype=dtype).ravel())


def world_mesh(mesh_objs, depsgraph=None):
    """(vertices (n, 3) world coordinates as shown, triangles (m, 3)) of the objects one after
    the other; rest (no depsgraph): their reference keys."""
    import numpy as np
    from ..shapes.mesh_io import read_co
    points, tris, offset = [], [], 0
    for obj in mesh_objs:
        faces, _ = triangles(obj.data)
        if depsgraph is None:
            co = to_world(obj, read_co(obj.data.shape_keys.reference_key))
        else:
            ev = obj.evaluated_get(depsgraph)
            co = np.empty(len(ev.data.vertices) * 3, dtype=np.float32)
            ev.data.vertices.foreach_get("co", co)
            co = to_world(ev, co.reshape(-1, 3).astype(np.float64))
        points.append(co)
        tris.append(faces + offset)
        offset += len(co)
    return np.concatenate(points), np.concatenate(tris)


def bound_meshes(gp_obj):
    """The mesh objects gp_obj is bound to (in order); None if one of them is gone."""
    names = gp_obj.get(BOUND, [])
    names = [names] if isinstance(names, str) else list(names)
    objs = [bpy.data.objects.get(name) for name in names]
    return objs if objs and all(o is not None and o.type == 'MESH' for o in objs) else None


def _frames(X, faces):
    """Per triangle: origin (m, 3), edge vectors e1, e2 (m, 3), unit normal (m, 3), area (m,)."""
    import numpy as np
    a, e1, e2 = X[faces[:, 0]], X[faces[:, 1]] - X[faces[:, 0]], X[faces[:, 2]] - X[faces[:, 0]]
    n = np.cross(e1, e2)
    area = np.linalg.norm(n, axis=1)
    return a, e1, e2, n / np.maximum(area, 1e-300)[:, None], area


def locate(P, X, faces):
    """(triangle (p,), barycentric (p, 3), height (p,)) of world points P on the mesh X."""
    import numpy as np
    a, e1, e2, normal, _ = _frames(X, faces)
    plane = normal.sum(axis=0)
    plane /= np.linalg.norm(plane)
    u = np.cross(plane, [1.0, 0.0, 0.0] if abs(plane[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(plane, u)
    basis = np.stack([u, v], axis=1)
    T = np.stack([e1 @ basis, e2 @ basis], axis=2)              # (m, 2, 2)
    Tinv = np.linalg.inv(T)
    tri, bary = np.empty(len(P), dtype=np.int64), np.empty((len(P), 3))
    for s in range(0, len(P), 64):                              # (64, m) at a time
        d = (P[s:s + 64, None, :] - a[None]) @ basis            # (q, m, 2)
        l12 = np.einsum("mij,qmj->qmi", Tinv, d)
        lam = np.concatenate([1.0 - l12.sum(axis=2, keepdims=True), l12], axis=2)
        best = np.argmax(lam.min(axis=2), axis=1)                # inside, or least outside
        tri[s:s + 64], bary[s:s + 64] = best, lam[np.arange(len(best)), best]
    height = np.einsum("pi,pi->p", P - (bary[:, :, None] * X[faces[tri]]).sum(axis=1), normal[tri])
    return tri, bary, height


def place(X, faces, tri, bary, height, rest_area):
    """(world positions (p, 3), radius scale (p,)) of bound points on the mesh shape X."""
    import numpy as np
    _, _, _, normal, area = _frames(X, faces[tri])  # noqa -- per point's own triangle
    pos = (bary[:, :, None] * X[faces[tri]]).sum(axis=1) + height[:, None] * normal
    return pos, np.sqrt(area / np.maximum(rest_area, 1e-300))


def bind_drawing(gp_obj, mesh_obj):
    """Bind every stroke point of gp_obj (all layers and frames) to the rest shape of mesh_obj,
    a mesh object or a list of them (a character: each point to the nearest triangle of any of
    them); from then on the strokes follow wherever the mesh is shown.  Returns the number of
    points."""
    reason = why_not(gp_obj)
    if reason:
        raise BakeError(reason)
    objs = list(mesh_obj) if isinstance(mesh_obj, (list, tuple)) else [mesh_obj]
    for obj in objs or [None]:
        if obj is None or obj.type != 'MESH' or obj.data.shape_keys is None:
            raise BakeError("%s is not a mesh with shape keys" % getattr(obj, "name", "No object"))
    if BOUND in gp_obj:
        unbind_drawing(gp_obj)
    X, faces = world_mesh(objs)
    located = []
    for d in drawings(gp_obj):  # all computed before anything is written
        P = to_world(gp_obj, read(d, "position", 3).astype(float))
        located.append((d, P, locate(P, X, faces) if len(P) else None))
    count = 0
    for d, P, found in located:
        if found is None:
            continue
        tri, bary, height = found
        write(d, REST, 'FLOAT_VECTOR', read(d, "position", 3))
        write(d, RADIUS, 'FLOAT', read(d, "radius", 1))
        write(d, TRI, 'INT', tri)
        write(d, BARY, 'FLOAT_VECTOR', bary)
        write(d, HEIGHT, 'FLOAT', height)
        count += len(P)
    gp_obj[BOUND] = [o.name for o in objs]
    return count


def unbind_drawing(gp_obj):
    """Put every point back where it was drawn (position and radius) and forget the binding."""
    for d in drawings(gp_obj):
        if d.attributes.get(REST) is None:
            continue
        write(d, "position", 'FLOAT_VECTOR', read(d, REST, 3))
        write(d, "radius", 'FLOAT', read(d, RADIUS, 1))
        for name, _ in ATTRS:
            d.attributes.remove(d.attributes[name])
    if BOUND in gp_obj:
        del gp_obj[BOUND]
    gp_obj.data.update_tag()


def update(gp_obj, depsgraph):
    """Write gp_obj's bound points from its meshes as evaluated; False if one of them is gone."""
    import numpy as np
    objs = bound_meshes(gp_obj)
    if objs is None:
        return False
    X, faces = world_mesh(objs, depsgraph)
    rest, _ = world_mesh(objs)
    changed = False
    for d in drawings(gp_obj):
        if d.attributes.get(REST) is None:
            continue
        tri = read(d, TRI, 1).astype(np.int64)
        pos, scale = place(X, faces, tri, read(d, BARY, 3).astype(float),
                           read(d, HEIGHT, 1).astype(float), _frames(rest, faces[tri])[4])
        new = to_local(gp_obj, pos).astype(np.float32)
        if not np.array_equal(new, read(d, "position", 3)):  # our own write re-enters: stop there
            write(d, "position", 'FLOAT_VECTOR', new)
            write(d, "radius", 'FLOAT', read(d, RADIUS, 1) * scale)
            changed = True
    if changed:
        gp_obj.data.update_tag()
    return True


@persistent
def on_update(scene, depsgraph=None):
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    for obj in scene.objects:
        if obj.type == 'GREASEPENCIL' and BOUND in obj:
            update(obj, depsgraph)


def chosen_meshes(context):
    """The active mesh and, if it has a target, the other selected meshes with that key (its
    character, as a bake solves it)."""
    obj = context.object
    target = getattr(getattr(obj, "bdi", None), "target", "")
    others = [o for o in context.selected_objects if o.type == 'MESH' and o != obj]
    return [obj] + (members(others, target) if target else [])


class BDINTERP_OT_bind_drawing(bpy.types.Operator):
    """Bind the selected Grease Pencil objects' strokes to the active mesh (with the selected
    meshes of its character): they follow its in-betweens wherever it is shown (Unbind puts
    every point back where it was drawn)"""
    bl_idname = "bdinterp.bind_drawing"
    bl_label = "Bind Drawings"
    bl_options = {'REGISTER', 'UNDO'}
    unbind: bpy.props.BoolProperty(name="Unbind", default=False)

    @classmethod
    def poll(cls, context):
        reason = why_not(None)
        if reason.startswith("binding"):
            cls.poll_message_set(reason)
            return False
        if not [o for o in context.selected_objects if o.type == 'GREASEPENCIL']:
            cls.poll_message_set("Select Grease Pencil objects and, last, the mesh")
            return False
        return True

    def execute(self, context):
        gps = [o for o in context.selected_objects if o.type == 'GREASEPENCIL']
        try:
            for gp_obj in gps:
                if self.unbind:
                    unbind_drawing(gp_obj)
                else:
                    bind_drawing(gp_obj, chosen_meshes(context))
        except (ValueError, RuntimeError) as exc:
            self.report({'ERROR'}, str(exc))
            return {'CANCELLED'}
        return {'FINISHED'}


HANDLERS = (bpy.app.handlers.depsgraph_update_post, bpy.app.handlers.frame_change_post)


def register():
    bpy.utils.register_class(BDINTERP_OT_bind_drawing)
    for handlers in HANDLERS:
        handlers.append(on_update)


def unregister():
    for handlers in HANDLERS:
        if on_update in handlers:
            handlers.remove(on_update)
    bpy.utils.unregister_class(BDINTERP_OT_bind_drawing)
