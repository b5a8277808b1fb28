"""Onion skins and motion trails drawn in a real Blender window (Xvfb): the ghost of the 0.75
in-between shows where its triangles project, nothing changes away from it, no error in live
mode, from baked keys or for the seven-object character, ghosts of the frames either side of the
current one tinted Before and After (examples/blender/onion_screenshot.py)."""

import os
import shutil
import subprocess

import bpy
import numpy as np
import pytest

from conftest import ROOT, json_lines

SCRIPT = os.path.join(ROOT, "examples", "blender", "onion_screenshot.py")


def run_in_window(tmp_path, *args):
    if shutil.which("xvfb-run") is None:
        pytest.skip("xvfb-run not found (Debian packages xvfb and xauth)")
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", bpy.app.binary_path,
           "--factory-startup", "--python", SCRIPT, "--", "--redraws", "3",
           "--out", os.path.join(str(tmp_path), "onion.png"), *args]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=dict(os.environ))
    assert "Traceback" not in proc.stderr, proc.stderr[-3000:]
    return json_lines(proc)[-1]


FRAMES = [0.25, 0.375, 0.625, 0.75]  # frames 3, 4, 6, 7 of a factor keyed 0 at 1 and 1 at 9


@pytest.mark.parametrize("args, factors", [
    (("--scene", "one", "--chords"), [0.25, 0.5, 0.75]),
    (("--scene", "one", "--live"), [0.25, 0.5, 0.75]),
    (("--scene", "seven", "--ghosts", "BAKED"), [0.25, 0.5, 0.75]),
    (("--scene", "one", "--ghosts", "FRAMES"), FRAMES),
    (("--scene", "one", "--live", "--ghosts", "FRAMES"), FRAMES),
    (("--scene", "seven", "--ghosts", "FRAMES"), FRAMES),
])
def test_ghosts_and_trails_draw_where_the_inbetweens_are(addon, tmp_path, args, factors):
    out = run_in_window(tmp_path, *args)
    assert out["error"] == "", out["error"]
    assert out["factors"] == pytest.approx(factors, abs=1e-6)
    assert out["trails"][0] == 33 and out["trails"][1] >= 7  # 7 pieces' centres, then joints
    # the ghost's triangles on empty background: tinted (fill alpha ~0.1) wherever they project
    change = np.array(out["ghost_change"])
    assert out["ghost_points"] >= 10, out
    moved = np.abs(change).max(axis=1) > 0.01
    assert moved.mean() > 0.9, change
    assert (change[:, 0] > change[:, 2]).mean() > 0.9  # towards the After colour (orange)
    first = np.array(out["first_change"])
    assert len(first) >= 10 and (np.abs(first).max(axis=1) > 0.01).mean() > 0.9
    # the first ghost (0.25) before the shape shown (live and frames: 0.5) takes the Before colour
    # (blue), after it (the slider at 0) the After colour
    shown = 0.5 if "--live" in args or factors == FRAMES else 0.0
    before = (first[:, 2] > first[:, 0]).mean()
    assert before > 0.9 if shown > factors[0] else before < 0.1
    assert out["corner_change"] < 1e-3
    assert out["draw_cached"] < 0.002  # a redraw with the overlay built: colours and batches only
