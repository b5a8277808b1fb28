"""A newcomer's character (examples/sprites/character.ora, ten pieces): Add Pose puts one key on
every piece, the torn-joint check names the joint a pose pulls apart and how far, and a bake of the
character goes stale on every member and on the slider's owner when any member's keys change,
until Bake Again."""

import math
import os

import bpy
import numpy as np
import pytest

from conftest import ROOT, read_key

PAINTING = os.path.join(ROOT, "examples", "sprites", "character.ora")
SCALE = 0.01


@pytest.fixture
def pieces(addon):
    """The painting's ten pieces, selected, the torso active."""
    import bdinterp_blender
    objs = bdinterp_blender.import_layered(PAINTING, scale=SCALE)
    bpy.context.view_layer.objects.active = bpy.data.objects["torso"]
    return objs


def move(obj, key, change):
    """Set obj's key to change(world coordinates (n, 3)) of its reference key."""
    m = np.array(obj.matrix_world)
    co = read_key(obj, obj.data.shape_keys.reference_key.name) @ m[:3, :3].T + m[:3, 3]
    local = np.linalg.solve(m[:3, :3], (change(co) - m[:3, 3]).T).T
    obj.data.shape_keys.key_blocks[key].data.foreach_set("co", local.astype(np.float32).ravel())
    obj.data.update()


def turn(degrees, centre):
    """World coordinates turned in the picture's plane (XZ) about centre (canvas pixels)."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    x0, z0 = centre[0] * SCALE, -centre[1] * SCALE

    def change(co):
        out = co.copy()
        out[:, 0] = x0 + c * (co[:, 0] - x0) - s * (co[:, 2] - z0)
        out[:, 2] = z0 + s * (co[:, 0] - x0) + c * (co[:, 2] - z0)
        return out
    return change


SHOULDER = (150, 104)


def test_add_pose_puts_one_key_on_every_piece(pieces):
    assert bpy.ops.bdinterp.add_pose() == {'FINISHED'}
    for obj in pieces:
        names = [kb.name for kb in obj.data.shape_keys.key_blocks]
        assert names == ["Basis", "Pose"], obj.name
        assert obj.active_shape_key.name == "Pose" and obj.bdi.target == "Pose"
        assert obj.data.shape_keys.key_blocks["Pose"].value == 0.0  # the slider may drive it
        assert np.array_equal(read_key(obj, "Pose"), read_key(obj, "Basis"))
    assert bpy.ops.bdinterp.add_pose() == {'FINISHED'}  # the next pose gets a name of its own
    assert {o.bdi.target for o in pieces} == {"Pose 2"}
    assert all(len(o.data.shape_keys.key_blocks) == 3 for o in pieces)


def test_add_pose_refuses_a_taken_name_and_changes_nothing(pieces):
    import bdinterp_blender
    bdinterp_blender.add_pose(pieces[:1], "Wave")
    with pytest.raises(bdinterp_blender.BakeError, match=r"forearm_l already has a key 'Wave'"):
        bdinterp_blender.add_pose(pieces, "Wave")
    assert [o.data.shape_keys is None for o in pieces] == [False] + [True] * 9


def test_a_forearm_pulled_off_is_reported_with_its_joint_and_distance(pieces):
    import bdinterp_blender
    bdinterp_blender.add_pose(pieces)
    arm = [bpy.data.objects[n] for n in ("upper_arm_r", "forearm_r")]
    for obj in arm:  # the whole arm raised about the shoulder: every joint holds
        move(obj, "Pose", turn(40, SHOULDER))
    assert bdinterp_blender.torn_joints(pieces, "Pose") == []
    move(arm[1], "Pose", lambda co: turn(40, SHOULDER)(co) + [0.3, 0.0, 0.0])  # 30 px off
    torn = bdinterp_blender.torn_joints(pieces, "Pose")
    assert [(a, b) for a, b, _ in torn] == [("forearm_r", "upper_arm_r")]
    assert torn[0][2] == pytest.approx(0.3, rel=1e-3)
    result = bdinterp_blender.bake([pieces[6]] + pieces, "Pose", count=1)  # scripts still bake
    assert result.objects == 10


def baked(pieces):
    import bdinterp_blender
    bdinterp_blender.add_pose(pieces)
    for name in ("upper_arm_r", "forearm_r"):
        move(bpy.data.objects[name], "Pose", turn(40, SHOULDER))
    torso = bpy.data.objects["torso"]
    result = bdinterp_blender.bake([torso] + [o for o in pieces if o != torso], "Pose", count=1)
    return torso, result


def stale(obj):
    from bdinterp_blender.keys import playback
    found = playback.find(obj, "Basis", "Pose")
    return playback.stale_members(obj, found)


def test_a_members_edit_makes_the_bake_stale_on_every_member_until_bake_again(pieces):
    torso, result = baked(pieces)
    assert result.slider == "Pose.bdi" and all(stale(o) == [] for o in pieces), result.keys
    arm = bpy.data.objects["upper_arm_r"]
    move(arm, "Pose", turn(50, SHOULDER))  # a member's target edited
    assert stale(torso) == ["upper_arm_r"]  # on the slider's owner
    assert all(stale(o) == ["upper_arm_r"] for o in pieces)  # and on every member
    before = read_key(arm, "Pose.bdi.050")
    assert bpy.ops.bdinterp.rebake(owner="torso", slider="Pose.bdi") == {'FINISHED'}
    assert all(stale(o) == [] for o in pieces)
    assert np.abs(read_key(arm, "Pose.bdi.050") - before).max() > 0.01  # baked from the new pose


def test_a_members_source_or_topology_edit_makes_it_stale_too(pieces):
    torso, _ = baked(pieces)
    head = bpy.data.objects["head"]
    head.data.shape_keys.key_blocks["Basis"].data[0].co.x += 0.05  # a still piece's source
    assert stale(torso) == ["head"]
    bpy.ops.bdinterp.rebake(owner="torso", slider="Pose.bdi")
    assert stale(torso) == []
    shin = bpy.data.objects["shin_l"]
    shin.data.polygons.foreach_set("vertices", np.roll(np.array([v for p in shin.data.polygons
                                                                 for v in p.vertices]), 1))
    shin.data.update()
    assert stale(torso) == ["shin_l"]


def panel_text(obj):
    """The sidebar's labels (wrapped lines joined) and operators with obj active."""
    import test_ui
    bpy.context.view_layer.objects.active = obj
    log = test_ui.draw_all(bpy.context)
    return " ".join(e[1] for e in log if e[0] == "label"), [e[1] for e in log if e[0] == "operator"]


