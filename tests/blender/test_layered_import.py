"""Layered painting import (OpenRaster and COA Tools' JSON): placement to one pixel, draw order as
depth, hidden layers and groups, sprite sheets, opacity, one object per layer or one object, a
broken file importing nothing."""
import json
import math
import os
import xml.etree.ElementTree as ET
import zipfile

import bpy
import numpy as np
import pytest

from conftest import ROOT, read_key, triangles

SCALE = 0.01


def png(path, w, h, *rects):
    """A w x h PNG, opaque inside each rect = (col0, row0, col1, row1) (rows from the top), clear
    elsewhere; returns its bytes."""
    image = bpy.data.images.new("tmp", w, h, alpha=True)
    px = np.zeros((h, w, 4), np.float32)
    for c0, r0, c1, r1 in rects:
        px[r0:r1, c0:c1] = 1.0
    image.pixels.foreach_set(px[::-1].ravel())
    image.filepath_raw, image.file_format = path, 'PNG'
    image.save()
    bpy.data.images.remove(image)
    return open(path, "rb").read()


# name: (x, y, w, h, rect) of each layer of the painting; the stack is listed top first.
LAYERS = {"head": (120, 10, 40, 30, (5, 5, 35, 25)), "ghost": (0, 0, 20, 20, (0, 0, 20, 20)),
          "arm": (90, 50, 30, 20, (0, 5, 30, 15)), "body": (20, 40, 60, 50, (0, 0, 60, 50))}
STACK = """<image w="200" h="100"><stack>
<layer name="head" src="data/head.png" x="120" y="10"/>
<layer name="ghost" src="data/ghost.png" x="0" y="0" visibility="hidden"/>
<stack name="limbs" x="10" y="0"><layer name="arm" src="data/arm.png" x="80" y="50"/></stack>
<layer name="body" src="data/body.png" x="20" y="40"/>
</stack></image>"""


@pytest.fixture
def ora(tmp_path):
    path = tmp_path / "character.ora"
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("mimetype", "image/openraster")
        z.writestr("stack.xml", STACK)
        for name, (_, _, w, h, rect) in LAYERS.items():
            z.writestr("data/%s.png" % name, png(str(tmp_path / (name + ".png")), w, h, rect))
    return path


def world_co(obj):
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    m = np.array(obj.matrix_world)
    return co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]


def local_co(obj, world):
    """World coordinates world (n, 3) in obj's local coordinates."""
    m = np.array(obj.matrix_world)
    return np.linalg.solve(m[:3, :3], (world - m[:3, 3]).T).T


def assert_placed(obj, x, y, rect):
    """obj's vertices span the opaque pixels' box rect (of its image, at x, y in the canvas), grown by
    the padding (1 px), to one pixel."""
    c0, r0, c1, r1 = rect
    co = world_co(obj)
    expected = [(x + c0 - 1) * SCALE, (x + c1 + 1) * SCALE, -(y + r1 + 1) * SCALE, -(y + r0 - 1) * SCALE]
    got = [co[:, 0].min(), co[:, 0].max(), co[:, 2].min(), co[:, 2].max()]
    assert np.abs(np.subtract(got, expected)).max() <= SCALE, (obj.name, got, expected)


def assert_drawn_in_order(objs):
    depth = [world_co(o)[:, 1].mean() for o in objs]
    assert all(a > b for a, b in zip(depth, depth[1:])), depth  # drawn higher: smaller y


def test_one_object_per_layer(addon, ora):
    import bdinterp_blender
    objs = bdinterp_blender.import_layered(str(ora), scale=SCALE)
    assert [o.name for o in objs] == ["body", "arm", "head"]  # draw order, bottom first
    assert all(o.select_get() for o in objs)
    for obj in objs:
        x, y, _, _, rect = LAYERS[obj.name]
        assert_placed(obj, x, y, rect)
        assert obj.data.materials[0].node_tree.nodes["Image Texture"].image.packed_file is not None
    assert_drawn_in_order(objs)


def test_one_object(addon, ora):
    import bdinterp_blender
    (obj,) = bdinterp_blender.import_layered(str(ora), one_object=True, scale=SCALE)
    assert [m.name.split(".")[0] for m in obj.data.materials] == ["body", "arm", "head"]
    index = np.empty(len(obj.data.polygons), np.int64)
    obj.data.polygons.foreach_get("material_index", index)
    assert set(index) == {0, 1, 2}


