"""A layered painting in one step: OpenRaster (.ora: a zip with stack.xml and a PNG per layer, as
Krita, GIMP and MyPaint write it) imported as cut-out pieces: each visible layer (groups flattened,
hidden layers and groups skipped) becomes a mesh from its alpha (bdinterp.mesh_from_image),
textured with its image, placed where the painting has it in Blender's front (XZ) plane: the
canvas's x to +x, its y (downwards) to -z, one pixel = `scale` units, a layer drawn higher nearer
the front view (smaller y). Everything is read and meshed before anything is created."""
import os
import tempfile
import xml.etree.ElementTree as ET
import zipfile

import bpy

from .core import load_core
from . import sprite_mesh

DEPTH = 1e-3  # Blender units between consecutive layers, in the draw order


def ora_layers(path):
    """(canvas (w, h), [(name, src, x, y)] bottom layer first) of an OpenRaster file."""
    try:
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("stack.xml"))
    except (OSError, zipfile.BadZipFile, KeyError, ET.ParseError) as e:
        raise ValueError("%r is not an OpenRaster file (%s)" % (os.fspath(path), e)) from None
    layers = []

    def walk(stack, dx, dy):  # a stack's first child is drawn on top
        for node in stack:
            if node.get("visibility", "visible") == "hidden":
                continue
            x, y = dx + int(float(node.get("x", 0))), dy + int(float(node.get("y", 0)))
            if node.tag == "stack":
                walk(node, x, y)
            elif node.tag == "layer":
                layers.append((node.get("name", node.get("src")), node.get("src"), x, y))
    top = root.find("stack")
    walk(top if top is not None else [], 0, 0)
    return (int(root.get("w")), int(root.get("h"))), layers[::-1]


def _material(name, image):
    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes = mat.node_tree.nodes
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    bsdf = next(n for n in nodes if n.type == 'BSDF_PRINCIPLED')
    mat.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    mat.node_tree.links.new(tex.outputs["Alpha"], bsdf.inputs["Alpha"])
    if hasattr(mat, "surface_render_method"):  # 4.2+
        mat.surface_render_method = 'BLENDED'
    else:
        mat.blend_method = 'BLEND'
    return mat


def _plans(path, scale, params):
    """Per visible layer: (name, image, vertices (n, 3), faces, uvs); images loaded and packed."""
    import numpy as np
    bd = load_core()
    (_, _), layers = ora_layers(path)
    if not layers:
        raise ValueError("%r has no visible layer" % os.fspath(path))
    plans, images = [], []
    try:
        with zipfile.ZipFile(path) as z, tempfile.TemporaryDirectory() as tmp:
            for depth, (name, src, x, y) in enumerate(layers):
                try:
                    data = z.read(src)
                except KeyError:
                    raise ValueError("%r: layer %r's image %r is missing" % (os.fspath(path), name, src)) from None
                file = os.path.join(tmp, "%d.png" % depth)
                with open(file, "wb") as f:
                    f.write(data)
                image = bpy.data.images.load(file)
                images.append(image)
                image.pack()
                image.name = name
                try:
                    mesh = bd.mesh_from_image(sprite_mesh.alpha_of(image), **params)
                except (bd.InvalidInputError, RuntimeError) as e:
                    raise ValueError("%r: layer %r: %s" % (os.fspath(path), name, e)) from None
                h = image.size[1]
                V = mesh.vertices
                co = np.c_[(x + V[:, 0]) * scale, np.full(len(V), -depth * DEPTH), -(y + h - V[:, 1]) * scale]
                plans.append((name, image, co, mesh.faces, mesh.uvs))
    except BaseException:
        for image in images:
            bpy.data.images.remove(image)
        raise
    return plans


def _object(name, parts):
    """One mesh object of parts [(material, co, faces, uvs)], a material slot each."""
    import numpy as np
    co = np.concatenate([p[1] for p in parts])
    offsets = np.cumsum([0] + [len(p[1]) for p in parts])
    faces = np.concatenate([p[2] + o for p, o in zip(parts, offsets)])
    uvs = np.concatenate([p[3] for p in parts])
    me = bpy.data.meshes.new(name)
    me.from_pydata(co.tolist(), [], faces.tolist())
    layer = me.uv_layers.new(name="UVMap")
    layer.data.foreach_set("uv", uvs[faces.reshape(-1)].astype(np.float32).ravel())
    for p in parts:
        me.materials.append(p[0])
    me.polygons.foreach_set("material_index", np.repeat(np.arange(len(parts)), [len(p[2]) for p in parts]))
    me.update()
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def import_layered(path, *, one_object=False, scale=0.01, **params):
    """The painting's visible layers as meshes (one object per layer, or one layered object);
    returns the objects, selected. ValueError naming the file or layer, with nothing imported."""
    plans = _plans(path, scale, params)
    parts = [(_material(name, image), co, faces, uvs) for name, image, co, faces, uvs in plans]
    if one_object:
        objs = [_object(os.path.splitext(os.path.basename(os.fspath(path)))[0], parts)]
    else:
        objs = [_object(plan[0], [part]) for plan, part in zip(plans, parts)]
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[-1]
    return objs


class BDINTERP_OT_import_layered(bpy.types.Operator):
    """Import a layered painting (OpenRaster .ora) as cut-out pieces meshed from each layer's alpha"""
    bl_idname = "bdinterp.import_layered"
    bl_label = "Layered painting (bdinterp)"
    bl_options = {'REGISTER', 'UNDO'}

    filepath: bpy.props.StringProperty(subtype='FILE_PATH')
    filter_glob: bpy.props.StringProperty(default="*.ora", options={'HIDDEN'})
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