def test_the_panel_says_stale_on_the_owner_and_a_member_with_bake_again(pieces):
    torso, _ = baked(pieces)
    for obj in (torso, bpy.data.objects["head"]):
        text, ops = panel_text(obj)
        assert "Stale" not in text and "bdinterp.rebake" not in ops
    move(bpy.data.objects["forearm_r"], "Pose", turn(45, SHOULDER))
    for obj in (torso, bpy.data.objects["head"]):
        text, ops = panel_text(obj)
        assert "Stale: the keys of 'forearm_r' changed after this bake" in text, text
        assert "bdinterp.rebake" in ops


def test_the_panel_shows_progress_while_a_bake_runs_and_a_deleted_key(pieces):
    from bdinterp_blender.ui import operators
    torso, _ = baked(pieces)
    operators.PROGRESS["bake"] = (3, 10)
    try:
        text, ops = panel_text(torso)
    finally:
        operators.PROGRESS["bake"] = None
    assert "Baking 3 of 10 (Esc to cancel)" in text and "bdinterp.bake" not in ops
    torso.shape_key_remove(torso.data.shape_keys.key_blocks["Pose.bdi.050"])
    text, ops = panel_text(torso)
    assert "Keys written: 1 1 of them deleted since (Pose.bdi.050): bake again" in text, text
    assert "bdinterp.bake" in ops
