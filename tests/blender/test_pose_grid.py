"""Pose grids: parameters set up by the API, keyframed, driven by a bone, followed live; missing
nodes refused with nothing changed; fill; undo of the setup."""

import itertools
import math
import os

import bpy
import numpy as np
import pytest

from conftest import add_key, evaluated_co, fcurve, grid, key_names, mesh_object, read_key, triangles

BENDS, THICKS = (-60, 0, 60), (-1, 0, 1)


def posed(V, bend, thick):
    """The strip [0, 2] x [0, 0.4] thickened by 1 + 0.25 thick, bent by `bend` degrees."""
    y = (V[:, 1] - 0.2) * (1 + 0.25 * thick)
    a = math.radians(bend)
    if a == 0:
        return np.c_[V[:, 0], y + 0.2, V[:, 2]]
    r0 = 2.0 / a
    r = r0 - y
    return np.c_[r * np.sin(V[:, 0] / r0), 0.2 + r0 - r * np.cos(V[:, 0] / r0), V[:, 2]]


def strip(skip=()):
    verts, quads = grid(16, 4, 2.0, 0.4)
    obj = mesh_object("Strip", verts, quads)
    obj.shape_key_add(name="Basis", from_mix=False)
    keys = {}
    for b, t in itertools.product(BENDS, THICKS):
        if (b, t) in skip:
            continue
        keys[(b, t)] = "Basis" if (b, t) == (0, 0) else "B%d_T%d" % (b, t)
        if (b, t) != (0, 0):
            add_key(obj, keys[(b, t)], posed(verts, b, t))
    return obj, keys


def hand_weights(keys, bend, thick):
    """Bilinear weights on the names of the cell's corners, computed here from the node values."""
    def cell(values, x):
        x = min(max(x, values[0]), values[-1])
        i = min(np.searchsorted(values, x, side="right") - 1, len(values) - 2)
        return i, (x - values[i]) / (values[i + 1] - values[i])
    (i, s), (j, t) = cell(BENDS, bend), cell(THICKS, thick)
    out = {}
    for di, dj, w in ((0, 0, (1 - s) * (1 - t)), (1, 0, s * (1 - t)), (0, 1, (1 - s) * t), (1, 1, s * t)):
        name = keys[(BENDS[i + di], THICKS[j + dj])]
        out[name] = out.get(name, 0.0) + w
    return out


def expected(bd, obj, keys, bend, thick):
    w = hand_weights(keys, bend, thick)
    names = ["Basis"] + [n for n in w if n != "Basis"]
    shapes = [read_key(obj, n) for n in names]
    return bd.blend(shapes, triangles(obj), [w.get(n, 0.0) for n in names])


def armature():
    """A rig with the bone 'Neck' (examples/face's)."""
    import sys
    from conftest import ROOT
    sys.path.insert(0, os.path.join(ROOT, "examples", "face"))
    import face_blender
    return face_blender.neck_rig()


def test_grid_keyframed_and_driven_by_a_bone(addon, bd):
    obj, keys = strip()
    paths = addon.pose_grid(obj, params={"bend": list(BENDS), "thick": list(THICKS)}, keys=keys,
                            name="head")
    assert paths == {"bend": 'bdi_grids["head"].params["bend"].amount',
                     "thick": 'bdi_grids["head"].params["thick"].amount'}
    size = np.linalg.norm(np.ptp(read_key(obj, "Basis"), axis=0))
    for frame, value in ((1, -60.0), (11, 50.0)):
        obj.path_resolve(paths["bend"].rsplit(".", 1)[0]).amount = value
        obj.keyframe_insert(paths["bend"], frame=frame)
    arm = armature()
    addon.drive_by_bone(obj, "head", "thick", arm, "Neck", axis="Z", angles=(-45, 45))
    # the F-curve has the path as given (Blender 3.4) or by index (4.3+: bdi_grids[0].params[0])
    item = obj.bdi_grids["head"].params["bend"]
    curve = fcurve(obj.animation_data, paths["bend"]) or \
        fcurve(obj.animation_data, item.path_from_id("amount"))
    for frame, degrees in ((1, 0.0), (4, 20.0), (8, -70.0), (11, 30.0)):
        arm.pose.bones["Neck"].rotation_euler.z = math.radians(degrees)
        bpy.context.scene.frame_set(frame)
        bend, thick = curve.evaluate(frame), -1 + (degrees + 45) / 90 * 2
        got = evaluated_co(obj)
        assert np.abs(got - expected(bd, obj, keys, bend, thick)).max() <= 1e-6 * size, frame
    assert not obj.bdi_grid_error


