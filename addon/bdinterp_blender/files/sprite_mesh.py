"""Mesh from Image: the mesh of an image plane (or any mesh whose material shows an image texture)
replaced by one made from the image's alpha (bdinterp.mesh_from_image), keeping the object's
transform, materials, size and place, with UVs onto the image. All objects are computed before any
is changed, so a failure changes none."""
from collections import Counter

import bpy

from ..core import load_core

# Work done, for the tests: 'meshed' images (calls of the core's mesher).
counters = Counter()

# Presets: (label, description, parameters); spacing_divisions: edges across the sprite's larger side.
PRESETS = {
    "RIGID": ("A rigid part", "Few triangles: a part that moves but hardly bends",
              dict(spacing_divisions=4, detail=1.5, min_angle=20.0)),
    "BENDS": ("A part that bends", "About twelve triangles across: arms, tails, hair",
              dict(spacing_divisions=12, detail=1.0, min_angle=25.0)),
    "FACE": ("A face", "Fine and even triangles for expressions",
             dict(spacing_divisions=24, detail=0.5, min_angle=28.0)),
}


def image_of(obj):
    """The first image an image-texture node of obj's materials shows (None if none)."""
    for slot in obj.material_slots:
        mat = slot.material
        if mat and mat.node_tree:  # (use_nodes: deprecated in 5.x, where materials always use nodes)
            for node in mat.node_tree.nodes:
                if node.type == 'TEX_IMAGE' and node.image is not None:
                    return node.image
    return None


def alpha_of(image):
    """float32 (h, w) alpha, row 0 the image's top (Blender stores the bottom row first)."""
    import numpy as np  # heavy: imported when used
    w, h = image.size
    if w == 0 or h == 0:
        raise ValueError("image %r has no pixels (is its file missing?)" % image.name)
    pixels = np.empty(w * h * 4, np.float32)
    image.pixels.foreach_get(pixels)
    return np.ascontiguousarray(pixels.reshape(h, w, 4)[::-1, :, 3])


def _plane_frame(obj):
    """The mesh's bounding box in local coordinates: its corners, the axes of the image's x and y
    (the two widest, in x, y, z order: an image plane lies in local XY) and of the plane's depth,
    and the depth (the mean)."""
    import numpy as np  # heavy: imported when used
    co = np.empty(len(obj.data.vertices) * 3, np.float64)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    lo, hi = co.min(0), co.max(0)
    flat = int(np.argmin(hi - lo))
    axes = [a for a in range(3) if a != flat] + [flat]
    return lo, hi, axes, co[:, axes[2]].mean()


def plan(obj, **params):
    """(vertices (n, 3) local, faces, uvs) of obj's new mesh; ValueError naming obj if impossible."""
    import numpy as np  # heavy: imported when used
    if obj.type != 'MESH' or len(obj.data.vertices) < 3:
        raise ValueError("%r is not a mesh showing an image" % obj.name)
    if obj.data.shape_keys is not None:
        raise ValueError("%r has shape keys: mesh it from its image before adding keys" % obj.name)
    image = image_of(obj)
    if image is None:
        raise ValueError("%r has no material with an image texture" % obj.name)
    bd = load_core()
    counters["meshed"] += 1
    try:
        mesh = bd.mesh_from_image(alpha_of(image), **params)
    except (bd.InvalidInputError, RuntimeError) as e:
        raise ValueError("%r (image %r): %s" % (obj.name, image.name, e)) from None
    lo, hi, axes, depth = _plane_frame(obj)
    local = np.empty((len(mesh.uvs), 3))
    local[:, axes[0]] = lo[axes[0]] + mesh.uvs[:, 0] * (hi[axes[0]] - lo[axes[0]])
    local[:, axes[1]] = lo[axes[1]] + mesh.uvs[:, 1] * (hi[axes[1]] - lo[axes[1]])
    local[:, axes[2]] = depth
    return local, mesh.faces, mesh.uvs


def fill(me, co, faces, uvs):
    """Mesh `me` (empty) made of vertices co (n, 3), triangles faces (m, 3) and per-vertex uvs
    (n, 2) in the layer 'UVMap'; the caller calls me.update() after its own additions."""
    import numpy as np  # heavy: imported when used
    me.from_pydata(co.tolist(), [], faces.tolist())
    layer = me.uv_layers.new(name="UVMap")
    layer.data.foreach_set("uv", uvs[faces.reshape(-1)].astype(np.float32).ravel())


def write(obj, local, faces, uvs):
    """Replaces obj's geometry in place (its materials, name and users kept), UVs onto the image."""
    obj.data.clear_geometry()
    fill(obj.data, local, faces, uvs)
    obj.data.update()


def mesh_from_image(objs, **params):
    """Every object of objs (one object or a list) meshed from its image's alpha; the keyword
    parameters are bdinterp.mesh_from_image's. Returns the triangle counts. ValueError (naming the
    object) before any change if one cannot be meshed."""
    objs = [objs] if isinstance(objs, bpy.types.Object) else list(objs)
    plans = [plan(obj, **params) for obj in objs]
    for obj, p in zip(objs, plans):
        write(obj, *p)
    return [len(p[1]) for p in plans]


def params_of(op, obj):
    """The operator's parameters as mesh_from_image's keywords: spacing 0 is the sprite's larger
    side over the preset's spacing_divisions (the core's own default for Custom)."""
    params = dict(threshold=op.threshold, spacing=op.spacing, detail=op.detail,
                  padding=op.padding, min_angle=op.min_angle)
    if op.spacing == 0 and op.preset in PRESETS:
        params["spacing_divisions"] = PRESETS[op.preset][2]["spacing_divisions"]
    return params


