"""Batch baking (examples/blender/bake_folder.py) and the Flamenco job type, run for real."""

import json
import os
import shutil
import subprocess
import zipfile

import bpy
import pytest

from conftest import ROOT, TOL, add_key, addon_zip, bent_strip, maxdiff, read_key, triangles

SCRIPT = os.path.join(ROOT, "examples", "blender", "bake_folder.py")
JOB_TYPE = os.path.join(ROOT, "examples", "flamenco", "bdinterp-bake.js")
RECORDER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "flamenco_author.js")


def save(path):
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.read_homefile(use_empty=True)


def shots(folder):
    """good (plannar pair), bad (a non-planar target beside a good one), flat (only a non-planar
    target), corrupt (not a .blend at all)."""
    os.makedirs(folder)
    bent_strip()
    save(os.path.join(folder, "a_good.blend"))
    obj = bent_strip("Bumpy")
    bad = read_key(obj, "Bend")
    bad[3, 2] += 0.2
    add_key(obj, "Off", bad)
    save(os.path.join(folder, "b_bad.blend"))
    with open(os.path.join(folder, "c_corrupt.blend"), "wb") as f:
        f.write(b"BLENDER-not-really" * 10)
    obj = bent_strip("Flat")
    kb = obj.data.shape_keys.key_blocks["Bend"]
    kb.data[3].co.z += 0.2
    save(os.path.join(folder, "d_flat.blend"))


def blender(args, cwd, env_drop=(), exe=None):
    env = {k: v for k, v in os.environ.items() if k not in env_drop}
    env["PWD"] = cwd  # as a shell sets it (Blender resolves relative paths on the command line by it)
    return subprocess.run([exe or bpy.app.binary_path, *args], cwd=cwd, capture_output=True,
                          text=True, timeout=300, env=env)


def test_relative_folder_failing_files_skipped_objects_summary(addon, bd, tmp_path):
    tmp = str(tmp_path)
    shots(os.path.join(tmp, "shots"))
    proc = blender(["--background", "--factory-startup", "--python", SCRIPT, "--", "shots",
                    "--count", "3", "--skip-nonplanar"], cwd=tmp)
    out = proc.stdout
    assert proc.returncode == 1, out[-3000:] + proc.stderr[-3000:]  # without --python-exit-code
    lines = [l for l in out.splitlines() if l.split(":")[0].endswith(".blend")]
    assert lines[0].startswith("a_good.blend: Strip: OK Basis -> Bend: 3 keys"), lines
    assert lines[1].startswith("b_bad.blend: Bumpy: OK") and "Off: skipped" in lines[1], lines
    assert lines[2].startswith("c_corrupt.blend: FAILED"), lines  # and it went on:
    assert lines[3].startswith("d_flat.blend: Flat: SKIPPED"), lines
    summary = json.load(open(os.path.join(tmp, "shots", "bake_summary.json")))
    assert (summary["ok"], summary["failed"], summary["skipped"]) == (2, 1, 1)
    assert [f["status"] for f in summary["files"]] == ["OK", "OK", "FAILED", "OK"]
    good = summary["files"][0]["objects"][0]["pairs"][0]
    assert good["keys"] == 3 and good["max_distortion"] <= good["input_distortion"] * (1 + 1e-6)
    bpy.ops.wm.open_mainfile(filepath=os.path.join(tmp, "shots", "a_good.blend"))
    obj = bpy.data.objects["Strip"]
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    assert maxdiff(read_key(obj, "Bend.bdi.050"), bd.interpolate(S, T, faces, 0.5)) < TOL


def test_failing_object_fails_the_run_and_is_reported(addon, tmp_path):
    tmp = str(tmp_path)
    obj = bent_strip("Bumpy")
    bad = read_key(obj, "Bend")
    bad[3, 2] += 0.2
    add_key(obj, "Off", bad)
    save(os.path.join(tmp, "one.blend"))
    proc = blender(["--background", "--factory-startup", "one.blend", "--python", SCRIPT, "--",
                    "--count", "2", "--out", "baked"], cwd=tmp)
    assert proc.returncode == 1, proc.stdout[-3000:]
    assert "one.blend: Bumpy: FAILED" in proc.stdout and "not planar" in proc.stdout
    summary = json.load(open(os.path.join(tmp, "baked", "bake_summary.json")))
    assert summary["failed"] == 1 and os.path.exists(os.path.join(tmp, "baked", "one.blend"))


