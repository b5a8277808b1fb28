"""Cut-out characters: layered pieces in one object, seven objects as one character,
joints, masked keys. The character is examples/cutout's (seven pieces, arm raised 150 degrees,
elbow bent 90, head tilted 30, every piece moved rigidly about pins); joint openings are measured
from the triangles that hold each pin (cutout_character.joint_openings), without the solver."""

import json
import math
import os
import re
import sys

import bpy
import numpy as np
import pytest
from mathutils import Matrix

from conftest import (ROOT, TOL, bent_strip, evaluated_co, json_lines, key_names, read_key,
                      run_blender, triangles)

sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402

COUNT = 9          # in-betweens: t = 0.1 ... 0.9
OPEN = 0.005       # joints within 0.5 % of the character's size
JOINED = 1e-5      # what float32 keys leave of a pin that the solver keeps joined (measured ~1e-7)


@pytest.fixture
def character():
    pieces, joints = cc.character()
    return pieces, joints, cb.size_of(pieces)


def float32_step(X):
    """float32's step at the largest coordinate of X: what writing a key may change."""
    return np.spacing(np.float32(np.abs(X).max()))


def state(objs):
    """Everything a bake could change: key names and data, custom properties (but the add-on's
    settings group, which its live-mode handler makes by reading it), drivers."""
    return [(key_names(o), [read_key(o, n).tobytes() for n in key_names(o)],
             sorted(k for k in o.keys() if k != "bdi"),
             len(o.data.shape_keys.animation_data.drivers) if o.data.shape_keys.animation_data else 0)
            for o in objs]


def test_one_object_layered_character_keeps_joints_and_depths(addon, character):
    pieces, joints, size = character
    obj, ranges = cb.one_object(pieces)
    obj.bdi.target, obj.bdi.count = cb.TARGET, COUNT
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    assert json.loads(obj.bdi.result)["joints"] == 6  # the six pins the character is built with
    opening = cb.openings([obj], ranges, joints, size, cb.baked(obj))
    assert max(opening.values()) < min(OPEN, JOINED), opening
    X0 = read_key(obj, "Basis")
    ulp = float32_step(X0)
    for name in cb.baked(obj):
        assert np.abs(read_key(obj, name)[:, 2] - X0[:, 2]).max() <= ulp, name  # depths to float32
    # rigid keys give rigid in-betweens: every piece keeps its edge lengths
    tris = triangles(obj)
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    length0 = np.linalg.norm(X0[edges[:, 0]] - X0[edges[:, 1]], axis=1)
    for name in cb.baked(obj):
        X = read_key(obj, name)
        ratio = np.linalg.norm(X[edges[:, 0]] - X[edges[:, 1]], axis=1) / length0
        assert np.abs(ratio - 1).max() < 1e-5, name


def test_joints_switched_off_in_the_panel_open_the_chain(addon, character):
    # Without joints each piece turns about its own fixed point: the forearm, turned by 150 + 90
    # = 240 degrees in all, takes the short way (-120) and leaves the elbow.
    pieces, joints, size = character
    obj, ranges = cb.one_object(pieces)
    obj.bdi.target, obj.bdi.count, obj.bdi.joints = cb.TARGET, COUNT, 'OFF'
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    assert json.loads(obj.bdi.result)["joints"] == 0
    opening = cb.openings([obj], ranges, joints, size, cb.baked(obj))
    assert opening[("UpperArm", "Forearm")] > 0.05, opening


def test_a_piece_not_parallel_is_refused_and_named(addon, character):
    pieces, joints, size = character
    obj, ranges = cb.one_object(pieces)
    hand = list(ranges["Hand"])
    co = read_key(obj, "Basis")
    tilt = math.radians(5)  # the hand turned by 5 degrees about its long (y) axis
    x = co[hand, 0] - 1.25
    co[hand, 0], co[hand, 2] = 1.25 + x * math.cos(tilt), co[hand, 2] + x * math.sin(tilt)
    obj.data.shape_keys.key_blocks["Basis"].data.foreach_set("co", co.astype(np.float32).ravel())
    obj.bdi.target = cb.TARGET
    before = state([obj])
    with pytest.raises(RuntimeError, match=r"Character: key 'Basis', vertex (\d+): not planar: .* off "
                                           r"the plane of its piece, which must be parallel") as info:
        bpy.ops.bdinterp.bake()
    assert int(re.search(r"vertex (\d+):", str(info.value)).group(1)) in hand  # the tilted piece's
    assert state([obj]) == before


