"""Pose blending (paper Section 5) and the distortion view."""

import bpy
import numpy as np
import pytest

from conftest import TOL, add_key, bent_strip, key_names, maxdiff, read_key, triangles


def strip_with_poses():
    obj = bent_strip()
    base = read_key(obj, "Basis")
    add_key(obj, "Long", base * [1.5, 1.0, 1.0])
    add_key(obj, "Thick", base * [1.0, 2.0, 1.0])
    return obj


def test_bake_pose_blend_operator(bd):
    obj = strip_with_poses()
    props = obj.bdi
    bpy.context.view_layer.objects.active = obj
    for name in ("Bend", "Long", "Thick"):
        obj.active_shape_key_index = key_names(obj).index(name)
        assert bpy.ops.bdinterp.pose_add() == {'FINISHED'}
    for item, w in zip(props.poses, (0.5, 0.2, 0.1)):
        item.weight = w
    assert bpy.ops.bdinterp.blend() == {'FINISHED'}
    import json
    box = json.loads(obj.bdi.result)  # the panel's result box
    assert box["keys"] == 1 and box["target"] == "blend of Bend, Long, Thick" and box["folded"] == 0
    assert box["max_distortion"] <= box["input_distortion"] * (1 + 1e-6)
    shapes = [read_key(obj, n) for n in ("Basis", "Bend", "Long", "Thick")]
    expected = bd.blend(shapes, triangles(obj), [0.2, 0.5, 0.2, 0.1])
    assert maxdiff(read_key(obj, "Blend.bdi"), expected) < TOL
    kb = obj.data.shape_keys.key_blocks["Blend.bdi"]
    assert kb.relative_key.name == "Basis"
    # baking again replaces the key
    props.poses[0].weight = 0.0
    bpy.ops.bdinterp.blend()
    assert key_names(obj).count("Blend.bdi") == 1
    expected = bd.blend(shapes, triangles(obj), [0.7, 0.0, 0.2, 0.1])
    assert maxdiff(read_key(obj, "Blend.bdi"), expected) < TOL


def test_blend_weights_above_one_are_normalised(addon, bd):
    obj = strip_with_poses()
    name, k_out, k_in = addon.blend(obj, {"Long": 1.0, "Thick": 3.0}, name="Mix")
    shapes = [read_key(obj, n) for n in ("Basis", "Long", "Thick")]
    assert maxdiff(read_key(obj, name), bd.blend(shapes, triangles(obj), [0.0, 0.25, 0.75])) < TOL
    assert k_out <= k_in * (1 + 1e-6)


def test_blend_errors_change_nothing(addon):
    obj = strip_with_poses()
    before = key_names(obj)
    with pytest.raises(ValueError, match=">= 0"):
        addon.blend(obj, {"Long": -0.5})
    with pytest.raises(ValueError, match="no shape key named"):
        addon.blend(obj, {"Nope": 0.5})
    assert key_names(obj) == before


def test_distortion_view(addon, bd):
    obj = bent_strip()
    result = addon.bake(obj, target="Bend", count=3)
    obj.active_shape_key_index = key_names(obj).index(result.keys[1])
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.bdinterp.distortion(action='SHOW') == {'FINISHED'}
    me = obj.data
    attr = me.attributes["bdi_distortion"]
    assert (attr.domain, attr.data_type) == ('FACE', 'FLOAT')
    k = np.empty(len(me.polygons), dtype=np.float32)
    attr.data.foreach_get("value", k)
    # per face: the worst of its triangles, against the source key
    tri_k = bd.conformal_distortion(read_key(obj, "Basis"), read_key(obj, result.keys[1]), triangles(obj))
    me.calc_loop_triangles()
    poly = np.array([t.polygon_index for t in me.loop_triangles])
    expected = np.ones(len(me.polygons))
    np.maximum.at(expected, poly, tri_k)
    assert np.allclose(k, expected, rtol=1e-6)
    assert k.max() > 1.0 + 1e-3  # a real, non-trivial distortion
    col = me.color_attributes["bdi_distortion_color"]
    assert me.color_attributes.active_color.name == col.name and col.domain == 'CORNER'
    assert bpy.context.scene.display.shading.color_type == 'VERTEX'
    assert obj.bdi.distortion_visible
    assert bpy.ops.bdinterp.distortion(action='TOGGLE') == {'FINISHED'}
    assert bpy.context.scene.display.shading.color_type == 'MATERIAL' and not obj.bdi.distortion_visible


def test_distortion_of_live_key(addon):
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.5)
    k = addon.show_distortion(obj, "bdi.live")
    assert len(k) == len(obj.data.polygons) and np.all(k >= 1.0)
