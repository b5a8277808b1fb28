"""Grease Pencil drawings that ride on a bdinterp mesh or character (Blender 4.3+, Grease Pencil v3).

bind_drawing stores, per stroke point, its rest position and radius and the triangle of the
mesh's rest shape (reference key, world space) that holds it (a character of several objects:
their triangles one object after the other, so a point goes to whichever piece holds it; found
with a grid of buckets, locate.py): barycentric coordinates in the mesh's plane (a point outside
the mesh: the nearby triangle it is least outside of, by that triangle's affine map), the height
above the plane and the triangle's rest area.  On every change that moves a bound mesh
(changes.py: slider, live mode, baked keys, render, the frame) the points are written from the
evaluated mesh, the radius scaled with the triangle's scale; unbind_drawing writes the rest
positions and radii back.  Everything is stored in point attributes of the drawings and a
property of the object, so a saved file keeps working; what an update needs is read from them
once and kept (Binding).  A bound mesh whose faces change (edited in Edit Mode, a modifier that
adds vertices) cannot carry the points: they are unbound, with a warning saying why.
"""

import zlib
from collections import Counter

import bpy
from bpy.app.handlers import persistent

from .. import changes
from ..keys.character import members, to_local, to_world
from ..shapes.mesh_io import BakeError, triangles
from .locate import locate_2d, plane_basis

BOUND = "bdi_bound_to"        # custom property of the Grease Pencil object: the mesh objects' names
TOPOLOGY = "bdi_bound_faces"  # ... and the faces they had when bound ('vertices:loops:crc' each)
WARNING = "bdi_bind_warning"  # ... and why it was unbound, when the handler had to
REST, RADIUS, TRI, BARY, HEIGHT, AREA = ("bdi_rest_position", "bdi_rest_radius", "bdi_tri",
                                         "bdi_bary", "bdi_height", "bdi_rest_area")
ATTRS = ((REST, 'FLOAT_VECTOR'), (RADIUS, 'FLOAT'), (TRI, 'INT'), (BARY, 'FLOAT_VECTOR'),
         (HEIGHT, 'FLOAT'), (AREA, 'FLOAT'))
DEFAULT_RADIUS = 0.01  # Grease Pencil v3's radius of a point without a radius attribute

# Work done, for the tests: 'located' points, 'loaded' Bindings read from the attributes.
counters = Counter()


def why_not(gp_obj):
    """'' if gp_obj's strokes can be bound, else why not."""
    if bpy.app.version < (4, 3, 0):
        return "binding drawings needs Blender 4.3 or later (Grease Pencil v3)"
    if gp_obj is None or gp_obj.type != 'GREASEPENCIL':
        return "%s is not a Grease Pencil object" % getattr(gp_obj, "name", "No object")
    return ""


def drawings(gp_obj):
    return [f.drawing for layer in gp_obj.data.layers for f in layer.frames if f.drawing is not None]


def read(drawing, name, width, default=None):
    """The point attribute `name` (width 1 or 3) of drawing; `default` for every point when the
    drawing has none (Grease Pencil v3 stores radius and opacity only once they are set)."""
    import numpy as np
    attr = drawing.attributes.get(name)
    if attr is None and default is not None:
        return np.full(len(drawing.attributes["position"].data), default, dtype=np.float32)
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


def topology(obj):
    """'vertices:loops:crc32 of the loops' vertices' of obj's mesh: changes when its faces do."""
    import numpy as np
    loops = np.empty(len(obj.data.loops), dtype=np.int32)
    obj.data.loops.foreach_get("vertex_index", loops)
    return "%d:%d:%08x" % (len(obj.data.vertices), len(loops), zlib.crc32(loops.tobytes()))


def mesh_faces(mesh_objs):
    """(triangles (m, 3) of the objects one after the other, their vertex counts)."""
    import numpy as np
    tris, offset, sizes = [], 0, []
    for obj in mesh_objs:
        tris.append(triangles(obj.data)[0] + offset)
        sizes.append(len(obj.data.vertices))
        offset += sizes[-1]
    return np.concatenate(tris), sizes


def rest_mesh(mesh_objs):
    """(world vertices (n, 3) of the objects' reference keys one after the other, triangles)."""
    import numpy as np
    from ..shapes.mesh_io import read_co
    faces, _ = mesh_faces(mesh_objs)
    return np.concatenate([to_world(o, read_co(o.data.shape_keys.reference_key)) for o in mesh_objs]), faces


def shown_mesh(mesh_objs, depsgraph):
    """(n, 3) world vertices of the objects as evaluated, one after the other; None if one of them
    shows another number of vertices than its mesh has (a modifier that adds some)."""
    import numpy as np
    points = []
    for obj in mesh_objs:
        ev = obj.evaluated_get(depsgraph)
        if len(ev.data.vertices) != len(obj.data.vertices):
            return None
        co = np.empty(len(ev.data.vertices) * 3, dtype=np.float32)
        ev.data.vertices.foreach_get("co", co)
        points.append(to_world(ev, co.reshape(-1, 3).astype(np.float64)))
    return np.concatenate(points)