def test_script_sets_a_parameter_by_its_path(addon, bd):
    obj, keys = strip()
    paths = addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    # a new grid starts at its rest node (the reference key's), showing the rest pose
    assert [p.amount for p in obj.bdi_grids["head"].params] == [0.0, 0.0]
    assert np.abs(evaluated_co(obj) - read_key(obj, "Basis")).max() <= 1e-6
    item = obj.path_resolve(paths["thick"].rsplit(".", 1)[0])
    item.amount = 0.5
    obj.bdi_grids["head"].params["bend"].amount = -25.0
    size = np.linalg.norm(np.ptp(read_key(obj, "Basis"), axis=0))
    assert np.abs(evaluated_co(obj) - expected(bd, obj, keys, -25, 0.5)).max() <= 1e-6 * size
    # clamped outside the grid: the corner pose itself
    item.amount = 7.0
    obj.bdi_grids["head"].params["bend"].amount = 99.0
    assert np.abs(evaluated_co(obj) - read_key(obj, "B60_T1")).max() <= 1e-6 * size


def test_missing_node_refused_with_nothing_changed(addon):
    obj, keys = strip(skip={(60, 1)})
    before = key_names(obj)
    with pytest.raises(addon.BakeError, match=r"node \(bend=60, thick=1\) has no shape key"):
        addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    keys[(60, 1)] = "No such key"
    with pytest.raises(addon.BakeError, match="names the shape key 'No such key'"):
        addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    assert key_names(obj) == before and len(obj.bdi_grids) == 0


def test_an_object_in_live_mode_is_refused(addon):
    obj, keys = strip()
    addon.set_live(obj, target="B60_T0", factor=0.5)
    before = key_names(obj)
    with pytest.raises(addon.BakeError, match="Strip is in live mode: switch that off first"):
        addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    assert key_names(obj) == before and len(obj.bdi_grids) == 0


def test_fill_makes_the_missing_node_and_reports_it(addon, bd):
    obj, keys = strip(skip={(60, 0)})
    addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head", fill=True)
    made = "head(bend=60, thick=0)"
    assert made in key_names(obj) and made in obj.bdi_grids["head"].made
    # made from its column neighbours (60, -1) and (60, 1): the core's blend of those halves
    want = bd.blend([read_key(obj, n) for n in ("Basis", "B60_T-1", "B60_T1")], triangles(obj),
                    [0.0, 0.5, 0.5])
    assert np.abs(read_key(obj, made) - want).max() <= 1e-6


def test_undo_removes_the_setup(addon):
    obj, keys = strip()
    before = key_names(obj)
    bpy.ops.ed.undo_push(message="before grid")
    addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    bpy.ops.ed.undo_push(message="grid")
    assert len(obj.bdi_grids) == 1 and "bdi.pose" in key_names(obj)
    bpy.ops.ed.undo()
    obj = bpy.data.objects["Strip"]
    assert len(obj.bdi_grids) == 0 and key_names(obj) == before


