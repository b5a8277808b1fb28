"""The whole FK biped of tests/python/biped.py posed by Blender's own armature: 17 pieces, one
object each, moved by an Armature modifier through a vertex group named after its bone, or
parented to their bones; the root and the hip bones carry no sprite and the poses translate them
(the hip slides under the torso, the root travels in the run, the jump and the fall). Each pose
applied as a key 'Pose' and baked with the joints found from the keys ('pins') and taken from the
bones ('bones'): every in-between against the armature's own (every bone's angle and location
blended by t), within 0.5 % of the size; in the fall with pins, after the best rigid fit of the
whole character (1.5 % without it: two keys do not fix the path of a root that travels)."""
import math
import os
import sys

import bpy
import mathutils
import numpy as np
import pytest

from conftest import ROOT, add_key, bone_pieces, new_armature, world

sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
from biped import BONES, PIECES, POSES, rigid_fit_error  # noqa: E402
from cutout_meshes import rectangle  # noqa: E402

TS = (0.25, 0.5, 0.75)
RIG_AT = (0.4, -0.3, 0.2)  # the armature object away from the origin


def armature():
    """Every bone from its pivot straight up (+Y, no roll): its local axes are the armature's, so
    a pose bone's location is its offset in its parent's frame and a turn about Z its angle."""
    return new_armature([(name, parent, pivot, (pivot[0], pivot[1] + 0.5))
                         for name, (parent, pivot, _) in BONES.items()], RIG_AT)


def pieces(arm, parented=False):
    """One object per piece, moved by its bone (conftest.bone_pieces)."""
    return bone_pieces(arm, [(name, rectangle(*BONES[name][2], 0.12, seed=k)) for k, name in enumerate(PIECES)],
                       parented)


def pose(arm, angles, t):
    """Every bone turned by t x its angle about Z and moved by t x its offset."""
    for pb in arm.pose.bones:
        value = angles.get(pb.name, 0.0)
        angle, (dx, dy) = value if isinstance(value, tuple) else (value, (0.0, 0.0))
        pb.rotation_mode = 'QUATERNION'
        pb.rotation_quaternion = mathutils.Quaternion((0, 0, 1), math.radians(t * angle))
        pb.location = (t * dx, t * dy, 0.0)
    bpy.context.view_layer.update()


def character(angles, parented):
    """(armature, objects, size): the pose applied as each object's key 'Pose'."""
    arm = armature()
    objs = pieces(arm, parented)
    size = float(np.linalg.norm(np.ptp(world(objs), axis=0)))
    pose(arm, angles, 1.0)
    posed = [world([obj]) for obj in objs]
    pose(arm, angles, 0.0)
    for obj, X in zip(objs, posed):
        m = np.linalg.inv(np.array(obj.matrix_world))
        add_key(obj, "Pose", X @ m[:3, :3].T + m[:3, 3])
    return arm, objs, size


@pytest.mark.parametrize("parented", [False, True], ids=["modifier", "parented"])
@pytest.mark.parametrize("joints", ["pins", "bones"])
@pytest.mark.parametrize("name", list(POSES))
def test_biped_inbetweens_are_the_bones_own(addon, name, joints, parented):
    arm, objs, size = character(POSES[name], parented)
    inp, _, _, frames = addon.compute_frames(objs, "Pose", factors=list(TS), joints=joints)
    assert inp.joint_source == ("bones of 'Rig'" if joints == "bones" else "")
    for t, X in zip(TS, frames):
        pose(arm, POSES[name], t)
        Y = world(objs)  # the bones' own in-between
        pose(arm, POSES[name], 0.0)
        raw = np.linalg.norm(X - Y, axis=1).max() / size
        fitted = rigid_fit_error(X[:, :2], Y[:, :2]) / size
        print("biped %s %s %s t=%.2f raw %.3g%% fitted %.3g%%" % (name, joints, parented, t,
                                                                   100 * raw, 100 * fitted))
        if name == "fall" and joints == "pins":
            assert fitted < 5e-3 and raw < 1.5e-2, (t, raw, fitted)
        else:
            assert raw < 5e-3, (t, raw)
