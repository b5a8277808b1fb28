"""Packaging: the zips, the registered UI, and the message for a Blender with another Python."""

import json
import os
import shutil
import sys
import tomllib
import zipfile

import bpy

from conftest import addon_zip, json_lines, run_blender, write_child_script


def test_installed_from_zip_and_registered(addon):
    assert hasattr(bpy.types.Object, "bdi")
    for op in ("bake", "clear", "blend", "distortion", "pose_add", "anchor_from_selection"):
        assert hasattr(bpy.ops.bdinterp, op)
    assert hasattr(bpy.types, "BDINTERP_PT_main")
    info = addon.build_info()
    assert info["python"] == "%d.%d" % sys.version_info[:2]
    assert addon.core_status() == (True, "")


def test_zip_names_and_manifest_state_the_python():
    legacy = addon_zip()
    assert legacy.endswith("-legacy-py%d%d.zip" % sys.version_info[:2])
    extension = legacy.replace("-legacy-", "-extension-")
    with zipfile.ZipFile(extension) as zf:
        manifest = tomllib.loads(zf.read("blender_manifest.toml").decode())
        names = zf.namelist()
        info = json.loads(zf.read("build_info.json"))
    assert manifest["id"] == "bdinterp_blender" and manifest["type"] == "add-on"
    assert manifest["platforms"] == ["linux-x64"] and manifest["blender_version_min"] == "4.2.0"
    assert "__init__.py" in names and any(n.startswith("_vendor/bdinterp/_core") for n in names)
    assert info["ext_suffix"].startswith(".cpython-%d%d-" % sys.version_info[:2])
    with zipfile.ZipFile(legacy) as zf:
        names = zf.namelist()
    assert all(n.startswith("bdinterp_blender/") for n in names)
    assert "bdinterp_blender/blender_manifest.toml" not in names


def test_core_status_names_both_pythons(addon):
    ok, message = addon.core_status(ext_suffix=".cpython-312-x86_64-linux-gnu.so")
    assert not ok
    assert "Python 3.11" in message and "Python 3.12" in message


CHILD = """
import addon_utils, traceback
bpy.ops.preferences.addon_install(filepath=sys.argv[-1])
mod = addon_utils.enable("bdinterp_blender", default_set=True, handle_error=lambda e: traceback.print_exc())
import bdinterp_blender.ui as ui
panel = bpy.types.BDINTERP_PT_main
print("JSON:" + json.dumps({"enabled": addon_utils.check("bdinterp_blender")[1],
                            "message": ui.CORE_ERROR, "panel": panel.bl_category,
                            "has_bake": hasattr(bpy.types, "BDINTERP_OT_bake")}))
"""


def test_wrong_python_gives_a_message_not_a_traceback(tmp_path):
    """A zip whose compiled module is for another Python: enabling works, the panel explains."""
    tmp = str(tmp_path)
    broken = os.path.join(tmp, "bdinterp_blender-wrong-py399.zip")
    with zipfile.ZipFile(addon_zip()) as src, zipfile.ZipFile(broken, "w") as dst:
        for item in src.infolist():
            data = src.read(item)
            name = item.filename
            if "_core.cpython-" in name:
                name = name.split("_core.cpython-")[0] + "_core.cpython-399-x86_64-linux-gnu.so"
            if name.endswith("build_info.json"):
                info = json.loads(data)
                info["python"] = "3.99"
                data = json.dumps(info).encode()
            dst.writestr(name, data)
    user = os.path.join(tmp, "user")
    os.makedirs(user)
    script = write_child_script(tmp_path, CHILD)
    env_user = os.environ.get("BLENDER_USER_SCRIPTS")
    os.environ["BLENDER_USER_SCRIPTS"] = user
    try:
        proc = run_blender(["--python", script, "--", broken], env_drop=())
    finally:
        os.environ["BLENDER_USER_SCRIPTS"] = env_user
    out = json_lines(proc)[0]
    assert out["enabled"] and out["panel"] == "bdinterp" and not out["has_bake"]
    assert "Python 3.99" in out["message"] and "runs Python 3.11" in out["message"]
    assert "Traceback" not in proc.stdout + proc.stderr
    shutil.rmtree(user, ignore_errors=True)