def bound_meshes(gp_obj):
    """The mesh objects gp_obj is bound to (in order); None if one of them is gone."""
    names = gp_obj.get(BOUND, [])
    names = [names] if isinstance(names, str) else list(names)
    objs = [bpy.data.objects.get(name) for name in names]
    return objs if objs and all(o is not None and o.type == 'MESH' for o in objs) else None


def locate(P, X, faces):
    """(triangle (p,), barycentric (p, 3), height (p,)) of world points P on the mesh X."""
    import numpy as np
    C = X[faces]
    normal = np.cross(C[:, 1] - C[:, 0], C[:, 2] - C[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    basis = plane_basis(normal)
    tri, bary = locate_2d(P @ basis, C @ basis)
    height = np.einsum("pi,pi->p", P - np.einsum("pi,pij->pj", bary, C[tri]), normal[tri])
    counters["located"] += len(P)
    return tri, bary, height


def place(C, bary, height, rest_area):
    """(world positions (p, 3), radius scale (p,)) of bound points whose triangles' corners are
    C (p, 3, 3) in the mesh as shown."""
    import numpy as np
    n = np.cross(C[:, 1] - C[:, 0], C[:, 2] - C[:, 0])
    area = np.sqrt(np.einsum("pi,pi->p", n, n))
    lift = height / np.maximum(area, 1e-300)
    pos = np.einsum("pi,pij->pj", bary, C) + lift[:, None] * n
    return pos, np.sqrt(area / np.maximum(rest_area, 1e-300))


def bind_drawing(gp_obj, mesh_obj):
    """Bind every stroke point of gp_obj (all layers and frames) to the rest shape of mesh_obj,
    a mesh object or a list of them (a character: each point to the nearest triangle of any of
    them); from then on (at once) the strokes follow wherever the mesh is shown.  Returns the
    number of points."""
    import numpy as np
    reason = why_not(gp_obj)
    if reason:
        raise BakeError(reason)
    objs = list(mesh_obj) if isinstance(mesh_obj, (list, tuple)) else [mesh_obj]
    for obj in objs or [None]:
        if obj is None or obj.type != 'MESH' or obj.data.shape_keys is None:
            raise BakeError("%s is not a mesh with shape keys" % getattr(obj, "name", "No object"))
    if BOUND in gp_obj:
        unbind_drawing(gp_obj)
    X, faces = rest_mesh(objs)
    located = []
    for d in drawings(gp_obj):  # all computed before anything is written
        P = to_world(gp_obj, read(d, "position", 3).astype(float))
        located.append((d, P, locate(P, X, faces) if len(P) else None))
    count = 0
    for d, P, found in located:
        if found is None:
            continue
        tri, bary, height = found
        C = X[faces[tri]]
        area = np.linalg.norm(np.cross(C[:, 1] - C[:, 0], C[:, 2] - C[:, 0]), axis=1)
        write(d, REST, 'FLOAT_VECTOR', read(d, "position", 3))
        write(d, RADIUS, 'FLOAT', read(d, "radius", 1, DEFAULT_RADIUS))
        write(d, TRI, 'INT', tri)
        write(d, BARY, 'FLOAT_VECTOR', bary)
        write(d, HEIGHT, 'FLOAT', height)
        write(d, AREA, 'FLOAT', area)
        count += len(P)
    gp_obj[BOUND] = [o.name for o in objs]
    gp_obj[TOPOLOGY] = [topology(o) for o in objs]
    if WARNING in gp_obj:
        del gp_obj[WARNING]
    _bindings.pop(gp_obj.name, None)
    update(gp_obj, bpy.context.evaluated_depsgraph_get())  # on the mesh as shown now
    return count


def unbind_drawing(gp_obj):
    """Put every point back where it was drawn (position and radius) and forget the binding."""
    for d in drawings(gp_obj):
        if d.attributes.get(REST) is None:
            continue
        write(d, "position", 'FLOAT_VECTOR', read(d, REST, 3))
        write(d, "radius", 'FLOAT', read(d, RADIUS, 1))
        for name, _ in ATTRS:
            if d.attributes.get(name) is not None:
                d.attributes.remove(d.attributes[name])
    for name in (BOUND, TOPOLOGY):
        if name in gp_obj:
            del gp_obj[name]
    _bindings.pop(gp_obj.name, None)
    gp_obj.data.update_tag()


class Binding:
    """What updating one bound object needs, read once from its attributes: the meshes' names,
    their triangles, and per drawing (the drawing, its points' triangles (p, 3) as vertex indices,
    barycentric coordinates, heights, rest areas and radii)."""

    def __init__(self, gp_obj, objs):
        import numpy as np
        self.names = [o.name for o in objs]
        faces, _ = mesh_faces(objs)
        self.drawings = []
        for d in drawings(gp_obj):
            if d.attributes.get(REST) is None:
                continue
            tri = read(d, TRI, 1).astype(np.int64)
            self.drawings.append((d, faces[tri], read(d, BARY, 3).astype(float),
                                  read(d, HEIGHT, 1).astype(float), read(d, AREA, 1).astype(float),
                                  read(d, RADIUS, 1)))
        self.pointers = [d.as_pointer() for d in drawings(gp_obj)]
        counters["loaded"] += 1


_bindings = {}   # Grease Pencil object name -> Binding
_edited = set()  # Grease Pencil objects whose meshes were seen in Edit Mode: faces compared next


def binding(gp_obj, objs):
    """gp_obj's Binding (read again if its drawings or meshes are not those it was read from)."""
    found = _bindings.get(gp_obj.name)
    if found is None or found.names != [o.name for o in objs] \
            or found.pointers != [d.as_pointer() for d in drawings(gp_obj)]:
        found = _bindings[gp_obj.name] = Binding(gp_obj, objs)
    return found


def changed_faces(gp_obj, objs, full=True):
    """Why the bound meshes cannot carry gp_obj's points any more ('' if they can): their faces
    are not those they were bound with (full; else only their vertex and loop counts checked)."""
    stored = list(gp_obj.get(TOPOLOGY, []))
    if len(stored) != len(objs):
        return "it was bound by another version of the add-on"
    for obj, before in zip(objs, stored):
        now = topology(obj) if full else "%d:%d:" % (len(obj.data.vertices), len(obj.data.loops))
        if not before.startswith(now):
            return "the faces of %s changed since the drawing was bound" % obj.name
    return ""


def update(gp_obj, depsgraph):
    """Write gp_obj's bound points from its meshes as evaluated; False if it is not bound (any
    more): one of its meshes is gone, or its faces changed (then unbound, with a warning).  The
    faces themselves are compared (a loop per face corner read: ~10 ms at 30k corners) after Edit
    Mode and when the binding is read; else only the numbers of vertices and corners."""
    objs = bound_meshes(gp_obj)
    if objs is None:
        return False
    if any(o.mode == 'EDIT' for o in objs):  # its faces are known again when Edit Mode ends
        _edited.add(gp_obj.name)
        return True
    full = gp_obj.name in _edited or gp_obj.name not in _bindings
    _edited.discard(gp_obj.name)
    reason = changed_faces(gp_obj, objs, full)
    X = shown_mesh(objs, depsgraph) if not reason else None
    if X is None:
        warn_unbound(gp_obj, reason or "a modifier of one of %s adds or removes vertices"
                     % ", ".join(o.name for o in objs))
        return False
    for d, tri, bary, height, area, radius in binding(gp_obj, objs).drawings:
        pos, scale = place(X[tri], bary, height, area)
        write(d, "position", 'FLOAT_VECTOR', to_local(gp_obj, pos))
        write(d, "radius", 'FLOAT', radius * scale)
    gp_obj.data.update_tag()
    return True


def warn_unbound(gp_obj, reason):
    """Unbind gp_obj (its points back where they were drawn) and say why, once."""
    message = "bdinterp: %s was unbound: %s (bind it again to follow the mesh)" % (gp_obj.name, reason)
    unbind_drawing(gp_obj)
    gp_obj[WARNING] = message
    print(message)


def on_changes(scene, depsgraph, changed):
    """Every update (changes.py): the bound drawings whose meshes (or themselves) moved or changed
    shape follow them; their own writes (a Grease Pencil update) change nothing here."""
    for obj in scene.objects:
        if obj.type != 'GREASEPENCIL' or BOUND not in obj:
            continue
        names = set(obj.get(BOUND, []))
        if changed.frame or obj.name in changed.moved or names & (changed.moved | changed.shaped):
            try:
                update(obj, depsgraph)
            except Exception as exc:  # noqa: BLE001 -- unbound once, never an error on every update
                warn_unbound(obj, "%s: %s" % (type(exc).__name__, exc))


@persistent
def forget(*_args):
    """After undo or loading a file the drawings are other objects: read them again."""
    _bindings.clear()
    _edited.clear()


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


HANDLERS = (bpy.app.handlers.undo_post, bpy.app.handlers.redo_post, bpy.app.handlers.load_post)


def register():
    bpy.utils.register_class(BDINTERP_OT_bind_drawing)
    for handlers in HANDLERS:
        handlers.append(forget)
    changes.subscribe(1, on_changes)


def unregister():
    changes.unsubscribe(on_changes)
    for handlers in HANDLERS:
        if forget in handlers:
            handlers.remove(forget)
    forget()
    bpy.utils.unregister_class(BDINTERP_OT_bind_drawing)
