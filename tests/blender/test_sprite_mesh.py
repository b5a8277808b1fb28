"""Mesh from Image on two image planes: geometry from the image's alpha in the plane's place and
size, UVs onto the image, materials and transforms kept, one undo step, a failure changing nothing."""
import os
import sys

import bpy
import numpy as np
import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "tools"))
from bdinterp_tools.sprites import SPRITES  # noqa: E402


def image_plane(name, sprite, location, scale=2.0):
    """An image plane as Images as Planes makes it: a quad of the image's aspect in local XY, a
    material whose image texture shows the sprite."""
    rgba = SPRITES[sprite]()
    h, w = rgba.shape[:2]
    image = bpy.data.images.new(name, w, h, alpha=True)
    image.pixels.foreach_set((rgba[::-1].astype(np.float32) / 255).ravel())
    sx, sy = scale / 2, scale * h / w / 2
    me = bpy.data.meshes.new(name)
    me.from_pydata([(-sx, -sy, 0), (sx, -sy, 0), (sx, sy, 0), (-sx, sy, 0)], [], [(0, 1, 2, 3)])
    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):  # always nodes on 5.x (use_nodes deprecated)
        mat.use_nodes = True
    node = mat.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    me.materials.append(mat)
    obj = bpy.data.objects.new(name, me)
    obj.location, obj.rotation_euler = location, (1.5708, 0, 0.3)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def local_co(obj):
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def test_two_planes_one_undo_step(addon):
    a, b = image_plane("Ring", "ring", (0, 0, 0)), image_plane("Letter", "letter_b", (3, 0, 0))
    for o in bpy.data.objects:
        o.select_set(o in (a, b))
    bpy.context.view_layer.objects.active = a
    bpy.ops.ed.undo_push(message="before")
    matrices = [o.matrix_world.copy() for o in (a, b)]
    assert bpy.ops.bdinterp.mesh_from_image('EXEC_DEFAULT', True, preset="BENDS") == {'FINISHED'}
    from bdinterp_blender.files import sprite_mesh
    bd = addon.load_core()
    for name in ("Ring", "Letter"):
        obj = bpy.data.objects[name]
        assert obj.matrix_world == matrices[0 if name == "Ring" else 1]
        assert obj.data.materials[0].name == name
        co = local_co(obj)
        assert len(obj.data.polygons) > 50 and all(len(p.vertices) == 3 for p in obj.data.polygons)
        assert np.abs(co[:, 2]).max() < 1e-6
        # UVs onto the image: each corner's UV is its vertex's place on the plane (-1..1 by -1..1).
        uv = np.empty(len(obj.data.loops) * 2, np.float32)
        obj.data.uv_layers[0].data.foreach_get("uv", uv)
        vi = np.empty(len(obj.data.loops), np.int64)
        obj.data.loops.foreach_get("vertex_index", vi)
        np.testing.assert_allclose(uv.reshape(-1, 2) * 2 - 1, co[vi, :2], atol=1e-5)
        # The same mesh as the core makes from the image's alpha as Blender holds it (8 bits a
        # channel: the sprite's box at the threshold, and so the spacing, is that image's).
        alpha = sprite_mesh.alpha_of(sprite_mesh.image_of(obj))
        expected = bd.mesh_from_image(alpha, spacing_divisions=12, detail=1.0,
                                      min_angle=25.0)  # the BENDS preset
        assert len(obj.data.vertices) == len(expected.vertices)
    bpy.ops.ed.undo()  # one step restores both quads
    assert [len(bpy.data.objects[n].data.vertices) for n in ("Ring", "Letter")] == [4, 4]


def test_failure_changes_nothing(addon):
    import bdinterp_blender
    good = image_plane("Good", "ring", (0, 0, 0))
    empty = image_plane("Empty", "ring", (3, 0, 0))
    empty.data.materials[0].node_tree.nodes["Image Texture"].image.pixels.foreach_set(
        np.zeros(128 * 128 * 4, np.float32))
    with pytest.raises(ValueError, match="'Empty'.*no pixel has alpha"):
        bdinterp_blender.mesh_from_image([good, empty])
    assert len(good.data.vertices) == 4 and len(empty.data.vertices) == 4
    assert bdinterp_blender.mesh_from_image(good)[0] > 50


def test_panel_and_menu(addon):
    obj = image_plane("Panel", "ring", (0, 0, 0))
    bpy.context.view_layer.objects.active = obj
    panel = bpy.types.BDINTERP_PT_sprite_mesh
    assert panel.poll(bpy.context)
    assert any(getattr(f, "__name__", "") == "_menu" for f in bpy.types.VIEW3D_MT_object._dyn_ui_initialize())
    obj.shape_key_add(name="Basis")
    assert not panel.poll(bpy.context)  # a mesh with keys is past this step


def test_spacing_0_is_said_in_words(addon):
    from bdinterp_blender.files import sprite_mesh
    assert sprite_mesh.spacing_zero("CUSTOM", None) == "0: automatic"
    assert sprite_mesh.spacing_zero("BENDS", None) == "0: from the preset (12 edges across)"
    image = bpy.data.images.new("sheet", 240, 96, alpha=True)
    mat = bpy.data.materials.new("m")
    mat.use_nodes = True
    mat.node_tree.nodes.new("ShaderNodeTexImage").image = image
    bpy.ops.mesh.primitive_plane_add()
    bpy.context.object.data.materials.append(mat)
    assert sprite_mesh.spacing_zero("FACE", bpy.context.object) == \
        "0: from the preset (24 edges across = 10 px)"


def test_the_dialog_meshes_once_per_changed_setting(addon):
    """The dialog's draw() runs on every redraw: the triangle count it shows is meshed once per
    request, and Apply uses that mesh (no third run); a changed setting meshes again."""
    from bdinterp_blender.files import sprite_mesh
    obj = image_plane("Ring", "ring", (0, 0, 0))
    params = dict(threshold=0.5, spacing=None, detail=1.0, padding=1.0, min_angle=25.0)
    before = sprite_mesh.counters["meshed"]
    first = sprite_mesh.preview(obj, params)
    for _ in range(5):  # redraws
        assert sprite_mesh.preview(obj, params) is first
    assert sprite_mesh.counters["meshed"] == before + 1
    other = sprite_mesh.preview(obj, dict(params, threshold=0.25))
    assert sprite_mesh.counters["meshed"] == before + 2 and other is not first
    assert sprite_mesh.preview(obj, params) is first  # back to the first setting: kept
    # the same request as plan() makes it: the same mesh
    again = sprite_mesh.plan(obj, **params)
    assert all(np.array_equal(a, b) for a, b in zip(again, first))
    with pytest.raises(ValueError, match="has no material with an image texture"):
        bare = bpy.data.objects.new("Bare", bpy.data.meshes.new("Bare"))
        bare.data.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
        sprite_mesh.preview(bare, params)
    count = sprite_mesh.counters["meshed"]
    with pytest.raises(ValueError, match="has no material"):  # the error is kept too
        sprite_mesh.preview(bare, params)
    assert sprite_mesh.counters["meshed"] == count