def spacing_zero(preset, obj):
    """What Spacing 0 means, in words: the preset's edges across the sprite (in pixels for obj's
    image), or automatic (Custom: the core's default)."""
    if preset not in PRESETS:
        return "0: automatic"
    divisions = PRESETS[preset][2]["spacing_divisions"]
    image = image_of(obj) if obj is not None and obj.type == 'MESH' else None
    size = " = %.0f px" % (max(image.size) / divisions) if image is not None else ""
    return "0: from the preset (%d edges across%s)" % (divisions, size)


_previews = {}   # the dialog's plans: request (preview_key) -> plan or the error's message


def preview_key(obj, params):
    """What plan(obj, **params) depends on, cheap to compare: the object, its mesh's vertices
    (their bounding box places the new mesh), its image (name, size; its pixels are taken as
    unchanged while a dialog is open) and the parameters."""
    image = image_of(obj) if obj is not None and obj.type == 'MESH' else None
    return (getattr(obj, "name", None), getattr(getattr(obj, "data", None), "name", None),
            len(obj.data.vertices) if image is not None else 0,
            (image.name, tuple(image.size)) if image is not None else None, tuple(sorted(params.items())))


def preview(obj, params):
    """plan(obj, **params), made once per request while the dialog is open (its draw() runs on
    every redraw); ValueError as plan's."""
    key = preview_key(obj, params)
    if key not in _previews:
        try:
            _previews[key] = plan(obj, **params)
        except (ValueError, AttributeError, RuntimeError) as e:
            _previews[key] = str(e)
    found = _previews[key]
    if isinstance(found, str):
        raise ValueError(found)
    return found


def _apply_preset(self, context):
    if self.preset in PRESETS:
        values = PRESETS[self.preset][2]
        self.detail, self.min_angle, self.spacing = values["detail"], values["min_angle"], 0.0


class BDINTERP_OT_mesh_from_image(bpy.types.Operator):
    """Replace the mesh of each selected image plane by a triangle mesh of its image's alpha that
    bends well (one undo step; nothing changes if one fails)"""
    bl_idname = "bdinterp.mesh_from_image"
    bl_label = "Mesh from Image"
    bl_options = {'REGISTER', 'UNDO'}

    preset: bpy.props.EnumProperty(
        name="Preset", items=[(k, v[0], v[1]) for k, v in PRESETS.items()] + [("CUSTOM", "Custom", "")],
        default="BENDS", update=_apply_preset)
    threshold: bpy.props.FloatProperty(name="Alpha threshold", default=0.5, min=0.001, max=1.0)
    spacing: bpy.props.FloatProperty(name="Spacing (px)", default=0.0, min=0.0,
                                     description="Longest edge in pixels; 0: from the preset")
    detail: bpy.props.FloatProperty(name="Detail (px)", default=1.0, min=0.0, max=16.0)
    padding: bpy.props.FloatProperty(name="Padding (px)", default=1.0, min=0.0, max=64.0)
    min_angle: bpy.props.FloatProperty(name="Smallest angle", default=25.0, min=1.0, max=30.0)

    @classmethod
    def poll(cls, context):
        return any(o.type == 'MESH' for o in context.selected_objects)

    def invoke(self, context, event):
        _previews.clear()  # the image or mesh may have changed since the last dialog
        return context.window_manager.invoke_props_dialog(self)

    def draw(self, context):
        obj = context.active_object
        for name in ("preset", "threshold", "spacing", "detail", "padding", "min_angle"):
            self.layout.prop(self, name)
            if name == "spacing" and self.spacing == 0:  # say what 0 means, not only "0.00"
                self.layout.label(text=spacing_zero(self.preset, obj), icon='INFO')
        try:  # the triangle count before applying (the active object's)
            count = len(preview(obj, params_of(self, obj))[1])
            self.layout.label(text="%s: %d triangles" % (obj.name, count))
        except ValueError as e:
            self.layout.label(text=str(e), icon='ERROR')

    def execute(self, context):
        objs = [o for o in context.selected_objects if o.type == 'MESH']
        try:  # the dialog's plans are reused (the redo panel's are made afresh)
            plans = [preview(o, params_of(self, o)) for o in objs]
        except ValueError as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        finally:
            _previews.clear()
        for o, p in zip(objs, plans):
            write(o, *p)
        self.report({'INFO'}, "Mesh from Image: %d objects, %d triangles"
                    % (len(objs), sum(len(p[1]) for p in plans)))
        return {'FINISHED'}


class BDINTERP_PT_sprite_mesh(bpy.types.Panel):
    """In the sidebar's bdinterp tab while the active object is a mesh showing an image, without
    shape keys yet (an image plane): the way to a mesh that bends."""
    bl_space_type, bl_region_type, bl_category = 'VIEW_3D', 'UI', "bdinterp"
    bl_label = "Mesh from Image"

    @classmethod
    def poll(cls, context):
        obj = context.object
        return (obj is not None and obj.type == 'MESH' and obj.data.shape_keys is None
                and image_of(obj) is not None)

    def draw(self, context):
        image = image_of(context.object)
        self.layout.label(text="%s: %d x %d px" % (image.name, *image.size), icon='IMAGE_DATA')
        self.layout.operator(BDINTERP_OT_mesh_from_image.bl_idname, icon='MOD_TRIANGULATE')


def _menu(self, context):
    self.layout.operator(BDINTERP_OT_mesh_from_image.bl_idname)


def register():
    bpy.utils.register_class(BDINTERP_OT_mesh_from_image)
    bpy.utils.register_class(BDINTERP_PT_sprite_mesh)
    bpy.types.VIEW3D_MT_object.append(_menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(_menu)
    bpy.utils.unregister_class(BDINTERP_PT_sprite_mesh)
    bpy.utils.unregister_class(BDINTERP_OT_mesh_from_image)
