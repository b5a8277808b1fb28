"""See and correct the joints: the biped of test_biped.py (one object per piece) with a joint parent
set by hand (Object.bdi.joint_parent). In the run the joints found root the tree at the right
thigh, the torso hanging from it; the right thigh set to hang from the torso re-roots the tree at
the torso, as set. The overlay's plan (dots, lines, roots) is the solver's own joints and roots;
the parent survives save and reload; the biped still bakes within test_biped.py's tolerances."""
import os

import bpy
import numpy as np
import pytest

from conftest import world
from test_biped import POSES, TS, character, pose

def select(objs, active):
    for o in bpy.context.view_layer.objects:
        o.select_set(o in objs)
    bpy.context.view_layer.objects.active = active


def tree(solver, objs):
    """({child name: parent name}, [(root name, reason)]) of a solver's joints, pieces by object."""
    starts = np.cumsum([0] + [len(o.data.vertices) for o in objs])
    name = lambda v: objs[int(np.searchsorted(starts, v, side="right")) - 1].name  # noqa: E731
    return ({name(j["child"]): name(j["parent"]) for j in solver.joints()},
            sorted((name(r["piece"]), r["reason"]) for r in solver.joint_roots()))


def solve(addon, objs, joints):
    """(Inputs, its solver, frames at TS) as a bake of the objects computes them."""
    inp, _, _, frames = addon.compute_frames(objs, "Pose", factors=list(TS), joints=joints)
    return inp, inp.interpolator(), frames


def centres(objs):
    """vertex -> the mean of its object's vertices in the base key, world space (a piece each)."""
    X, starts = world(objs), np.cumsum([0] + [len(o.data.vertices) for o in objs])

    def centre(v):
        k = int(np.searchsorted(starts, v, side="right")) - 1
        return X[starts[k]:starts[k + 1]].mean(axis=0)
    return centre


@pytest.mark.parametrize("joints", ["pins", "bones"])
def test_a_parent_set_by_hand_changes_the_tree_and_survives_reload(addon, joints, tmp_path):
    arm, objs, size = character(POSES["run"], parented=False)
    by = {o.name: o for o in objs}
    _, solver, _ = solve(addon, objs, joints)
    parents, roots = tree(solver, objs)
    if joints == "pins":  # found: the run's tree is rooted at the right thigh
        assert roots == [("thigh_r", "turns")] and parents["torso"] == "thigh_r"
    else:  # the bones: the torso hangs from nothing, the thighs from it through the hip
        assert roots == [("torso", "path")] and parents["thigh_r"] == "torso"
    by["thigh_r"].bdi.joint_parent = by["torso"]
    by["hand_l"].bdi.joint_parent = by["torso"]  # a hand straight from the torso
    inp, solver, _ = solve(addon, objs, joints)
    assert inp.joint_source.endswith("2 set by hand")
    set_parents, set_roots = tree(solver, objs)
    assert set_parents["thigh_r"] == "torso" and set_parents["hand_l"] == "torso"
    assert set_roots == ([("torso", "given")] if joints == "pins" else [("torso", "path")])
    assert "torso" not in set_parents and len(set_parents) == len(objs) - 1
    assert {k: v for k, v in set_parents.items() if k not in ("thigh_r", "hand_l", "torso")} == \
        {k: v for k, v in parents.items() if k not in ("thigh_r", "hand_l", "torso")}
    names = [o.name for o in objs]
    path = os.path.join(str(tmp_path), "parents.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    objs = [bpy.data.objects[n] for n in names]
    assert objs[names.index("thigh_r")].bdi.joint_parent.name == "torso"
    assert objs[names.index("hand_l")].bdi.joint_parent.name == "torso"
    assert objs[names.index("shin_r")].bdi.joint_parent is None  # Automatic
    assert tree(solve(addon, objs, joints)[1], objs) == (set_parents, set_roots)


def test_a_parent_outside_the_character_or_in_a_cycle_is_refused(addon):
    arm, objs, size = character(POSES["walk"], parented=False)
    by = {o.name: o for o in objs}
    by["hand_l"].bdi.joint_parent = by["torso"]
    with pytest.raises(ValueError, match="hand_l: its joint parent 'torso' is not part of"):
        addon.compute_frames([by["hand_l"], by["fore_l"]], "Pose", joints="pins")
    by["torso"].bdi.joint_parent = by["hand_l"]
    with pytest.raises(ValueError, match="their joint parents make a cycle"):
        addon.compute_frames(objs, "Pose", joints="pins")


def test_the_overlay_plan_is_the_solvers_joints(addon):
    from bdinterp_blender.view import joint_view
    arm, objs, size = character(POSES["run"], parented=False)
    by = {o.name: o for o in objs}
    by["thigh_r"].bdi.joint_parent = by["torso"]
    objs[0].bdi.target, objs[0].bdi.joints = "Pose", 'PINS'
    select(objs, objs[0])
    scene = bpy.context.scene
    assert scene.bdi_view_joints is False  # off by default: nothing planned
    assert joint_view.current(bpy.context) == (None, "")
    scene.bdi_view_joints = True
    plan, error = joint_view.current(bpy.context)
    assert error == "" and plan is not None
    from bdinterp_blender.view import onion
    objs = onion.drawn_objects(bpy.context)  # the active object first, as a bake orders them
    assert len(objs) == 17 and objs[0].name == "torso"
    _, solver, _ = solve(addon, objs, "pins")  # the bake's own solver, made apart
    centre = centres(objs)
    starts = np.cumsum([0] + [len(o.data.vertices) for o in objs])
    joints = solver.joints()
    points = np.array([j["point"] for j in joints])
    assert len(joints) == 16 and len(plan["dots"]) == 16
    assert np.abs(plan["dots"] - points).max() < 1e-9 * size
    ends = np.array([[centre(j["parent"]), p, p, centre(j["child"])] for j, p in zip(joints, points)])
    assert np.abs(plan["lines"] - ends.reshape(-1, 3)).max() < 1e-6 * size
    roots = solver.joint_roots()
    assert [r["reason"] for r in roots] == ["given"]
    assert np.abs(plan["roots"] - np.array([centre(r["piece"]) for r in roots])).max() < 1e-6 * size
    assert np.abs(plan["roots"][0] - centre(starts[[o.name for o in objs].index("torso")])).max() < 1e-6 * size
    by["thigh_r"].bdi.joint_parent = None  # Automatic again: the plan follows
    plan, _ = joint_view.current(bpy.context)
    assert np.abs(plan["roots"][0] - centre(starts[[o.name for o in objs].index("thigh_r")])).max() < 1e-6 * size
    scene.bdi_view_joints = False


@pytest.mark.parametrize("joints", ["pins", "bones"])
@pytest.mark.parametrize("name", ["walk", "run"])
def test_the_biped_with_a_parent_set_by_hand_bakes_within_its_tolerances(addon, name, joints):
    arm, objs, size = character(POSES[name], parented=False)
    by = {o.name: o for o in objs}
    by["thigh_r"].bdi.joint_parent = by["torso"]
    inp, _, frames = solve(addon, objs, joints)
    assert "set by hand" in inp.joint_source
    for t, X in zip(TS, frames):
        pose(arm, POSES[name], t)
        Y = world(objs)
        pose(arm, POSES[name], 0.0)
        raw = np.linalg.norm(X - Y, axis=1).max() / size
        print("biped by hand %s %s t=%.2f raw %.3g%%" % (name, joints, t, 100 * raw))
        assert raw < 5e-3, (t, raw)
    result = addon.bake(objs, "Pose", factors=list(TS), joints=joints)
    assert "set by hand" in result.joint_source and result.joints == 16
