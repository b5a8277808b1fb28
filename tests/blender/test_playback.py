"""Playback of a bake through native drivers, with the add-on and in a Blender without it."""

import os

import bpy
import numpy as np

from conftest import (TOL, bent_strip, evaluated_co, fcurves, json_lines, maxdiff, read_key,
                      run_blender, write_child_script)

SLIDER_VALUES = [0.0, 0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.9, 1.0]


def expected_playback(obj, result, s):
    """Piecewise-linear through source, the baked in-betweens (at their slider positions), target."""
    knots = [0.0] + list(result.positions) + [1.0]
    shapes = ([read_key(obj, result.source)] + [read_key(obj, k) for k in result.keys]
              + [read_key(obj, result.target)])
    j = min(int(np.searchsorted(knots, s, side="right")) - 1, len(knots) - 2)
    a = (s - knots[j]) / (knots[j + 1] - knots[j])
    return (1 - a) * shapes[j] + a * shapes[j + 1]


def set_slider(obj, prop, s):
    obj[prop] = s
    obj.update_tag()


def test_slider_plays_source_inbetweens_target(addon):
    obj = bent_strip()
    result = addon.bake(obj, source="Basis", target="Bend", count=3, easing="EASE_IN_OUT")
    assert result.slider == "Bend.bdi" and obj["Bend.bdi"] == 0.0
    drivers = obj.data.shape_keys.animation_data.drivers
    assert len(drivers) == 4  # three in-betweens + the target
    assert all(fc.driver.is_simple_expression and fc.driver.is_valid for fc in drivers)
    for s in SLIDER_VALUES:
        set_slider(obj, "Bend.bdi", s)
        assert maxdiff(evaluated_co(obj), expected_playback(obj, result, s)) < TOL, s
    # at an in-between's slider position the mesh is exactly that in-between
    set_slider(obj, "Bend.bdi", result.positions[1])
    assert maxdiff(evaluated_co(obj), read_key(obj, result.keys[1])) < TOL


def test_rebake_keeps_one_set_of_drivers(addon):
    obj = bent_strip()
    addon.bake(obj, target="Bend", count=5)
    result = addon.bake(obj, target="Bend", count=2)
    drivers = obj.data.shape_keys.animation_data.drivers
    assert sorted(fc.data_path for fc in drivers) == sorted(
        'key_blocks["%s"].value' % n for n in result.keys + ["Bend"])


def test_clear_removes_keys_drivers_and_slider(addon):
    obj = bent_strip()
    addon.bake(obj, target="Bend", count=3)
    obj.bdi.target = "Bend"
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.bdinterp.clear() == {'FINISHED'}
    assert [kb.name for kb in obj.data.shape_keys.key_blocks] == ["Basis", "Bend"]
    assert len(obj.data.shape_keys.animation_data.drivers) == 0
    assert "Bend.bdi" not in obj.keys()


CHILD = """
assert "bdinterp_blender" not in sys.modules and not hasattr(bpy.types.Object, "bdi")
obj = bpy.data.objects["Strip"]
out = []
for s in json.loads(sys.argv[-1]):
    obj["Bend.bdi"] = s
    obj.update_tag()
    bpy.context.view_layer.update()
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    co = np.empty(len(ev.data.vertices) * 3, dtype=np.float32)
    ev.data.vertices.foreach_get("co", co)
    out.append(co.astype(float).reshape(-1, 3).tolist())
# and through the timeline: keyframed slider, stepped with frame_set
obj.animation_data_create()
bpy.context.scene.frame_set(1)
frames = []
for f in (1, 5, 11):
    bpy.context.scene.frame_set(f)
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    co = np.empty(len(ev.data.vertices) * 3, dtype=np.float32)
    ev.data.vertices.foreach_get("co", co)
    frames.append(co.astype(float).reshape(-1, 3).tolist())
print("JSON:" + json.dumps({"slider": out, "frames": frames,
                            "autoexec": bpy.app.autoexec_fail}))
"""


def test_baked_file_plays_without_addon(addon, tmp_path):
    obj = bent_strip()
    result = addon.bake(obj, target="Bend", count=4, easing="EASE_IN")
    # keyframe the slider 0 -> 1 over frames 1..11 (linear), as an animator would
    obj["Bend.bdi"] = 0.0
    obj.keyframe_insert('["Bend.bdi"]', frame=1)
    obj["Bend.bdi"] = 1.0
    obj.keyframe_insert('["Bend.bdi"]', frame=11)
    for kp in fcurves(obj.animation_data)[0].keyframe_points:
        kp.interpolation = 'LINEAR'
    path = os.path.join(str(tmp_path), "baked.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    script = write_child_script(tmp_path, CHILD)
    proc = run_blender([path, "--python", script, "--", "[" + ", ".join(map(repr, SLIDER_VALUES)) + "]"])
    out = json_lines(proc)[0]
    assert out["autoexec"] is False  # drivers ran without trusting Python
    for s, co in zip(SLIDER_VALUES, out["slider"]):
        assert maxdiff(co, expected_playback(obj, result, s)) < TOL, s
    for f, co in zip((1, 5, 11), out["frames"]):
        assert maxdiff(co, expected_playback(obj, result, (f - 1) / 10.0)) < TOL, f
