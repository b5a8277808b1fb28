"""Every panel's draw() in a real Blender window (Xvfb), and the README's screenshot of it."""

import os
import shutil
import subprocess

import bpy
import pytest

from conftest import ROOT, json_lines

SCRIPT = os.path.join(ROOT, "examples", "blender", "panel_screenshot.py")


def run_in_window(args, timeout=240):
    if shutil.which("xvfb-run") is None:
        pytest.skip("xvfb-run not found (Debian packages xvfb and xauth)")
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", bpy.app.binary_path,
           "--factory-startup", "--enable-event-simulate", "--python", SCRIPT, "--", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=dict(os.environ))


def test_every_panel_draws_in_a_real_window(addon, tmp_path):
    png = os.path.join(str(tmp_path), "panel.png")
    proc = run_in_window(["--open-all", "--out", png])
    out = json_lines(proc)[-1]
    assert out["errors"] == {}, out["errors"]
    from bdinterp_blender.ui import panels as ui
    for cls in ui.PANELS:
        assert out["calls"].get(cls.__name__ + ".draw", 0) >= 1, (cls.__name__, out["calls"])
    assert "Traceback" not in proc.stderr, proc.stderr[-3000:]
    img = bpy.data.images.load(png)
    assert img.size[0] == 560 and img.size[1] > 500


def test_bake_from_the_ui_cancels_with_esc_and_undoes(addon):
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "window_bake.py")
    if shutil.which("xvfb-run") is None:
        pytest.skip("xvfb-run not found (Debian packages xvfb and xauth)")
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", bpy.app.binary_path,
           "--factory-startup", "--enable-event-simulate", "--python", script]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=240, env=dict(os.environ))
    out = json_lines(proc)[-1]
    assert "error" not in out, out["error"]
    assert out["invoke"] == ["RUNNING_MODAL"]  # modal: the chunks computed on a thread
    assert out["step_threads"] and not any(out["step_threads"])  # the window is never blocked
    assert out["after_cancel"] == ["Basis", "Bend"] and not out["slider_after_cancel"]
    # the wait after Esc (60 ticks) was longer than a whole bake takes: the bake really stopped
    assert out["after_bake"] == 2 + 48 and out["ticks_to_bake"] < 60
    assert out["after_undo"] == ["Basis", "Bend"]  # the whole bake is one undo step


def test_a_bake_from_the_ui_shows_its_progress_in_the_panel_and_status_bar(addon, tmp_path):
    import re
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "window_progress.py")
    if shutil.which("xvfb-run") is None:
        pytest.skip("xvfb-run not found (Debian packages xvfb and xauth)")
    shot = os.path.join(str(tmp_path), "progress.png")
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", bpy.app.binary_path,
           "--factory-startup", "--enable-event-simulate", "--python", script, "--", shot]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=dict(os.environ))
    out = json_lines(proc)[-1]
    assert "error" not in out, out["error"]
    assert out["invoke"] == ["RUNNING_MODAL"] and out["draws"] > 0  # the panel was open
    seen = [tuple(map(int, re.fullmatch(r"Baking (\d+) of (\d+) \(Esc to cancel\)", s).groups()))
            for s in out["seen"]]
    assert seen[0] == (0, 12) and any(0 < k < 12 for k, _ in seen), seen  # under way, then done
    assert out["after"] == "" and out["keys"] == 2 + 12  # the progress gone once written
    assert bpy.data.images.load(out["shot"]).size[0] == 1600
    # a pose that pulls the forearm off: Bake asks first and bakes nothing; the dialog's OK bakes
    assert out["torn_invoke"] == ["CANCELLED"] and out["torn_unbaked"]
    assert out["torn_report"].startswith("'forearm_r' comes off 'upper_arm_r' by 0.3")
    assert out["torn_ok"] == ["FINISHED"] and out["torn_baked"]
