"""Packaging: the zips, the registered UI, and the message for a Blender with another Python."""

import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
import zipfile

import bpy
import pytest

from conftest import ADDON_MODULE, EXTENSION, addon_zip, json_lines, run_blender, write_child_script

RUNNING = "%d.%d" % sys.version_info[:2]


def test_installed_from_zip_and_registered(addon):
    assert hasattr(bpy.types.Object, "bdi")
    for op in ("bake", "clear", "blend", "distortion", "pose_add", "anchor_from_selection"):
        assert hasattr(bpy.ops.bdinterp, op)
    assert hasattr(bpy.types, "BDINTERP_PT_main")
    info = addon.build_info()
    assert RUNNING in info["pythons"]
    assert info["layout"] == ("extension" if EXTENSION else "legacy")
    assert addon.core_status() == (True, "")
    bd = addon.load_core()
    if EXTENSION:  # from its wheel, in the extensions' site-packages
        assert bd.__name__ == "bdinterp" and "site-packages" in bd.__file__
    else:  # private to the add-on: no global `bdinterp` module, no sys.path entry
        assert bd.__name__ == ADDON_MODULE + "._vendor.bdinterp"
        assert not any(p.endswith("_vendor") for p in sys.path)


def test_core_calls_its_bundled_blas_and_finds_the_thread_controls(addon):
    """The shipped module carries CHOLMOD's BLAS (OpenBLAS) and OpenMP runtime under private names
    (libopenblas-bdi.so.0, libgomp-bdi.so.1). CHOLMOD's BLAS calls reach the bundled OpenBLAS even
    where Blender has another BLAS in the process (Debian's 4.3 and 5.2 link the reference BLAS),
    and bdinterp holds its threads at one during a factorisation; the OpenMP runtime is the bundled
    one or the one Blender loaded, to which CHOLMOD's calls then bind, found by its library either
    way (looking the libraries up by soname missed them)."""
    info = addon.load_core().threading_info()
    here = os.path.dirname(addon.load_core().__file__)
    assert info["blas"] and os.path.samefile(info["blas"], os.path.join(here, "libopenblas-bdi.so.0")), info
    assert info["blas_threads"], info
    assert info["openmp"] and "libgomp" in os.path.basename(info["openmp"]), info
    if info["openmp"].startswith(here):
        assert "-bdi" in os.path.basename(info["openmp"]), info  # the private copy
    assert 1 <= info["usable_cores"] <= os.cpu_count()


def test_scripting_name_gives_the_same_modules(addon):
    """`import bdinterp_blender.ui.panels` (the scripting name) must not load a second copy of the
    module under an extension, whose state would then diverge from the registered one."""
    import importlib
    ui = importlib.import_module("bdinterp_blender.ui.panels")
    assert ui is importlib.import_module(ADDON_MODULE + ".ui.panels")
    assert ui.__spec__.name == ADDON_MODULE + ".ui.panels"  # the real name, for reload and pickling
    assert ui.BDINTERP_PT_main is bpy.types.BDINTERP_PT_main
    copies = [n for n, m in sys.modules.items() if getattr(m, "__file__", None) == ui.__file__
              and m is not ui]
    assert copies == []


def test_extension_zip_lists_a_wheel_per_python(addon):
    if addon.build_info().get("development"):
        pytest.skip("development zip (build_addon.py --core): no extension, no bundled libraries")
    legacy = addon_zip()
    assert legacy.endswith("-legacy-py311.zip")  # Blender 3.4-4.1 embed Python 3.11
    extension = re.sub(r"-legacy-py\d+\.zip$", "-extension.zip", legacy)
    with zipfile.ZipFile(extension) as zf:
        manifest = tomllib.loads(zf.read("blender_manifest.toml").decode())
        names = zf.namelist()
        info = json.loads(zf.read("build_info.json"))
    assert manifest["id"] == "bdinterp_blender" and manifest["type"] == "add-on"
    assert manifest["platforms"] == ["linux-x64"] and manifest["blender_version_min"] == "4.2.0"
    assert manifest["license"] == ["SPDX:GPL-3.0-or-later"]
    tags = sorted(re.search(r"-(cp\d+)-cp\d+-manylinux_2_31_x86_64\.whl$", w).group(1)
                  for w in manifest["wheels"])
    assert tags == ["cp311", "cp313", "cp314"] and info["pythons"] == ["3.11", "3.13", "3.14"]
    assert all(w[2:] in names for w in manifest["wheels"])  # './wheels/...'
    assert "__init__.py" in names and not any(n.startswith("_vendor/") for n in names)
    assert "LICENSE" in names and "licenses/suitesparse.copyright" in names
    with zipfile.ZipFile(legacy) as zf:
        names = zf.namelist()
    assert all(n.startswith("bdinterp_blender/") for n in names)
    assert "bdinterp_blender/blender_manifest.toml" not in names
    assert "bdinterp_blender/_vendor/bdinterp/_core.cpython-311-x86_64-linux-gnu.so" in names
    assert "bdinterp_blender/licenses/libopenblas0-pthread.copyright" in names


def test_core_status_names_both_pythons(addon):
    ok, message = addon.core_status(ext_suffix=".cpython-312-x86_64-linux-gnu.so")
    assert not ok
    assert "Python 3.11" in message and "Python 3.12" in message  # 3.11: in both zips