def test_broken_file_imports_nothing(addon, ora, tmp_path):
    import bdinterp_blender
    broken = tmp_path / "broken.ora"
    with zipfile.ZipFile(ora) as src, zipfile.ZipFile(broken, "w") as dst:
        for item in src.namelist():
            if item != "data/arm.png":
                dst.writestr(item, src.read(item))
    before = (len(bpy.data.objects), len(bpy.data.meshes), len(bpy.data.images), len(bpy.data.materials))
    with pytest.raises(ValueError, match="layer 'arm': its image 'data/arm.png' is missing"):
        bdinterp_blender.import_layered(str(broken))
    with pytest.raises(ValueError, match="not an OpenRaster file"):
        bdinterp_blender.import_layered(str(tmp_path / "head.png"))
    assert (len(bpy.data.objects), len(bpy.data.meshes), len(bpy.data.images), len(bpy.data.materials)) == before


# COA Tools' JSON: the same painting (the group's offset added to the arm), listed out of draw order,
# with a 2 x 2 sprite sheet whose frame 2 (bottom left) is shown, at half opacity, in front.
COA_NODES = [("arm", 1), ("eye", 3), ("body", 0), ("head", 2)]
SHEET = (30, 60, 40, 20, (3, 12, 15, 18))  # x, y, w, h and the shown frame's opaque box in the sheet


@pytest.fixture
def coa(tmp_path):
    folder = tmp_path / "export"
    (folder / "sprites").mkdir(parents=True)
    nodes = []
    for name, z in COA_NODES:
        x, y, w, h, rect = LAYERS.get(name, SHEET)
        file = str(folder / "sprites" / (name + ".png"))
        node = {"name": name, "type": "SPRITE", "resource_path": "sprites/%s.png" % name,
                "offset": [-100, 50], "position": [x, y], "z": z, "opacity": 1, "tiles_x": 1, "tiles_y": 1}
        if name == "eye":  # frames 0, 1 and 3 full, frame 2 the box
            png(file, w, h, (0, 0, 40, 10), (20, 10, 40, 20), rect)
            node.update(tiles_x=2, tiles_y=2, frame_index=2, opacity=0.5)
        else:
            png(file, w, h, rect)
        nodes.append(node)
    path = folder / "character.json"
    path.write_text(json.dumps({"name": "character", "nodes": nodes}))
    return path


def test_coa_json_one_object_per_layer(addon, coa):
    import bdinterp_blender
    objs = bdinterp_blender.import_layered(str(coa), scale=SCALE)
    assert [o.name for o in objs] == ["body", "arm", "head", "eye"]  # by z, bottom first
    for obj in objs:
        x, y, _, _, rect = LAYERS.get(obj.name, SHEET)
        if obj.name == "eye":  # the frame's box, from the frame's top-left corner (row 10)
            rect = (rect[0], rect[1] - 10, rect[2], rect[3] - 10)
        assert_placed(obj, x, y, rect)
    assert_drawn_in_order(objs)
    nodes = [m.node_tree.nodes for o in objs for m in o.data.materials]
    assert [n["Math"].inputs[1].default_value if "Math" in n else 1 for n in nodes] == [1, 1, 1, 0.5]


def test_coa_sprite_sheet_frame_uvs(addon, coa):
    import bdinterp_blender
    eye = bdinterp_blender.import_layered(str(coa), scale=SCALE)[-1]
    me = eye.data
    index = np.empty(len(me.loops), np.int64)
    me.loops.foreach_get("vertex_index", index)
    uv = np.empty(len(me.loops) * 2, np.float32)
    me.uv_layers[0].data.foreach_get("uv", uv)
    co = world_co(eye)[index]
    x, y, w, h, _ = SHEET
    # frame 2 of 2 x 2 is the sheet's bottom-left quarter: u * w from its left, v * h from its bottom
    assert np.abs(uv[0::2] * w - (co[:, 0] / SCALE - x)).max() < 1e-3
    assert np.abs(uv[1::2] * h - (10 + co[:, 2] / SCALE + y)).max() < 1e-3
    assert uv[0::2].max() < 0.5 and uv[1::2].max() < 0.5


def test_coa_json_one_object(addon, coa):
    import bdinterp_blender
    (obj,) = bdinterp_blender.import_layered(str(coa), one_object=True, scale=SCALE)
    assert obj.name == "character"
    assert [m.name.split(".")[0] for m in obj.data.materials] == ["body", "arm", "head", "eye"]
    index = np.empty(len(obj.data.polygons), np.int64)
    obj.data.polygons.foreach_get("material_index", index)
    assert set(index) == {0, 1, 2, 3}


