"""Layered painting import (OpenRaster): placement to one pixel, draw order as depth, hidden layers
and groups, one object per layer or one object, a broken file importing nothing."""
import os
import zipfile

import bpy
import numpy as np
import pytest

SCALE = 0.01


def png(path, w, h, rect):
    """A w x h PNG, opaque inside rect = (col0, row0, col1, row1) (rows from the top), clear elsewhere."""
    image = bpy.data.images.new("tmp", w, h, alpha=True)
    px = np.zeros((h, w, 4), np.float32)
    c0, r0, c1, r1 = rect
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
    return co.reshape(-1, 3)


def test_one_object_per_layer(addon, ora):
    import bdinterp_blender
    objs = bdinterp_blender.import_layered(str(ora), scale=SCALE)
    assert [o.name for o in objs] == ["body", "arm", "head"]  # draw order, bottom first
    assert all(o.select_get() for o in objs)
    for obj in objs:
        x, y, _, _, (c0, r0, c1, r1) = LAYERS[obj.name]
        co = world_co(obj)
        # The opaque pixels' box in the canvas, grown by the padding (1 px), to one pixel.
        expected = [(x + c0 - 1) * SCALE, (x + c1 + 1) * SCALE, -(y + r1 + 1) * SCALE, -(y + r0 - 1) * SCALE]
        got = [co[:, 0].min(), co[:, 0].max(), co[:, 2].min(), co[:, 2].max()]
        assert np.abs(np.subtract(got, expected)).max() <= SCALE, obj.name
        assert obj.data.materials[0].node_tree.nodes["Image Texture"].image.packed_file is not None
    depth = [world_co(o)[:, 1].mean() for o in objs]
    assert depth[0] > depth[1] > depth[2]  # drawn higher: nearer the front view (smaller y)


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
    with pytest.raises(ValueError, match="layer 'arm'.*data/arm.png.*missing"):
        bdinterp_blender.import_layered(str(broken))
    with pytest.raises(ValueError, match="not an OpenRaster file"):
        bdinterp_blender.import_layered(str(tmp_path / "head.png"))
    assert (len(bpy.data.objects), len(bpy.data.meshes), len(bpy.data.images), len(bpy.data.materials)) == before