def test_two_groups_and_a_wrap_on_two_objects(addon, bd):
    obj, keys = strip()
    other, _ = strip()
    wide = read_key(obj, "Basis") * [1.0, 1.5, 1.0]
    for o in (obj, other):
        add_key(o, "Wide", wide)
        add_key(o, "Turn90", posed(read_key(obj, "Basis"), 40, 0))
        add_key(o, "Turn180", posed(read_key(obj, "Basis"), 0, -1))
        add_key(o, "Turn270", posed(read_key(obj, "Basis"), -40, 0))
    addon.pose_grid([obj, other], {"open": [0, 1]}, {0: "Basis", 1: "Wide"}, name="mouth")
    addon.pose_grid(obj, {"turn": {"values": [0, 90, 180, 270], "wrap": True}},
                    {0: "Basis", 90: "Turn90", 180: "Turn180", 270: "Turn270"}, name="body")
    obj.bdi_grids["mouth"].params["open"].amount = 0.5
    obj.bdi_grids["body"].params["turn"].amount = 315.0  # half way from 270 back to 0 (360)
    names = ["Basis", "Wide", "Turn270"]
    # each group's difference from the rest added: Basis -1 + (0.5 + 0.5), Wide 0.5, Turn270 0.5
    want = bd.blend([read_key(obj, n) for n in names], triangles(obj), [0.0, 0.5, 0.5])
    size = np.linalg.norm(np.ptp(read_key(obj, "Basis"), axis=0))
    assert np.abs(evaluated_co(obj) - want).max() <= 1e-6 * size
    assert addon.pose_grid_report(obj)[obj.name].startswith("convex blend: K <= ")  # Basis 0
    obj.bdi_grids["mouth"].params["open"].amount = 1.0  # Basis -1 + (0 + 0.5): an extrapolation
    want = bd.blend([read_key(obj, n) for n in names], triangles(obj), [-0.5, 1.0, 0.5])
    assert np.abs(evaluated_co(obj) - want).max() <= 1e-6 * size
    report = addon.pose_grid_report(obj)
    assert report[obj.name].startswith("extrapolated blend: worst K") and "0 flipped" in report[obj.name]
    assert report[other.name].startswith("convex blend: K <= ")  # the mouth alone
    obj.bdi_grids["mouth"].params["open"].amount = 0.5
    with pytest.raises(addon.BakeError, match="Strip has pose grids: remove them first"):
        addon.set_live(obj, target="Wide", factor=0.5)
    # the other object follows the first one's mouth only
    want = bd.blend([read_key(other, n) for n in names[:2]], triangles(other), [0.5, 0.5])
    assert np.abs(evaluated_co(other) - want).max() <= 1e-6 * size


def test_bake_grid_plays_linearly_within_its_error(addon, bd):
    obj, keys = strip()
    addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    written, error = addon.bake_grid(obj, "head", n=2)
    assert len(written) == 25 and 0 < error < 0.05
    drivers = obj.data.shape_keys.animation_data.drivers
    assert len(drivers) == 25 and all(fc.driver.is_simple_expression for fc in drivers)
    size = np.linalg.norm(np.ptp(read_key(obj, "Basis"), axis=0))
    params = obj.bdi_grids["head"].params
    params["bend"].amount, params["thick"].amount = -45.0, 0.5  # mid-way between fine nodes 0 and 1
    got = evaluated_co(obj)
    # the keys' linear blend, by hand: bend -45 lies half way from fine node 0 (-60) to 1 (-30),
    # thick 0.5 is fine node 3
    want = 0.5 * read_key(obj, "head.bake.0_3") + 0.5 * read_key(obj, "head.bake.1_3")
    assert np.abs(got - want).max() <= 1e-6 * size
    exact = expected(bd, obj, keys, -45.0, 0.5)
    assert np.linalg.norm(got - exact, axis=1).max() <= error * size * (1 + 1e-4) + 1e-6 * size
    _, coarse = addon.bake_grid(obj, "head", n=1)
    assert coarse > 2 * error  # the runtime's blend of the grid's own poses is worse