def compile_job(settings, tmp):
    if shutil.which("node") is None:
        pytest.skip("node not found (Debian package nodejs)")
    path = os.path.join(tmp, "settings.json")
    with open(path, "w") as f:
        json.dump(settings, f)
    proc = subprocess.run(["node", RECORDER, JOB_TYPE, path], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def command_line(cmd):
    """What a Flamenco Worker runs for a blender-render command: exe exeArgs argsBefore blendfile args."""
    p = cmd["parameters"]
    exe = p["exe"].replace("{blender}", bpy.app.binary_path)
    exe_args = p.get("exeArgs", "").replace("{blenderArgs}", "-b -y").split()
    return [exe, *exe_args, *p.get("argsBefore", []), p["blendfile"], *p["args"]]


def worker_addon(farm):
    """(the job's addon_dir, the environment Workers lack) of a farm folder: on Blender 4.2+
    Workers have the extension installed; else the legacy add-on is unpacked on shared storage
    and Workers do not have it installed."""
    if os.environ.get("BDI_EXTENSION_ZIP"):
        return "", ()
    addon_dir = os.path.join(farm, "addon")
    zipfile.ZipFile(addon_zip()).extractall(addon_dir)
    return addon_dir, ("BLENDER_USER_SCRIPTS",)


def run_task(task, tmp, env_drop):
    """Run a compiled task's one blender-render command as a Worker would; the process."""
    assert task["type"] == "blender" and len(task["commands"]) == 1
    cmd = task["commands"][0]
    assert cmd["type"] == "blender-render"
    exe, *args = command_line(cmd)
    proc = blender(args, cwd=tmp, env_drop=env_drop, exe=exe)
    assert "bake_folder:" in proc.stdout, proc.stdout[-2000:] + proc.stderr[-2000:]
    return proc


def test_flamenco_job_compiles_and_its_commands_run(addon, tmp_path):
    tmp = str(tmp_path)
    farm = os.path.join(tmp, "farm")
    shots(os.path.join(farm, "shots"))
    addon_dir, env_drop = worker_addon(farm)
    files = [os.path.join(farm, "shots", n) for n in ("a_good.blend", "b_bad.blend")]
    job = compile_job({"blendfiles": ";".join(files), "script": SCRIPT, "addon_dir": addon_dir,
                       "count": 4, "summary_dir": os.path.join(farm, "summaries")}, tmp)
    assert job["label"] == "bdinterp Bake In-betweens"
    assert [t["name"] for t in job["tasks"]] == ["bake-a_good.blend", "bake-b_bad.blend"]
    os.makedirs(os.path.join(farm, "summaries"))
    codes = [run_task(task, tmp, env_drop).returncode for task in job["tasks"]]
    assert codes == [0, 1]  # the task with a non-planar key fails; the other is done
    a = json.load(open(os.path.join(farm, "summaries", "a_good.blend.bake_summary.json")))
    assert a["ok"] == 1 and a["files"][0]["objects"][0]["pairs"][0]["keys"] == 4
    b = json.load(open(os.path.join(farm, "summaries", "b_bad.blend.bake_summary.json")))
    assert b["failed"] == 1


def test_flamenco_job_rejects_bad_file_lists(addon, tmp_path):
    if shutil.which("node") is None:
        pytest.skip("node not found (Debian package nodejs)")
    path = os.path.join(str(tmp_path), "settings.json")
    with open(path, "w") as f:
        json.dump({"blendfiles": "shot.txt", "script": SCRIPT, "summary_dir": "/tmp"}, f)
    proc = subprocess.run(["node", RECORDER, JOB_TYPE, path], capture_output=True, text=True, timeout=60)
    assert proc.returncode != 0 and "shot.txt is not a .blend file" in proc.stderr
