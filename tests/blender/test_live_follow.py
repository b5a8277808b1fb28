"""Live mode follows every change Blender can signal: drivers, F-curve edits, key edits, undo;
set_live validates before it writes; Bake Live to Keys."""

import bpy
import numpy as np
import pytest

from conftest import (TOL, bent_strip, evaluated_co, fcurve, key_names, maxdiff, read_key,
                      triangles)


def expected(bd, obj, t, target="Bend"):
    return bd.interpolate(read_key(obj, "Basis"), read_key(obj, target), triangles(obj), t)


def test_driven_factor_updates_mesh(addon, bd):
    obj = bent_strip()
    obj["ctl"] = 0.2
    addon.set_live(obj, target="Bend", factor=0.0)
    fc = obj.driver_add("bdi.live_factor")
    var = fc.driver.variables.new()
    var.name, var.type = "c", 'SINGLE_PROP'
    var.targets[0].id, var.targets[0].data_path = obj, '["ctl"]'
    fc.driver.expression = "c * 2"
    for ctl in (0.2, 0.35, 0.1):
        obj["ctl"] = ctl
        obj.update_tag()  # what the UI does when a custom property is edited
        assert maxdiff(evaluated_co(obj), expected(bd, obj, 2 * ctl)) < TOL, ctl
    assert obj.bdi.live and not obj.bdi.live_error


def live_strip_keyframed(addon, last_frame):
    """A strip in live mode whose factor is keyframed 0 (frame 1) -> 1 (last_frame)."""
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.0)
    obj.keyframe_insert("bdi.live_factor", frame=1)
    obj.bdi.live_factor = 1.0
    obj.keyframe_insert("bdi.live_factor", frame=last_frame)
    return obj


def test_fcurve_edit_updates_mesh_without_frame_change(addon, bd):
    obj = live_strip_keyframed(addon, 11)
    bpy.context.scene.frame_set(6)
    curve = fcurve(obj.animation_data, "bdi.live_factor")
    assert maxdiff(evaluated_co(obj), expected(bd, obj, curve.evaluate(6))) < TOL
    before = curve.evaluate(6)
    curve.keyframe_points[1].co.y = 0.4  # as a drag in the Graph Editor
    curve.keyframe_points[1].handle_left.y = curve.keyframe_points[1].handle_right.y = 0.4
    curve.update()
    obj.animation_data.action.update_tag() if hasattr(bpy.types.Action, "update_tag") else None
    bpy.context.view_layer.update()
    t = curve.evaluate(6)
    assert abs(t - before) > 0.05  # the edit changed the factor at this frame
    assert maxdiff(evaluated_co(obj), expected(bd, obj, t)) < TOL


def test_edited_target_key_is_noticed(addon, bd):
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.5)
    kb = obj.data.shape_keys.key_blocks["Bend"]
    co = read_key(obj, "Bend") * [1.3, 1.0, 1.0]  # still planar: a valid new target
    kb.data.foreach_set("co", co.astype(np.float32).ravel())
    obj.data.shape_keys.update_tag()
    assert maxdiff(evaluated_co(obj), expected(bd, obj, 0.5)) < TOL
    bpy.context.scene.frame_set(3)
    assert maxdiff(evaluated_co(obj), expected(bd, obj, 0.5)) < TOL


def test_undo_of_factor_change_updates_mesh(addon, bd):
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.3)
    bpy.ops.ed.undo_push(message="factor 0.3")
    obj.bdi.live_factor = 0.9
    bpy.ops.ed.undo_push(message="factor 0.9")
    obj = bpy.data.objects["Strip"]
    assert maxdiff(evaluated_co(obj), expected(bd, obj, 0.9)) < TOL
    bpy.ops.ed.undo()
    obj = bpy.data.objects["Strip"]
    assert obj.bdi.live_factor == pytest.approx(0.3)
    assert maxdiff(evaluated_co(obj), expected(bd, obj, 0.3)) < TOL


@pytest.mark.parametrize("kwargs,match", [({"target": "Nope"}, "no shape key named 'Nope'"),
                                          ({"target": "Basis"}, "is the source key"),
                                          ({"weights": {"Bend": -1.0}}, ">= 0"),
                                          ({"target": "Bend", "anchor": "SIDEWAYS"}, "anchor must be")])
def test_set_live_validates_before_writing(addon, kwargs, match):
    obj = bent_strip()
    obj.bdi.target, obj.bdi.live_factor = "Bend", 0.25
    before = {name: getattr(obj.bdi, name) for name in ("target", "source", "live_mode", "anchor",
                                                        "live_factor", "live")}
    with pytest.raises(ValueError, match=match):
        addon.set_live(obj, factor=0.75, **kwargs)
    assert {name: getattr(obj.bdi, name) for name in before} == before
    assert len(obj.bdi.poses) == 0 and "bdi.live" not in key_names(obj)