def test_grid_renders_with_blender_b_a(addon, bd, tmp_path):
    """`blender -b file.blend -a` renders the grid's blend of each frame: the frames equal renders
    of a plain file holding the expected shapes as keyframed shape keys."""
    from conftest import fcurves
    from test_live import reference_file, render_pair, render_scene
    tmp = str(tmp_path)
    obj, keys = strip()
    render_scene(obj)
    bpy.data.objects["Cam"].location = (1.0, 0.5, 5.0)
    paths = addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    bends = {1: -50.0, 2: -5.0, 3: 40.0}
    for frame in (1, 3):
        obj.bdi_grids["head"].params["bend"].amount = bends[frame]
        obj.keyframe_insert(paths["bend"], frame=frame)
    for fc in fcurves(obj.animation_data):
        for kp in fc.keyframe_points:
            kp.interpolation = 'LINEAR'
    bpy.context.scene.frame_set(1)
    grid_path = os.path.join(tmp, "grid.blend")
    bpy.ops.wm.save_as_mainfile(filepath=grid_path)
    addon.remove_pose_grid(obj, "head")  # the reference: the expected shapes as plain keys
    ref_path = reference_file(obj, {f: expected(bd, obj, keys, b, 0.0) for f, b in bends.items()},
                              tmp)
    render_pair(tmp, grid_path, ref_path, "pose grid of", differ=0.01)


def test_follows_an_edited_input_key(addon, bd):
    obj, keys = strip()
    addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    params = obj.bdi_grids["head"].params
    params["bend"].amount, params["thick"].amount = 30.0, 0.0
    evaluated_co(obj)
    kb = obj.data.shape_keys.key_blocks["B60_T0"]
    kb.data.foreach_set("co", (read_key(obj, "B60_T0") * [1.0, 1.2, 1.0]).astype(np.float32).ravel())
    obj.data.shape_keys.update_tag()
    size = np.linalg.norm(np.ptp(read_key(obj, "Basis"), axis=0))
    assert np.abs(evaluated_co(obj) - expected(bd, obj, keys, 30.0, 0.0)).max() <= 1e-6 * size


def test_face_example_combines_its_groups(addon, bd):
    """examples/face: three grids on six layered pieces; a mouth opened on a turned head and a
    turned body is the core's blend of the three groups' differences from the rest."""
    import sys
    from conftest import ROOT
    sys.path.insert(0, os.path.join(ROOT, "examples", "face"))
    import face_blender
    obj, paths = face_blender.build()
    assert paths["body"] == {"turn": 'bdi_grids["body"].params["turn"].amount'}
    grids = obj.bdi_grids
    grids["head"].params["angle_x"].amount = 20.0
    grids["mouth"].params["open"].amount = 1.0
    grids["body"].params["turn"].amount = -45.0  # = 315: half way from 270 back to 0
    bpy.data.objects["Rig"].pose.bones["Neck"].rotation_euler.z = math.radians(-15)  # angle_y 15
    bpy.context.scene.frame_set(1)
    # by hand: head (20, 15): 2/3 x 1/2 of each corner of the cell (0..30) x (0..30); then each
    # group's difference from the rest: Basis loses 1 per extra group
    w = {"Basis": 1 / 6 - 2.0, "Head_+30_+0": 1 / 3, "Head_+0_+30": 1 / 6, "Head_+30_+30": 1 / 3,
         "Mouth_open": 1.0, "Body_270": 0.5}
    w["Basis"] += 0.5  # body's half at its rest node (0)
    import face_rig
    from bdinterp_blender.shapes import solve
    from bdinterp_blender.shapes.settings import BakeSettings
    # the core's blend of every pose of the grids, these weights and zero elsewhere (the joints'
    # roots are found from all the poses), with the keys as the add-on hands them over: each piece
    # in its layer's plane, joined by the joints found for them
    names = ["Basis"] + [n for n in face_rig.poses()[0] if n != "Basis"]
    inp = solve.Inputs(obj, BakeSettings(), names[1:])
    want = bd.Interpolator(inp.shapes, inp.faces, base=0, joints=inp.joints,
                           layers=inp.layers).blend([w.get(n, 0.0) for n in names])
    size = np.linalg.norm(np.ptp(read_key(obj, "Basis"), axis=0))
    assert np.abs(evaluated_co(obj) - want).max() <= 1e-6 * size
    assert not obj.bdi_grid_error