def test_seven_objects_bake_as_one_character(addon, bd, character, monkeypatch):
    pieces, joints, size = character
    objs = cb.seven_objects(pieces)
    fits = []
    fit = bd.Layers.fit
    monkeypatch.setattr(bd.Layers, "fit", lambda *a, **kw: fits.append(1) or fit(*a, **kw))
    result = addon.bake(objs, target=cb.TARGET, count=COUNT)
    assert len(fits) == 1  # the layers are fitted once (the keys, the solver, the distortion)
    assert (result.objects, result.joints) == (7, 6)
    names = cb.baked(objs[0])
    assert len(names) == COUNT and all(cb.baked(o) == names for o in objs)
    opening = cb.openings(objs, None, joints, size, names)
    assert max(opening.values()) < min(OPEN, JOINED), opening
    frames = cb.in_world(objs, names)[0]
    # the same in-betweens as the character made of one object, whose coordinates are the world's
    bpy.ops.object.select_all(action='DESELECT')
    one, _ = cb.one_object(pieces)
    one.bdi.target, one.bdi.count = cb.TARGET, COUNT
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    assert np.abs(frames - cb.in_world([one], names)[0]).max() < 1e-5 * size
    # depths (world z) kept to the float32 roundoff of the objects' own coordinates
    z0 = cb.in_world(objs, ["Basis"])[0][0][:, 2]
    assert np.abs(frames[:, :, 2] - z0).max() < 1e-6 * size


def test_one_slider_on_the_active_object_plays_every_object(addon, character):
    pieces, joints, size = character
    objs = cb.seven_objects(pieces)
    addon.bake(objs, target=cb.TARGET, count=1)  # one in-between, at t = 0.5: slider 0.5
    slider = cb.TARGET + ".bdi"
    assert slider in objs[0].keys() and not any(slider in o.keys() for o in objs[1:])
    for s, key in ((0.5, cb.TARGET + ".bdi.050"), (1.0, cb.TARGET)):
        objs[0][slider] = s
        objs[0].update_tag()
        shown = [cb.world(o, evaluated_co(o)) for o in objs]
        expected = [cb.world(o, read_key(o, key)) for o in objs]
        assert max(np.abs(a - b).max() for a, b in zip(shown, expected)) < TOL * size, s
    # baked again from another active object: its slider takes over every object's keys
    result = addon.bake(objs[::-1], target=cb.TARGET, count=1)
    assert result.note == "" and result.slider == slider and slider in objs[-1].keys()
    assert not any(slider in o.keys() for o in objs[:-1])
    assert all(cb.baked(o) == [cb.TARGET + ".bdi.050"] for o in objs)  # no end-key copies
    objs[-1][slider] = 1.0
    objs[-1].update_tag()
    shown = [cb.world(o, evaluated_co(o)) for o in objs]
    expected = [cb.world(o, read_key(o, cb.TARGET)) for o in objs]
    assert max(np.abs(a - b).max() for a, b in zip(shown, expected)) < TOL * size
    # clearing the character removes every object's keys and drivers, and the slider
    assert len(addon.clear(objs, cb.TARGET)) == len(objs)
    assert all(cb.baked(o) == [] and not o.data.shape_keys.animation_data.drivers for o in objs)
    assert slider not in objs[-1].keys()


def test_selection_bakes_in_one_undo_step(addon, character):
    pieces, joints, size = character
    objs = cb.seven_objects(pieces)
    objs[0].bdi.target, objs[0].bdi.count = cb.TARGET, 3
    bpy.ops.ed.undo_push(message="before bake")
    before = state(objs)
    # As from the UI: EXEC with an undo push (scripts' bpy.ops calls push none by default).
    assert bpy.ops.bdinterp.bake('EXEC_DEFAULT', True) == {'FINISHED'}
    objs = [bpy.data.objects[p.name] for p in pieces]
    assert all(len(cb.baked(o)) == 3 for o in objs)
    bpy.ops.ed.undo()  # one step
    assert state([bpy.data.objects[p.name] for p in pieces]) == before


def test_a_failure_in_one_object_changes_none(addon, character):
    pieces, joints, size = character
    objs = cb.seven_objects(pieces)
    hand = bpy.data.objects["Hand"]
    hand.matrix_world = Matrix.Rotation(math.radians(5), 4, 'Y') @ hand.matrix_world
    objs[0].bdi.target = cb.TARGET
    before = state(objs)
    with pytest.raises(RuntimeError, match=r"character of 7 objects: key 'Basis', vertex \d+ of 'Hand': "
                                           r"not planar: .* which must be parallel"):
        bpy.ops.bdinterp.bake()
    assert state(objs) == before


