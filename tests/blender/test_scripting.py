"""Scripting from the command line and the batch script, in separate Blender processes."""

import os

import bpy

from conftest import (ROOT, TOL, add_key, bent_strip, json_lines, maxdiff, read_key, run_blender,
                      triangles)

EXPR = ("import bpy, json, bdinterp_blender; "
        "r = bdinterp_blender.bake(bpy.data.objects['Strip'], source='Basis', target='Bend', "
        "count=8, easing='EASE_IN_OUT'); "
        "bpy.ops.wm.save_mainfile(); "
        "print('JSON:' + json.dumps({'keys': r.keys, 'factors': r.factors}))")


def test_bake_from_command_line_python_expr(addon, bd, tmp_path):
    bent_strip()
    path = os.path.join(str(tmp_path), "strip.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    # the installed add-on (not enabled: factory startup) is importable by name
    proc = run_blender([path, "--python-exit-code", "1", "--python-expr", EXPR], env_drop=())
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json_lines(proc)[0]
    assert len(out["keys"]) == 8
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects["Strip"]
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    for name, t in zip(out["keys"], out["factors"]):
        assert maxdiff(read_key(obj, name), bd.interpolate(S, T, faces, t)) < TOL


def test_batch_script_bakes_folder_and_reports_failures(addon, bd, tmp_path):
    folder = os.path.join(str(tmp_path), "shots")
    os.makedirs(folder)
    bent_strip()
    bpy.ops.mesh.primitive_cube_add()  # no shape keys: not suitable, ignored
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(folder, "a_good.blend"))
    bpy.ops.wm.read_homefile(use_empty=True)
    obj = bent_strip("Bumpy")
    bad = read_key(obj, "Bend")
    bad[3, 2] += 0.2
    add_key(obj, "Off", bad)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(folder, "b_bad.blend"))
    script = os.path.join(ROOT, "examples", "blender", "bake_folder.py")
    proc = run_blender(["--python", script, "--", folder, "--count", "3"], env_drop=())
    lines = [l for l in proc.stdout.splitlines() if l.startswith(("a_good", "b_bad"))]
    assert proc.returncode == 1, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert len(lines) == 2, lines
    assert lines[0].startswith("a_good.blend: Strip: OK Basis -> Bend: 3 keys")
    assert lines[1].startswith("b_bad.blend: Bumpy: FAILED") and "not planar" in lines[1]
    bpy.ops.wm.open_mainfile(filepath=os.path.join(folder, "a_good.blend"))
    obj = bpy.data.objects["Strip"]
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    assert maxdiff(read_key(obj, "Bend.bdi.050"), bd.interpolate(S, T, faces, 0.5)) < TOL