def test_panel_operator_sets_up_and_refuses(addon):
    obj, keys = strip()
    spec = "; ".join("%d, %d: %s" % (b, t, name) for (b, t), name in keys.items())
    bpy.ops.ed.undo_push(message="before")
    assert bpy.ops.bdinterp.pose_grid_add(name="head", params="bend = -60, 0, 60; thick = -1, 0, 1",
                                          keys=spec) == {'FINISHED'}
    assert [p.name for p in obj.bdi_grids["head"].params] == ["bend", "thick"]
    before = key_names(obj)
    spec_missing = spec.replace("60, 1: B60_T1", "60, 1: Nope")
    with pytest.raises(RuntimeError, match="names the shape key 'Nope'"):  # reported as an error
        bpy.ops.bdinterp.pose_grid_add(name="other", params="bend = -60, 0, 60; thick = -1, 0, 1",
                                       keys=spec_missing)
    assert key_names(obj) == before and len(obj.bdi_grids) == 1
    assert bpy.ops.bdinterp.pose_grid_add(name="turn", params="turn = 0, 180 wrap",
                                          keys="0: Basis; 180: B60_T0") == {'FINISHED'}
    assert obj.bdi_grids["turn"].params["turn"].wrap


def test_drive_by_bone_and_bake_grid_operators(addon):
    obj, keys = strip()
    addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    arm = armature()
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.bdinterp.pose_grid_bone(grid="head", param="bend", armature=arm.name, bone="Neck",
                                           axis='Z', angle0=-30.0, angle1=30.0) == {'FINISHED'}
    arm.pose.bones["Neck"].rotation_euler.z = math.radians(15)  # 3/4 of the way: bend 30
    bpy.context.scene.frame_set(1)
    assert obj.evaluated_get(bpy.context.evaluated_depsgraph_get()) \
        .bdi_grids["head"].params["bend"].amount == pytest.approx(30.0)
    with pytest.raises(RuntimeError, match="no bone 'Nope'"):
        bpy.ops.bdinterp.pose_grid_bone(grid="head", param="thick", armature=arm.name, bone="Nope")
    assert bpy.ops.bdinterp.pose_grid_bake(name="head", n=1) == {'FINISHED'}
    assert len([n for n in key_names(obj) if n.startswith("head.bake.")]) == 9


def test_undo_of_a_parameter_change_updates_the_mesh(addon, bd):
    obj, keys = strip()
    addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    obj.bdi_grids["head"].params["bend"].amount = 30.0
    bpy.ops.ed.undo_push(message="bend 30")
    obj.bdi_grids["head"].params["bend"].amount = -50.0
    bpy.ops.ed.undo_push(message="bend -50")
    bpy.ops.ed.undo()
    obj = bpy.data.objects["Strip"]
    assert obj.bdi_grids["head"].params["bend"].amount == 30.0
    size = np.linalg.norm(np.ptp(read_key(obj, "Basis"), axis=0))
    assert np.abs(evaluated_co(obj) - expected(bd, obj, keys, 30.0, 0.0)).max() <= 1e-6 * size


def test_a_handler_error_is_said_once_and_keeps_the_keys(addon, monkeypatch, capsys):
    import importlib
    grid_live = importlib.import_module(addon.__name__ + ".params.live")
    obj, keys = strip()
    addon.pose_grid(obj, {"bend": list(BENDS), "thick": list(THICKS)}, keys, name="head")
    obj.bdi_grids["head"].params["bend"].amount = 20.0
    before = read_key(obj, "bdi.pose")
    capsys.readouterr()

    def failing(*_args):
        raise TypeError("injected")
    monkeypatch.setattr(grid_live, "compute", failing)
    obj.bdi_grids["head"].params["bend"].amount = 40.0  # the property's update fails: said once
    for frame in (2, 3, 4):
        bpy.context.scene.frame_set(frame)
    assert capsys.readouterr().out.count("pose grid of Strip stopped: TypeError: injected") == 1
    assert np.array_equal(read_key(obj, "bdi.pose"), before)
