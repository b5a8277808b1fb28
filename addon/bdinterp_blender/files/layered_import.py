"""A layered painting in one step: the visible layers of an OpenRaster file or of COA Tools' JSON
export (painting_files) imported as cut-out pieces: each layer becomes a mesh from its alpha
(bdinterp.mesh_from_image; a sprite sheet's frame for several tiles), textured with its image
(alpha blended, times the layer's opacity), placed where the painting has it in Blender's front
(XZ) plane: the canvas's x to +x, its y (downwards) to -z, one pixel = `scale` units, the canvas's
top-left corner at the world origin, a layer drawn higher nearer the front view (smaller y).
Each layer object's origin lies at its own depth: renderers sort alpha-blended objects by their
origins, so the painting's order holds in every view and render (also once a bake's drivers change
the order in which objects are evaluated); in the picture's plane it lies where the piece turns
(pivots.pivots: its joint with the piece it hangs from, else its middle). Everything is read and
meshed before any object is created."""
import os
import tempfile

import bpy

from ..core import load_core
from .painting_files import read_painting
from . import sprite_mesh
from ..shapes import pivots

DEPTH = 1e-3  # Blender units between consecutive layers, in the draw order


def _material(name, image, opacity):
    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    bsdf = next(n for n in nodes if n.type == 'BSDF_PRINCIPLED')
    links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    alpha = tex.outputs["Alpha"]
    if opacity < 1.0:  # the layer's opacity scales its image's alpha
        times = nodes.new("ShaderNodeMath")
        times.operation, times.inputs[1].default_value = 'MULTIPLY', opacity
        links.new(alpha, times.inputs[0])
        alpha = times.outputs[0]
    links.new(alpha, bsdf.inputs["Alpha"])
    if hasattr(mat, "surface_render_method"):  # 4.2+
        mat.surface_render_method = 'BLENDED'
    else:
        mat.blend_method = 'BLEND'
    return mat


def _load(layer, tmp, index):
    """The layer's image, packed into the file; ValueError naming it if Blender cannot read it."""
    file = layer.file
    if file is None:
        file = os.path.join(tmp, "%d.png" % index)
        with open(file, "wb") as f:
            f.write(layer.data)
    try:
        image = bpy.data.images.load(file, check_existing=False)
    except RuntimeError as e:
        raise ValueError("layer %r: %s" % (layer.name, e)) from None
    image.name = layer.name
    if image.size[0] == 0 or image.size[1] == 0:
        bpy.data.images.remove(image)
        raise ValueError("layer %r: %r is not an image Blender can read" % (layer.name, file))
    image.pack()
    return image