@pytest.mark.parametrize("platform_name, ext_suffix, install", [
    ("windows-x64", ".cp311-win_amd64.pyd", "vcpkg"),
    ("macos-arm64", ".cpython-311-darwin.so", "Homebrew"),
])
def test_core_status_names_a_platform_without_a_module(addon, platform_name, ext_suffix, install):
    # The zips carry linux-x64 modules only: elsewhere the message names both platforms and what to
    # install to build one, instead of an ImportError or a wrong "other Python" message.
    ok, message = addon.core_status(ext_suffix=ext_suffix, platform_name=platform_name)
    assert not ok
    assert platform_name in message and "linux-x64" in message and install in message
    assert "docs/PLATFORMS.md" in message
    assert addon.core_status(platform_name="linux-x64") == (True, "")


CHILD = """
import addon_utils, traceback
bpy.ops.preferences.addon_install(filepath=sys.argv[-1])
mod = addon_utils.enable("bdinterp_blender", default_set=True, handle_error=lambda e: traceback.print_exc())
import bdinterp_blender.ui.panels as ui
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
                info["python"], info["pythons"] = "3.99", ["3.99"]
                data = json.dumps(info).encode()
            dst.writestr(name, data)
    user = os.path.join(tmp, "user")
    os.makedirs(user)
    script = write_child_script(tmp_path, CHILD)
    env_user = os.environ.get("BLENDER_USER_SCRIPTS")
    os.environ["BLENDER_USER_SCRIPTS"] = user
    try:
        proc = run_blender(["--python", script, "--", broken], env_drop=("BLENDER_USER_EXTENSIONS",))
    finally:
        os.environ["BLENDER_USER_SCRIPTS"] = env_user
    out = json_lines(proc)[0]
    assert out["enabled"] and out["panel"] == "bdinterp" and not out["has_bake"]
    assert "Python 3.99" in out["message"] and "runs Python %s" % RUNNING in out["message"]
    assert "Traceback" not in proc.stdout + proc.stderr
    shutil.rmtree(user, ignore_errors=True)


def next_build(src, dst):
    """Copy the zip `src` as the next build of the add-on (same id, patch version + 1 in bl_info,
    the manifest and build_info.json); return the new version."""
    with zipfile.ZipFile(src) as zin:
        info_name = next(n for n in zin.namelist() if n.endswith("build_info.json"))
        old = json.loads(zin.read(info_name))["version"]
        major, minor, patch = map(int, old.split("."))
        new = "%d.%d.%d" % (major, minor, patch + 1)
        with zipfile.ZipFile(dst, "w", zipfile.ZIP_DEFLATED) as zout:
            for item in zin.infolist():
                data = zin.read(item)
                if item.filename == info_name:
                    data = data.replace(b'"version": "%s"' % old.encode(), b'"version": "%s"' % new.encode())
                elif item.filename.endswith("blender_manifest.toml"):
                    data = data.replace(b'version = "%s"' % old.encode(), b'version = "%s"' % new.encode())
                elif item.filename in ("__init__.py", "bdinterp_blender/__init__.py"):
                    data = data.replace(b'"version": (%d, %d, %d)' % (major, minor, patch),
                                        b'"version": (%d, %d, %d)' % (major, minor, patch + 1))
                zout.writestr(item, data)
    return old, new


REPORT = """
import addon_utils, sys
if sys.argv[-1] != "-":
    bpy.ops.preferences.addon_install(filepath=sys.argv[-1], overwrite=True)
addon_utils.enable(sys.argv[-2], default_set=True)
mod = sys.modules[sys.argv[-2]]
bd = mod.load_core()
print("JSON:" + json.dumps({"version": mod.build_info()["version"], "status": mod.core_status()[0],
                            "core": bd.__name__, "solver": bd.SolverError.__name__}))
"""


def test_newer_build_installs_over_the_installed_one(tmp_path):
    """Install this build, then the next one (same id) over it, in a fresh user folder: the new
    version is the one that loads, with a working compiled core."""
    tmp = str(tmp_path)
    src = EXTENSION or addon_zip()
    newer = os.path.join(tmp, "newer-" + os.path.basename(src))
    old, new = next_build(src, newer)
    env = dict(os.environ, BLENDER_USER_SCRIPTS=os.path.join(tmp, "scripts"),
               BLENDER_USER_EXTENSIONS=os.path.join(tmp, "extensions"),
               BLENDER_USER_CONFIG=os.path.join(tmp, "config"))
    script = write_child_script(tmp_path, REPORT)
    versions = []
    for zip_path in (src, newer):
        if EXTENSION:
            cmd = ["--command", "extension", "install-file", "-r", "user_default", zip_path]
            proc = subprocess.run([bpy.app.binary_path, "--background", "--factory-startup", *cmd],
                                  capture_output=True, text=True, env=env, timeout=300)
            assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
        proc = subprocess.run([bpy.app.binary_path, "--background", "--factory-startup", "--python",
                               script, "--", ADDON_MODULE, "-" if EXTENSION else zip_path],
                              capture_output=True, text=True, env=env, timeout=300)
        out = json_lines(proc)[0]
        assert out["status"] and out["solver"] == "SolverError", out
        versions.append(out["version"])
    assert versions == [old, new]