def broken_coa(coa, change):
    doc = json.loads(coa.read_text())
    change(doc)
    path = coa.parent / "broken.json"
    path.write_text(json.dumps(doc))
    return str(path)


@pytest.mark.parametrize("change, message", [
    (lambda d: d["nodes"][0].update(resource_path="sprites/gone.png"),
     r"broken.json': node 0 'arm': its image '.*sprites/gone.png' is missing"),
    (lambda d: d["nodes"][2].update(position=[1]), r"node 2 'body': 'position' must be two numbers"),
    (lambda d: d["nodes"][3].pop("z"), r"node 3 'head': 'z' must be a number"),
    (lambda d: d["nodes"][1].update(frame_index=4), r"node 1 'eye': 'frame_index' must be a frame of"),
    (lambda d: d["nodes"][1].update(opacity=2), r"node 1 'eye': 'opacity' must lie in \[0, 1\]"),
    (lambda d: d["nodes"][3].update(resource_path="character.json"),
     r"broken.json': node 3 'head': its image '.*character.json': it is not a PNG image"),
    (lambda d: d.pop("nodes"), r"is not a COA Tools JSON file: it has no list of 'nodes'"),
])
def test_broken_coa_json_imports_nothing(addon, coa, change, message):
    import bdinterp_blender
    path = broken_coa(coa, change)
    before = (len(bpy.data.objects), len(bpy.data.meshes), len(bpy.data.images), len(bpy.data.materials))
    with pytest.raises(ValueError, match=message):
        bdinterp_blender.import_layered(path)
    with pytest.raises(ValueError, match="not a COA Tools JSON file"):
        bdinterp_blender.import_layered(str(coa.parent / "sprites" / "arm.png") + ".json")
    assert (len(bpy.data.objects), len(bpy.data.meshes), len(bpy.data.images), len(bpy.data.materials)) == before


def test_operator_imports_json_and_refuses_a_broken_file(addon, coa):
    assert bpy.ops.bdinterp.import_layered(filepath=str(coa), one_object=True) == {'FINISHED'}
    assert [o.name for o in bpy.context.selected_objects] == ["character"]
    before = (len(bpy.data.objects), len(bpy.data.images), len(bpy.data.materials))
    path = broken_coa(coa, lambda d: d["nodes"][2].update(z="front"))
    with pytest.raises(RuntimeError, match="node 2 'body': 'z' must be a number"):
        bpy.ops.bdinterp.import_layered(filepath=path)
    assert (len(bpy.data.objects), len(bpy.data.images), len(bpy.data.materials)) == before


# A character of three overlapping layers (canvas pixels): the arm overlaps the torso at the
# shoulder, the head overlaps its top; the arm is raised by 60 degrees about the shoulder.
CHARACTER = {"torso": (60, 60, 60, 100), "arm": (110, 70, 70, 20), "head": (65, 10, 50, 55)}
SHOULDER, RAISE = (115.0, 80.0), math.radians(60)


def turned(co, centre, angle):
    """co (n, 3) turned by angle about the front-view axis (y) through centre (x, z)."""
    c, s = math.cos(angle), math.sin(angle)
    d = co[:, [0, 2]] - centre
    out = co.copy()
    out[:, 0], out[:, 2] = centre[0] + c * d[:, 0] - s * d[:, 1], centre[1] + s * d[:, 0] + c * d[:, 1]
    return out


def raised_arm(tmp_path):
    """CHARACTER imported, with the key 'Raise' on every piece: the arm raised about the shoulder."""
    import bdinterp_blender
    nodes = []
    for z, (name, (x, y, w, h)) in enumerate(CHARACTER.items()):
        png(str(tmp_path / (name + ".png")), w, h, (0, 0, w, h))
        nodes.append({"name": name, "resource_path": name + ".png", "position": [x, y], "z": z})
    (tmp_path / "character.json").write_text(json.dumps({"nodes": nodes}))
    objs = bdinterp_blender.import_layered(str(tmp_path / "character.json"), scale=SCALE)
    centre = np.multiply([SHOULDER[0], -SHOULDER[1]], SCALE)
    for obj in objs:
        obj.shape_key_add(name="Basis")
        co = world_co(obj)
        target = turned(co, centre, RAISE) if obj.name == "arm" else co
        obj.shape_key_add(name="Raise", from_mix=False).data.foreach_set(
            "co", local_co(obj, target).ravel())
    return objs, centre