def _piece(bd, layer, image, params):
    """(vertices (n, 3) at depth 0, faces, uvs, mask) of the layer's image (its frame of a sprite
    sheet); mask: (x, y, opaque pixels (h, w) bool) in the canvas, for pivots.pivots."""
    import numpy as np
    columns, rows, frame = layer.tiles
    w, h = image.size
    tw, th = w // columns, h // rows
    if tw < 2 or th < 2:
        raise ValueError("layer %r: %d x %d tiles of a %d x %d image are too small"
                         % (layer.name, columns, rows, w, h))
    left, top = (frame % columns) * tw, (frame // columns) * th
    alpha = sprite_mesh.alpha_of(image)[top:top + th, left:left + tw]
    try:
        mesh = bd.mesh_from_image(np.ascontiguousarray(alpha), **params)
    except (bd.InvalidInputError, RuntimeError) as e:
        raise ValueError("layer %r: %s" % (layer.name, e)) from None
    V = mesh.vertices  # pixels in the frame, y up from its bottom
    co = np.c_[(layer.x + V[:, 0]), np.zeros(len(V)), -(layer.y + th - V[:, 1])]
    uvs = (V + [left, h - top - th]) / [w, h]
    mask = alpha >= params.get("threshold", 0.5)
    return co, mesh.faces, uvs, (int(round(layer.x)), int(round(layer.y)), mask)


def _plans(path, scale, params):
    """Per visible layer, bottom first: (name, image, opacity, vertices (n, 3), faces, uvs, pivot
    (3,)), all in world coordinates (pivots.pivots: where the piece joins its parent, or its
    middle)."""
    bd = load_core()
    layers = read_painting(path)
    if not layers:
        raise ValueError("%r has no visible layer" % os.fspath(path))
    plans, images, masks = [], [], []
    try:
        with tempfile.TemporaryDirectory() as tmp:
            for depth, layer in enumerate(layers):
                images.append(_load(layer, tmp, depth))
                co, faces, uvs, mask = _piece(bd, layer, images[-1], params)
                co *= scale
                co[:, 1] = -depth * DEPTH
                plans.append((layer.name, images[-1], layer.opacity, co, faces, uvs))
                masks.append(mask)
            points = pivots.pivots(masks)[1]
    except BaseException as e:
        for image in images:
            bpy.data.images.remove(image)
        if isinstance(e, ValueError):  # a layer's error, said with the file's name
            raise ValueError("%r: %s" % (os.fspath(path), e)) from None
        raise
    return [plan + ((x * scale, -depth * DEPTH, -y * scale),)
            for depth, (plan, (x, y)) in enumerate(zip(plans, points))]


def _object(name, parts, origin=(0.0, 0.0, 0.0)):
    """One mesh object of parts [(material, co, faces, uvs)] (world coordinates), a material slot
    each, its origin at `origin` (world coordinates)."""
    import numpy as np
    origin = np.asarray(origin, dtype=np.float64)
    co = np.concatenate([p[1] for p in parts]) - origin
    offsets = np.cumsum([0] + [len(p[1]) for p in parts])
    faces = np.concatenate([p[2] + o for p, o in zip(parts, offsets)])
    uvs = np.concatenate([p[3] for p in parts])
    me = bpy.data.meshes.new(name)
    sprite_mesh.fill(me, co, faces, uvs)
    for p in parts:
        me.materials.append(p[0])
    me.polygons.foreach_set("material_index", np.repeat(np.arange(len(parts)), [len(p[2]) for p in parts]))
    me.update()
    obj = bpy.data.objects.new(name, me)
    obj.location = origin.tolist()
    bpy.context.scene.collection.objects.link(obj)
    return obj


def import_layered(path, *, one_object=False, scale=0.01, **params):
    """The painting's visible layers as meshes (one object per layer, or one layered object);
    returns the objects, selected. ValueError naming the file or layer, with nothing imported."""
    plans = _plans(path, scale, params)
    parts = [(_material(name, image, opacity), co, faces, uvs)
             for name, image, opacity, co, faces, uvs, _ in plans]
    if one_object:
        objs = [_object(os.path.splitext(os.path.basename(os.fspath(path)))[0], parts)]
    else:
        objs = [_object(plan[0], [part], plan[-1]) for plan, part in zip(plans, parts)]
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[-1]
    bpy.context.view_layer.update()  # the objects' matrices, for what reads them next (a bake)
    return objs


class BDINTERP_OT_import_layered(bpy.types.Operator):
    """Import a layered painting (OpenRaster .ora, or COA Tools' .json export) as cut-out pieces
    meshed from each layer's alpha"""
    bl_idname = "bdinterp.import_layered"
    bl_label = "Layered painting (bdinterp)"
    bl_options = {'REGISTER', 'UNDO'}

    filepath: bpy.props.StringProperty(subtype='FILE_PATH')
    filter_glob: bpy.props.StringProperty(default="*.ora;*.json", options={'HIDDEN'})
    one_object: bpy.props.BoolProperty(name="One object", default=False)
    scale: bpy.props.FloatProperty(name="Scale (units per pixel)", default=0.01, min=1e-6)

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {'RUNNING_MODAL'}

    def execute(self, context):
        try:
            objs = import_layered(self.filepath, one_object=self.one_object, scale=self.scale)
        except (ValueError, RuntimeError) as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        self.report({'INFO'}, "Imported %d objects" % len(objs))
        return {'FINISHED'}


def _menu(self, context):
    self.layout.operator(BDINTERP_OT_import_layered.bl_idname, text="Layered painting (bdinterp)")


def register():
    bpy.utils.register_class(BDINTERP_OT_import_layered)
    bpy.types.TOPBAR_MT_file_import.append(_menu)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_menu)
    bpy.utils.unregister_class(BDINTERP_OT_import_layered)
