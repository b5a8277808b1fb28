"""The batch script, run directly or by the Flamenco job type, bakes a file's several-object
character (objects sharing a parent and a target key) as one character: one slider, joints kept,
beside an object baked on its own."""

import json
import os
import sys

import bpy

from conftest import ROOT, bent_strip
from test_batch import SCRIPT, blender, compile_job, run_task, worker_addon

sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402


def character_file(folder):
    """A .blend holding the seven-object character (parented to one rig) and a strip of its own;
    (its path, the character's pieces and joints)."""
    pieces, joints = cc.character()
    objs = cb.seven_objects(pieces)
    rig = bpy.data.objects.new("Rig", None)
    bpy.context.scene.collection.objects.link(rig)
    for obj in objs:  # the rig sits at the origin: world coordinates stay as they are
        obj.parent = rig
    bent_strip()  # no parent: baked on its own
    path = os.path.join(str(folder), "character.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path, pieces, joints


def check_lines(stdout, pieces, count):
    names = sorted(p.name for p in pieces)
    lines = [l for l in stdout.splitlines() if l.startswith("character.blend: ")]
    assert len(lines) == 2, lines
    assert lines[0].startswith("character.blend: %s: OK Basis -> Pose: %d keys"
                               % (" + ".join(names), count)), lines
    assert lines[1].startswith("character.blend: Strip: OK Basis -> Bend: %d keys" % count), lines


def check_baked_as_one(path, pieces, joints):
    """The file's seven objects carry one bake: one slider, on the first by name; joints closed."""
    bpy.ops.wm.open_mainfile(filepath=path)
    names = sorted(p.name for p in pieces)
    objs = [bpy.data.objects[p.name] for p in pieces]
    from bdinterp_blender.keys import playback
    owners = {playback.find(o, "Basis", cb.TARGET).record["owner"] for o in objs}
    assert owners == {names[0]}  # one slider, on the first by name
    assert sum("Pose.bdi" in o.keys() for o in objs) == 1
    size = cb.size_of(pieces)
    opening = cb.openings(objs, None, joints, size, cb.baked(objs[0]))
    assert max(opening.values()) < 1e-5, opening  # baked object by object, the elbow opens


def test_batch_bakes_a_seven_object_character_as_one(addon, tmp_path):
    path, pieces, joints = character_file(tmp_path)
    proc = blender(["--background", "--factory-startup", "--python", SCRIPT, "--", path,
                    "--count", "5"], cwd=str(tmp_path))
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    check_lines(proc.stdout, pieces, 5)
    check_baked_as_one(path, pieces, joints)


def test_flamenco_job_bakes_a_seven_object_character_as_one(addon, tmp_path):
    tmp = str(tmp_path)
    farm = os.path.join(tmp, "farm")
    os.makedirs(os.path.join(farm, "summaries"))
    path, pieces, joints = character_file(farm)
    addon_dir, env_drop = worker_addon(farm)
    job = compile_job({"blendfiles": path, "script": SCRIPT, "addon_dir": addon_dir, "count": 4,
                       "summary_dir": os.path.join(farm, "summaries")}, tmp)
    assert [t["name"] for t in job["tasks"]] == ["bake-character.blend"]
    proc = run_task(job["tasks"][0], tmp, env_drop)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    check_lines(proc.stdout, pieces, 4)
    summary = json.load(open(os.path.join(farm, "summaries", "character.blend.bake_summary.json")))
    pairs = [o["pairs"][0] for o in summary["files"][0]["objects"]]
    assert [(p["objects"], p["keys"], p["joints"]) for p in pairs] == [(7, 4, 6), (1, 4, 0)]
    check_baked_as_one(path, pieces, joints)
