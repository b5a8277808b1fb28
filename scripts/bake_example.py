"""Bake an example into out/example.blend and render pictures of it (run inside Blender).

    blender --background --factory-startup --python-exit-code 1 \
        --python scripts/bake_example.py -- [--example character] [--count 4] [--out out] [--core DIR]

Loads examples/<example>/source.obj + target.obj (made by examples/make_examples.py), makes a
mesh with shape keys 'Basis' and 'Pose', bakes bounded-distortion in-betweens with the add-on's scripting API, keyframes the playback slider over frames 1-24,
saves out/example.blend and renders out/example_<NN>.png (each state, coloured by conformal
distortion) and out/example_strip.png (all of them side by side, the README picture).
With --core DIR (`make demo`: python/, where `make build` puts the compiled module) it runs this
checkout's addon/ on the bdinterp package in DIR, ahead of any installed copy; without it, the
installed add-on if importable, else addon/ (then bdinterp must be importable by Blender's Python,
e.g. after `pip install .`).
"""

import argparse
import importlib
import os
import sys

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def import_addon(core=None):
    if core:
        sys.path[:0] = [os.path.abspath(core), os.path.join(ROOT, "addon")]
    try:
        import bdinterp_blender
    except ImportError:
        sys.path.insert(0, os.path.join(ROOT, "addon"))
        import bdinterp_blender
    return bdinterp_blender


def example_shapes(addon, name):
    """(source (n,3), target (n,3), faces) of examples/<name>, read with bdinterp's own OBJ reader."""
    folder = os.path.join(ROOT, "examples", name)
    io = importlib.import_module(addon.load_core().__name__ + ".io")
    src, tgt, faces = io.read_pair(os.path.join(folder, "source.obj"), os.path.join(folder, "target.obj"))
    pad = [np.c_[X, np.zeros(len(X))] if X.shape[1] == 2 else X for X in (src, tgt)]
    return pad[0], pad[1], faces.tolist()


def make_object(src, tgt, faces):
    bpy.ops.wm.read_homefile(use_empty=True)
    me = bpy.data.meshes.new("Example")
    me.from_pydata(src.tolist(), [], faces)
    obj = bpy.data.objects.new("Example", me)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.shape_key_add(name="Basis", from_mix=False)
    obj.shape_key_add(name="Pose", from_mix=False).data.foreach_set("co", tgt.astype(np.float32).ravel())
    return obj


def setup_render(shapes, resolution):
    """Orthographic top view framing every state; Workbench, flat, attribute colours."""
    lo = np.min([s.min(axis=0) for s in shapes], axis=0)
    hi = np.max([s.max(axis=0) for s in shapes], axis=0)
    scene = bpy.context.scene
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.data.type = 'ORTHO'
    cam.data.ortho_scale = float(max(hi[0] - lo[0], hi[1] - lo[1])) * 1.1
    cam.location = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, 10.0)
    r = scene.render
    r.engine = 'BLENDER_WORKBENCH'
    r.resolution_x = r.resolution_y = resolution
    r.resolution_percentage = 100
    r.image_settings.file_format = 'PNG'
    scene.display.shading.light = 'FLAT'
    scene.display.shading.show_object_outline = False
    scene.view_settings.view_transform = 'Standard'
    world = bpy.data.worlds.new("World")
    world.color = (1.0, 1.0, 1.0)
    scene.world = world


def render_to(path):
    bpy.context.scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    px = np.empty(len(img.pixels), dtype=np.float32)
    img.pixels.foreach_get(px)
    return px.reshape(img.size[1], img.size[0], 4)


def save_strip(tiles, path):
    strip = np.concatenate(tiles, axis=1)
    img = bpy.data.images.new("strip", strip.shape[1], strip.shape[0], alpha=True)
    img.pixels.foreach_set(strip.ravel())
    img.filepath_raw, img.file_format = path, 'PNG'
    img.save()


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="bake_example.py")
    ap.add_argument("--example", default="character")
    ap.add_argument("--count", type=int, default=4)
    ap.add_argument("--out", default=os.path.join(ROOT, "out"))
    ap.add_argument("--resolution", type=int, default=256)
    ap.add_argument("--core", help="a folder holding the bdinterp package (python/ after `make build`): "
                    "runs it with this checkout's addon/")
    args = ap.parse_args(argv)
    args.out = os.path.abspath(args.out)  # Blender's save operator wants absolute paths
    os.makedirs(args.out, exist_ok=True)
    addon = import_addon(args.core)

    src, tgt, faces = example_shapes(addon, args.example)
    obj = make_object(src, tgt, faces)
    result = addon.bake(obj, source="Basis", target="Pose", count=args.count, easing="EASE_IN_OUT")
    print(result.message)
    scene = bpy.context.scene
    keys = obj.data.shape_keys.key_blocks
    states = ["Basis"] + result.keys + ["Pose"]
    knots = [0.0] + list(result.positions) + [1.0]
    setup_render([np.array([tuple(d.co) for d in keys[n].data]) for n in states], args.resolution)
    from bdinterp_blender.view import distortion
    tiles = []
    for i, (name, s) in enumerate(zip(states, knots)):
        # each state through the playback slider, coloured by its conformal distortion
        obj[result.slider] = s
        obj.update_tag()  # ID-property writes do not tag the depsgraph by themselves
        if name == "Basis":
            scene.display.shading.color_type = 'SINGLE'
            scene.display.shading.single_color = tuple(distortion.colors(np.ones(1), 2.0)[0, :3])
        else:
            addon.show_distortion(obj, name)
        tiles.append(render_to(os.path.join(args.out, "example_%02d.png" % i)))
    # an animator's timeline: slider 0 -> 1 over frames 1..24 (after the stills: keyframes
    # would override the slider values set above when rendering)
    scene.frame_start, scene.frame_end = 1, 24
    for frame, value in ((1, 0.0), (24, 1.0)):
        obj[result.slider] = value
        obj.keyframe_insert('["%s"]' % result.slider, frame=frame)
    obj[result.slider] = 0.0

    save_strip(tiles, os.path.join(args.out, "example_strip.png"))
    # save with the playback state (slider keyframed), viewport colours back to materials
    addon.hide_distortion(obj)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(args.out, "example.blend"))
    print("bake_example: wrote %s/example.blend, example_00..%02d.png, example_strip.png"
          % (args.out, len(states) - 1))


main()
