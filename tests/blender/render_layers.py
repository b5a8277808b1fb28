"""Child script for test_layer_render.py: the example painting imported with the add-on's layered
import, rendered with EEVEE (needs a display: run under Xvfb) before a bake and after it, each
render compared with the painting's own mergedimage.png.

    xvfb-run ... blender --background --factory-startup --python render_layers.py -- OUT_DIR
Prints 'JSON:{...}': per render the fraction of pixels off (see differs) and its largest error,
and the joints the pose tears (none: the arm turns about the shoulder as one).

The render shows each layer's colour as it is (an emission shader of its image over transparency,
alpha blended like the imported material, view transform Standard, one sample, no pixel filter,
an orthographic camera with one pixel per canvas pixel), so that a pixel differs from the
painting only where another layer is drawn in front of it."""

import json
import math
import os
import sys
import zipfile

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PAINTING = os.path.join(ROOT, "examples", "sprites", "character.ora")
SCALE = 0.01
OFF = 0.1  # a pixel is off when a premultiplied channel or its alpha differs by more than this
POSE = "Pose"
# the pose: the right arm (the picture's left) raised about the shoulder, the forearm bent more
TURNS = {"upper_arm_r": 35.0, "forearm_r": 35.0}
SHOULDER = (150, 104)  # canvas pixels


def flat(mat):
    """The imported material's image shown as its colour (emission) over transparency."""
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = next(n for n in nodes if n.type == 'TEX_IMAGE')
    tex.interpolation = 'Closest'
    bsdf = next(n for n in nodes if n.type == 'BSDF_PRINCIPLED')
    alpha = bsdf.inputs["Alpha"].links[0].from_socket
    out = next(n for n in nodes if n.type == 'OUTPUT_MATERIAL')
    mix, clear, glow = (nodes.new(t) for t in ("ShaderNodeMixShader", "ShaderNodeBsdfTransparent",
                                               "ShaderNodeEmission"))
    links.new(tex.outputs["Color"], glow.inputs["Color"])
    links.new(alpha, mix.inputs["Fac"])
    links.new(clear.outputs[0], mix.inputs[1])
    links.new(glow.outputs[0], mix.inputs[2])
    links.new(mix.outputs[0], out.inputs["Surface"])


def camera(scene, width, height):
    """An orthographic camera looking at the canvas (XZ plane) from the front, pixel for pixel."""
    data = bpy.data.cameras.new("Canvas")
    data.type, data.ortho_scale = 'ORTHO', max(width, height) * SCALE
    cam = bpy.data.objects.new("Canvas", data)
    scene.collection.objects.link(cam)
    cam.location = (width * SCALE / 2, -10.0, -height * SCALE / 2)
    cam.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.camera = cam
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.film_transparent, r.filter_size = True, 0.0
    r.image_settings.file_format, r.image_settings.color_mode = 'PNG', 'RGBA'
    engines = {e.identifier for e in bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items}
    r.engine = 'BLENDER_EEVEE_NEXT' if 'BLENDER_EEVEE_NEXT' in engines else 'BLENDER_EEVEE'
    scene.eevee.taa_render_samples = 1
    scene.view_settings.view_transform, scene.view_settings.look = 'Standard', 'None'


def pixels(path):
    """float (h, w, 4) of a PNG, row 0 at the top, straight alpha."""
    image = bpy.data.images.load(path, check_existing=False)
    w, h = image.size
    px = np.empty(w * h * 4, np.float32)
    image.pixels.foreach_get(px)
    bpy.data.images.remove(image)
    return px.reshape(h, w, 4)[::-1]


def differs(render, painting):
    """(fraction of pixels off, largest difference) of premultiplied colour and alpha."""
    def premultiplied(px):
        return np.concatenate([px[..., :3] * px[..., 3:], px[..., 3:]], axis=-1)
    d = np.abs(premultiplied(render) - premultiplied(painting)).max(axis=-1)
    return float((d > OFF).mean()), float(d.max())


def render(scene, out, name, painting):
    scene.render.filepath = os.path.join(out, name + ".png")
    bpy.ops.render.render(write_still=True)
    fraction, largest = differs(pixels(scene.render.filepath), painting)
    return {"off": fraction, "largest": largest, "png": scene.render.filepath}


def rotate(co, centre, degrees):
    """co (n, 3) in world space turned in the XZ plane about centre (canvas pixels)."""
    c = np.array([centre[0] * SCALE, 0.0, -centre[1] * SCALE])
    a = math.radians(degrees)
    x, z = co[:, 0] - c[0], co[:, 2] - c[2]
    out = co.copy()
    out[:, 0], out[:, 2] = c[0] + math.cos(a) * x - math.sin(a) * z, c[2] + math.sin(a) * x + math.cos(a) * z
    return out


def pose(bdi, objs):
    """Add Pose (the key POSE on every piece); the right arm's pieces turned about the shoulder."""
    assert bdi.add_pose(objs) == POSE
    for obj in objs:
        kb = obj.data.shape_keys.key_blocks[POSE]
        if obj.name in TURNS:
            m = np.array(obj.matrix_world)
            co = np.array([v.co for v in obj.data.vertices], dtype=np.float64)
            world = rotate(co @ m[:3, :3].T + m[:3, 3], SHOULDER, TURNS[obj.name])
            local = np.linalg.solve(m[:3, :3], (world - m[:3, 3]).T).T
            kb.data.foreach_set("co", local.astype(np.float32).ravel())


def main(out):
    sys.path.insert(0, os.path.join(ROOT, "examples", "blender"))
    import addon_loader
    bdi = addon_loader.enable()
    result = {}
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    objs = bdi.import_layered(PAINTING, scale=SCALE)
    for mat in {s.material for o in objs for s in o.material_slots}:
        flat(mat)
    with zipfile.ZipFile(PAINTING) as z:
        z.extract("mergedimage.png", out)
    painting = pixels(os.path.join(out, "mergedimage.png"))
    camera(scene, painting.shape[1], painting.shape[0])
    result["before"] = render(scene, out, "before", painting)
    pose(bdi, objs)
    torso = bpy.data.objects["torso"]
    result["torn"] = bdi.torn_joints(objs, POSE)
    baked = bdi.bake([torso] + [o for o in objs if o != torso], POSE, count=3)
    result["slider"], result["slider_owner"] = baked.slider, torso.name
    for value in (0.0, 1.0):
        torso[baked.slider] = value
        torso.update_tag()
        bpy.context.view_layer.update()
        result["after_%g" % value] = render(scene, out, "after_%g" % value, painting)
    print("JSON:" + json.dumps(result), flush=True)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1])
