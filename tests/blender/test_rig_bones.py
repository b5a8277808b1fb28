"""A cut-out character posed by Blender's own armature: eleven pieces (one object each, or one
object), each moved by an Armature modifier through a vertex group named after its bone, the limbs
and the tail overlapping the torso and each other; its pose applied as a shape key. Baked with the
joints found from the keys ('pins') and taken from the bones ('bones', and 'auto'), every
in-between is the armature's own (every bone turned by t times its angle) within 0.5 % of the
size, and the still pieces do not move (1e-6 of the size)."""
import math
import os
import sys

import bpy
import mathutils
import numpy as np
import pytest

from conftest import ROOT, add_key, bone_pieces, new_armature, world

sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
from cutout_meshes import rectangle  # noqa: E402
from fk_rig import NAMES, POSES, RIG  # noqa: E402

TS = (0.25, 0.5, 0.75)
RIG_AT = (0.7, -0.4, 0.3)  # the armature object away from the origin: its space is not the world's


def armature():
    """The bones: each from its pin (the root: from the torso's centre) towards its piece's centre."""
    bones = []
    for name in NAMES:
        (x0, y0, w, h), parent, pin = RIG[name]
        centre = np.array([x0 + w / 2, y0 + h / 2])
        head = np.array(pin) if pin else centre
        tail = centre if np.linalg.norm(centre - head) > 0.1 else head + [0.0, 0.5]
        bones.append((name, parent, head, tail))
    return new_armature(bones, RIG_AT)


def pieces(arm, parented=False):
    """One object per piece, moved by its bone (conftest.bone_pieces)."""
    return bone_pieces(arm, [(name, rectangle(*RIG[name][0], 0.2, seed=k)) for k, name in enumerate(NAMES)],
                       parented)


def pose(arm, angles, t):
    """Every bone turned by t x its angle about the view axis (the armature's Z)."""
    for pb in arm.pose.bones:
        axis = pb.bone.matrix_local.to_3x3().inverted() @ mathutils.Vector((0, 0, 1))
        pb.rotation_mode = 'QUATERNION'
        pb.rotation_quaternion = mathutils.Quaternion(axis, math.radians(t * angles.get(pb.name, 0.0)))
    bpy.context.view_layer.update()


def character(angles, one_object=False, more=None, parented=False):
    """(armature, objects, rest (n, 3), size): the pose applied as each object's key 'Pose' (and
    more: {key name: angles} as further keys); parented: the pose's world positions brought into
    each object's rest coordinates."""
    arm = armature()
    objs = pieces(arm, parented)
    rest = world(objs)
    for key, a in {"Pose": angles, **(more or {})}.items():
        pose(arm, a, 1.0)
        posed = [world([obj]) for obj in objs]
        pose(arm, a, 0.0)
        for obj, X in zip(objs, posed):
            m = np.linalg.inv(np.array(obj.matrix_world))
            co = X @ m[:3, :3].T + m[:3, 3]
            add_key(obj, key, co)
    if one_object:
        bpy.ops.object.select_all(action='DESELECT')
        for obj in objs:
            obj.select_set(True)
        bpy.context.view_layer.objects.active = objs[0]
        bpy.ops.object.join()
        objs = [objs[0]]
    return arm, objs, rest, float(np.linalg.norm(np.ptp(rest, axis=0)))


@pytest.mark.parametrize("one_object", [False, True], ids=["pieces", "one object"])
@pytest.mark.parametrize("joints", ["pins", "bones"])
@pytest.mark.parametrize("name", list(POSES))
def test_inbetweens_are_the_bones_own(addon, name, joints, one_object):
    arm, objs, rest, size = character(POSES[name], one_object)
    inp, _, ts, frames = addon.compute_frames(objs, "Pose", factors=list(TS), joints=joints)
    assert inp.joint_source == ("bones of 'Rig'" if joints == "bones" else "")
    assert list(ts) == list(TS)
    for t, X in zip(TS, frames):
        pose(arm, POSES[name], t)
        err = np.linalg.norm(X - world(objs), axis=1).max() / size
        assert err < 5e-3, (t, err)


@pytest.mark.parametrize("joints", ["pins", "bones"])
def test_from_one_pose_to_another(addon, joints):
    # the source key is not the rest pose: the bones' pins are carried into it by their pieces
    a, b = POSES["limbs_out"], POSES["hand_crosses_body"]
    arm, objs, rest, size = character(a, more={"Across": b})
    inp, _, _, frames = addon.compute_frames(objs, "Across", source="Pose", factors=list(TS),
                                             joints=joints)
    assert inp.joint_source == ("bones of 'Rig'" if joints == "bones" else "")
    for t, X in zip(TS, frames):
        pose(arm, {n: (1 - t) * a.get(n, 0.0) + t * b.get(n, 0.0) for n in NAMES}, 1.0)
        err = np.linalg.norm(X - world(objs), axis=1).max() / size
        assert err < 5e-3, (t, err)


@pytest.mark.parametrize("joints", ["pins", "bones"])
def test_still_pieces_stay_still(addon, joints):
    # the torso and the left arm do not move between the keys: in no in-between either
    angles = {k: v for k, v in POSES["limbs_out"].items() if not k.endswith("_l")}
    arm, objs, rest, size = character(angles)
    inp, _, _, frames = addon.compute_frames(objs, "Pose", factors=list(TS), joints=joints)
    still = [i for i, n in enumerate(NAMES) if n == "torso" or n.endswith("_l")]
    for X in frames:
        for i in still:
            a, b = inp.offsets[i], inp.offsets[i + 1]
            assert np.abs(X[a:b] - rest[a:b]).max() / size < 1e-6, NAMES[i]


def test_pieces_parented_to_bones(addon):
    arm, objs, rest, size = character(POSES["hand_crosses_body"], parented=True)
    inp, _, _, frames = addon.compute_frames(objs, "Pose", factors=list(TS), joints="bones")
    assert inp.joint_source == "bones of 'Rig'"
    for t, X in zip(TS, frames):
        pose(arm, POSES["hand_crosses_body"], t)
        posed = world(objs)  # the bones' own in-between, brought into the rest pose's world
        pose(arm, POSES["hand_crosses_body"], 0.0)
        err = np.linalg.norm(X - posed, axis=1).max() / size
        assert err < 5e-3, (t, err)


def test_auto_takes_the_bones_and_says_so(addon):
    arm, objs, rest, size = character(POSES["limbs_out"])
    result = addon.bake(objs, target="Pose", count=3)
    assert result.joints == len(NAMES) - 1
    assert result.joint_source == "bones of 'Rig'"
    assert "10 joints between pieces (bones of 'Rig')" in result.message


def test_a_piece_without_a_bone(addon):
    # 'bones' names the piece and changes nothing; 'auto' falls back to the pins found from the keys
    arm, objs, rest, size = character(POSES["limbs_out"])
    hand = bpy.data.objects["hand_r"]
    hand.vertex_groups.clear()
    keys = {o.name: len(o.data.shape_keys.key_blocks) for o in objs}
    with pytest.raises(addon.BakeError, match="hand_r: the piece of vertex 0 has no bone"):
        addon.bake(objs, target="Pose", joints="bones")
    assert keys == {o.name: len(o.data.shape_keys.key_blocks) for o in objs}
    result = addon.bake(objs, target="Pose", joints="auto")
    assert result.joint_source == "" and result.joints == len(NAMES) - 1
    with pytest.raises(addon.BakeError, match="joints must be 'auto', 'bones', 'pins' or 'off'"):
        addon.bake(objs, target="Pose", joints="armature")
