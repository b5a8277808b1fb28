"""The batch script bakes a file's several-object character (objects sharing a parent and a
target key) as one character: one slider, joints kept, beside an object baked on its own."""

import os
import sys

import bpy

from conftest import ROOT, bent_strip
from test_batch import SCRIPT, blender

sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402


def test_batch_bakes_a_seven_object_character_as_one(addon, tmp_path):
    pieces, joints = cc.character()
    objs = cb.seven_objects(pieces)
    rig = bpy.data.objects.new("Rig", None)
    bpy.context.scene.collection.objects.link(rig)
    for obj in objs:  # the rig sits at the origin: world coordinates stay as they are
        obj.parent = rig
    bent_strip()  # no parent: baked on its own
    path = str(tmp_path / "character.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    proc = blender(["--background", "--factory-startup", "--python", SCRIPT, "--", path,
                    "--count", "5"], cwd=str(tmp_path))
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    names = sorted(p.name for p in pieces)
    lines = [l for l in proc.stdout.splitlines() if l.startswith("character.blend: ")]
    assert len(lines) == 2, lines
    assert lines[0].startswith("character.blend: %s: OK Basis -> Pose: 5 keys" % " + ".join(names))
    assert lines[1].startswith("character.blend: Strip: OK Basis -> Bend: 5 keys"), lines
    bpy.ops.wm.open_mainfile(filepath=path)
    objs = [bpy.data.objects[p.name] for p in pieces]
    from bdinterp_blender import playback
    owners = {playback.find(o, "Basis", cb.TARGET).record["owner"] for o in objs}
    assert owners == {names[0]}  # one slider, on the first by name
    assert sum("Pose.bdi" in o.keys() for o in objs) == 1
    size = cb.size_of(pieces)
    opening = cb.openings(objs, None, joints, size, cb.baked(objs[0]))
    assert max(opening.values()) < 1e-5, opening  # baked object by object, the elbow opens