def test_a_masked_key_is_read_as_blender_shows_it(addon, bd):
    obj = bent_strip()
    co = read_key(obj, "Basis")
    group = obj.vertex_groups.new(name="Tip")
    for v, x in enumerate(co[:, 0]):  # the bend fades in along the strip
        group.add([v], float(np.clip(x + 0.5, 0.0, 1.0)), 'REPLACE')
    kb = obj.data.shape_keys.key_blocks["Bend"]
    kb.vertex_group, kb.value = "Tip", 1.0
    shown = evaluated_co(obj)  # what Blender shows at the target
    kb.value = 0.0
    assert np.abs(shown - read_key(obj, "Bend")).max() > 0.1  # the mask matters
    obj.bdi.target, obj.bdi.count = "Bend", 3
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    faces = triangles(obj)
    for name, t in zip(cb.baked(obj, "Bend"), (0.25, 0.5, 0.75)):
        assert np.abs(read_key(obj, name) - bd.interpolate(co, shown, faces, t)).max() < TOL, name
    obj["Bend.bdi"] = 1.0  # the playback ends where Blender shows the target
    obj.update_tag()
    assert np.abs(evaluated_co(obj) - shown).max() < TOL


def test_the_example_bakes_one_and_seven_objects(addon, tmp_path):
    """examples/cutout/bake_cutout.py, run as a user runs it (a fresh Blender, the add-on installed)."""
    script = os.path.join(ROOT, "examples", "cutout", "bake_cutout.py")
    proc = run_blender(["--python-exit-code", "1", "--python", script, "--", "--count", "5",
                        "--out", str(tmp_path)], env_drop=())
    found = json_lines(proc)[0]
    for case in ("one", "seven"):
        assert found[case]["bdi"] < JOINED, found
        # the linear blend carries a pin through both triangles alike (it blends the vertices)
        assert found[case]["linear"] < JOINED, found
        assert found[case]["arap"] > 0.05, found  # ARAP places each piece on its own
        assert os.path.isfile(os.path.join(str(tmp_path), "cutout_%s.blend" % case))


def test_the_panel_says_what_a_selection_bakes(addon, character):
    from test_ui import draw_all
    pieces, joints, size = character
    objs = cb.seven_objects(pieces)
    objs[0].bdi.target = cb.TARGET
    labels = [e[1] for e in draw_all(bpy.context) if e[0] == "label"]
    assert "Bakes 7 selected objects as one character (slider here)" in " ".join(labels)
    assert ("prop", "joints") in draw_all(bpy.context)  # Expert > Joints
    assert bpy.ops.bdinterp.bake() == {'FINISHED'}
    labels = [e[1] for e in draw_all(bpy.context) if e[0] == "label"]
    assert {"Objects: 7 (one character)", "Joints between pieces: 6"} <= set(labels)
    bpy.context.view_layer.objects.active = objs[-1]  # the hand's panel names the slider's owner
    objs[-1].bdi.target = cb.TARGET
    labels = " ".join(e[1] for e in draw_all(bpy.context) if e[0] == "label")
    assert "Played by the slider 'Pose.bdi' of 'Torso'" in labels


def test_live_mode_shows_the_layered_character_joined(addon, character):
    pieces, joints, size = character
    obj, ranges = cb.one_object(pieces)
    for factor in (0.3, 0.8):
        assert addon.set_live(obj, target=cb.TARGET, factor=factor) == "bdi.live"
        opening = cb.openings([obj], ranges, joints, size, ["bdi.live"])
        assert max(opening.values()) < JOINED, (factor, opening)
        X0 = read_key(obj, "Basis")
        assert np.abs(read_key(obj, "bdi.live")[:, 2] - X0[:, 2]).max() <= float32_step(X0), factor
    assert not obj.bdi.live_error


def test_a_folded_key_is_reported_with_its_object(addon, character):
    pieces, joints, size = character
    hand = pieces[-1]
    assert hand.name == "Hand" and len(hand.source) == 15  # 3 x 5 vertices: 7 is the middle one
    hand.target[7] += 1.6 * (hand.target[8] - hand.target[7])  # pushed past its row's end
    objs = cb.seven_objects(pieces)
    result = addon.bake(objs, target=cb.TARGET, count=3)
    found = re.search(r"key 'Pose' has (\d+) folded polygons? near vertex (\d+) of 'Hand'",
                      result.note)
    assert found, result.note
    around = [i for i, f in enumerate(hand.polygons) if 7 in f]  # the quads around vertex 7
    assert 1 <= int(found.group(1)) <= len(around) == 4