def test_onion_skins_tint_only_the_pieces_that_move(addon, tmp_path):
    from bdinterp_blender.view import ghosts, motion_trails
    objs, _ = raised_arm(tmp_path)
    path = motion_trails.Path(objs, target="Raise", with_solver=False)
    faces = ghosts.moving_faces(path)
    first = [o.name for o in path.objs].index("arm")
    sizes = np.cumsum([0] + [len(o.data.vertices) for o in path.objs])
    arm = (sizes[first] <= faces) & (faces < sizes[first + 1])
    assert len(faces) == len(triangles(objs[[o.name for o in objs].index("arm")])), len(faces)
    assert arm.all()  # the torso and the head stand still: no ghost of theirs


def test_imported_character_bakes_the_arm_about_the_shoulder(addon, tmp_path):
    import bdinterp_blender
    objs, centre = raised_arm(tmp_path)
    result = bdinterp_blender.bake(objs, target="Raise", count=1)
    assert (result.objects, result.keys) == (3, ["Raise.bdi.050"])
    assert result.joints == 1  # the shoulder's pin (the head and the torso are both still)
    everything = np.concatenate([world_co(o) for o in objs])
    size = np.ptp(everything[:, [0, 2]], axis=0).max()
    for obj in objs:
        half = read_key(obj, "Raise.bdi.050") + np.array(obj.location)
        expected = turned(world_co(obj), centre, RAISE / 2) if obj.name == "arm" else world_co(obj)
        tolerance = 0.005 if obj.name == "arm" else 1e-6
        assert np.abs(half - expected).max() <= tolerance * size, obj.name


def test_the_example_character_imports_in_draw_order(addon):
    import bdinterp_blender
    path = os.path.join(ROOT, "examples", "sprites", "character.ora")
    with zipfile.ZipFile(path) as z:
        layers = ET.fromstring(z.read("stack.xml")).find("stack")
    objs = bdinterp_blender.import_layered(path, scale=SCALE)
    assert [o.name for o in objs] == [layer.get("name") for layer in layers][::-1]
    assert len(objs) >= 7
    for obj, layer in zip(objs, list(layers)[::-1]):  # each within its layer's box (its PNG's size)
        image = obj.data.materials[0].node_tree.nodes["Image Texture"].image
        x, y, (w, h) = int(layer.get("x")), int(layer.get("y")), image.size
        co = world_co(obj) / SCALE
        assert x <= co[:, 0].min() and co[:, 0].max() <= x + w, obj.name
        assert -y - h <= co[:, 2].min() and co[:, 2].max() <= -y, obj.name
    assert_drawn_in_order(objs)


# The example's pieces and the piece each hangs from (the torso, the largest, hangs from none).
PARENTS = {"head": "torso", "upper_arm_l": "torso", "upper_arm_r": "torso", "thigh_l": "torso",
           "thigh_r": "torso", "forearm_l": "upper_arm_l", "forearm_r": "upper_arm_r",
           "shin_l": "thigh_l", "shin_r": "thigh_r"}


def test_each_layer_object_has_its_origin_at_its_depth_and_joint(addon):
    import bdinterp_blender
    objs = bdinterp_blender.import_layered(os.path.join(ROOT, "examples", "sprites", "character.ora"),
                                           scale=SCALE)
    depth = [o.location.y for o in objs]  # renderers sort blended objects by origin: no ties
    assert all(a - b > 0.5 * bdinterp_blender.files.layered_import.DEPTH for a, b in zip(depth, depth[1:]))
    by_name = {o.name: o for o in objs}
    for obj in objs:
        assert np.abs(world_co(obj)[:, 1] - obj.location.y).max() < 1e-9, obj.name
        co = world_co(obj)
        if obj.name not in PARENTS:  # the root turns about its middle
            middle = (co.min(0) + co.max(0)) / 2
            assert np.abs(np.array(obj.location) - middle)[[0, 2]].max() <= SCALE, obj.name
            continue
        for piece in (obj, by_name[PARENTS[obj.name]]):  # the joint lies where both pieces are
            box = world_co(piece)
            x, z = obj.location.x, obj.location.z
            assert box[:, 0].min() < x < box[:, 0].max() and box[:, 2].min() < z < box[:, 2].max(), \
                (obj.name, piece.name)
