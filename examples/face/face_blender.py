"""examples/face in Blender: the cut-out face as one object of six layered pieces, its poses as
shape keys and three pose grids (head: angle_x x angle_y; mouth: open; body: turn, wrapping),
the head's angle_y driven by a bone of a small rig ("Drive by Bone").

    blender --background --factory-startup --addons bdinterp_blender \
        --python examples/face/face_blender.py [-- out.blend]
"""

import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import face_rig  # noqa: E402


def face_object(name="Face"):
    """The face as one mesh object with a shape key per pose (Basis: the rest)."""
    shapes, faces, groups = face_rig.poses()
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in shapes["Basis"]], [], [tuple(int(i) for i in f) for f in faces])
    me.update()
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    obj.shape_key_add(name="Basis", from_mix=False)
    for key, co in shapes.items():
        if key != "Basis":
            kb = obj.shape_key_add(name=key, from_mix=False)
            kb.value = 0.0
            kb.data.foreach_set("co", np.asarray(co, dtype=np.float32).ravel())
    return obj, groups


def neck_rig():
    arm = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(arm)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode='EDIT')
    bone = arm.data.edit_bones.new("Neck")
    bone.head, bone.tail = (0.0, 0.25, 0.0), (0.0, 1.2, 0.0)
    bpy.ops.object.mode_set(mode='OBJECT')
    arm.pose.bones["Neck"].rotation_mode = 'XYZ'
    return arm


def build():
    """The face with its grids; returns (object, {group: {parameter: data path}})."""
    import bdinterp_blender
    obj, groups = face_object()
    paths = {name: bdinterp_blender.pose_grid(obj, params, keys, name=name)
             for name, (params, keys) in groups.items()}
    bdinterp_blender.drive_by_bone(obj, "head", "angle_y", neck_rig(), "Neck", axis="Z",
                                   angles=(30.0, -30.0))
    return obj, paths


if __name__ == "__main__":
    face, data_paths = build()
    for group, params in data_paths.items():
        print(group, params)
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if argv:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(argv[0]))