def test_bake_live_to_keys(addon, bd):
    obj = live_strip_keyframed(addon, 9)
    obj.bdi.count = 7
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.bdinterp.bake_live() == {'FINISHED'}
    assert not obj.bdi.live and "bdi.live" not in key_names(obj)
    factor = fcurve(obj.animation_data, "bdi.live_factor")
    slider = fcurve(obj.animation_data, '["Bend.bdi"]')
    assert slider is not None
    for frame in (1, 3, 5, 9):
        assert slider.evaluate(frame) == pytest.approx(factor.evaluate(frame), abs=1e-6)
    # at the slider positions of the in-betweens the played mesh is the exact in-between
    bpy.context.scene.frame_set(5)  # factor 0.5 = the 4th of 7 in-betweens
    assert obj["Bend.bdi"] == pytest.approx(0.5, abs=1e-6)
    assert maxdiff(evaluated_co(obj), expected(bd, obj, 0.5)) < TOL
    result = __import__("json").loads(obj.bdi.result)
    assert result["keys"] == 7 and "keyframed like the live factor" in result["note"]


def test_file_with_live_objects_warns_on_load(addon, tmp_path, capsys):
    import os
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.5)
    path = os.path.join(str(tmp_path), "live.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    capsys.readouterr()
    bpy.ops.wm.open_mainfile(filepath=path)
    out = capsys.readouterr().out
    assert "bdinterp: Strip in scene Scene needs the bdinterp add-on enabled" in out
    assert "Bake Live to Keys" in out


def live_blend_strip(addon, long_weight, last_frame):
    """A strip in live pose-blend mode over keys 'Bend' (weight 0) and 'Long' (a stretch), with
    the scene's frames 1 .. last_frame."""
    from conftest import add_key
    obj = bent_strip()
    add_key(obj, "Long", read_key(obj, "Basis") * [1.4, 1.0, 1.0])
    addon.set_live(obj, weights={"Bend": 0.0, "Long": long_weight})
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, last_frame
    return obj


def assert_baked_blends(bd, obj, weights):
    """At every frame f of weights {f: (w_bend, w_long)} the baked keys play bd.blend's result."""
    shapes = [read_key(obj, n) for n in ("Basis", "Bend", "Long")]
    for frame, (a, b) in weights.items():
        bpy.context.scene.frame_set(frame)
        w = [1 - a - b, a, b]
        assert maxdiff(evaluated_co(obj), bd.blend(shapes, triangles(obj), w)) < TOL, frame


def test_bake_live_pose_blend_to_keyframed_keys(addon, bd):
    obj = live_blend_strip(addon, 0.0, 6)
    poses = obj.bdi.poses
    for frame, (a, b) in {1: (0.0, 0.0), 4: (0.6, 0.3)}.items():
        poses[0].weight, poses[1].weight = a, b
        obj.keyframe_insert("bdi.poses[0].weight", frame=frame)
        obj.keyframe_insert("bdi.poses[1].weight", frame=frame)
    curves = [fcurve(obj.animation_data, "bdi.poses[%d].weight" % i) for i in (0, 1)]
    expected_w = {f: (curves[0].evaluate(f), curves[1].evaluate(f)) for f in range(1, 7)}
    result = addon.bake_live(obj)
    assert not obj.bdi.live and "bdi.live" not in key_names(obj)
    assert len(result.keys) == len(set(expected_w.values())) == 4  # frames 4-6 share their weights
    assert_baked_blends(bd, obj, expected_w)


def test_bake_live_pose_blend_with_a_driven_weight(addon, bd):
    """A weight driven by the frame (a driver, not keyframes) is baked as Blender evaluates it."""
    obj = live_blend_strip(addon, 0.25, 5)
    fc = obj.driver_add("bdi.poses[0].weight")
    fc.driver.expression = "min(frame, 4) / 8"  # 1/8 .. 1/2, constant from frame 4 on
    obj.bdi.use_factors, obj.bdi.factors = True, "x"  # the in-betweens' factors: not the blend's
    result = addon.bake_live(obj)
    assert len(result.keys) == 4  # frames 4 and 5 share their weights
    obj.driver_remove("bdi.poses[0].weight")
    assert_baked_blends(bd, obj, {f: (min(f, 4) / 8, 0.25) for f in range(1, 6)})
