"""The glTF files tests/blender/test_export.py wrote, validated with Khronos' glTF validator and
played in three.js (node: tests/node/play_gltf.mjs), against the frames Blender showed.

Runs on the host after a Blender suite (the chroots have no node):
    BDI_RUNTIME_DIR=build/runtime/blender-4.3 python3 -m pytest -q tests/runtime
needs `npm ci --prefix tests/node` (make setup).
"""

import glob
import json
import os
import subprocess

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NODE = os.path.join(ROOT, "tests", "node")
BOUND = 1e-5  # of the character's size
RUNTIME = os.environ.get("BDI_RUNTIME_DIR", "")
CASES = sorted(os.path.basename(p)[:-5] for p in glob.glob(os.path.join(RUNTIME, "*.json")))


def test_the_blender_suite_wrote_its_exports():
    assert RUNTIME and os.path.isdir(RUNTIME), "BDI_RUNTIME_DIR=%r is no folder" % RUNTIME
    assert CASES == ["character", "cutout_one", "cutout_seven", "face_grid"], CASES


def play(glb, meta, tmp_path):
    """node's result for a GLB: validator summary, animations, meshes and, per frame, every
    mesh's vertices converted back from glTF's y-up to Blender's z-up axes."""
    times = [f / meta["fps"] for f in range(meta["frames"][0], meta["frames"][1] + 1)]
    (tmp_path / "times.json").write_text(json.dumps({"times": times}))
    out = tmp_path / "played.json"
    subprocess.run(["node", os.path.join(NODE, "play_gltf.mjs"), glb,
                    str(tmp_path / "times.json"), str(out)], check=True, timeout=300)
    result = json.loads(out.read_text())
    names = [m["name"] for m in result["meshes"]]
    frames = {n: np.array([f[n] for f in result["frames"]]).reshape(len(times), -1, 3)
              for n in names}
    result["frames"] = {n: X[..., [0, 2, 1]] * [1, -1, 1] for n, X in frames.items()}
    return result


def match(rest, other_rest):
    """For each glTF vertex (m, 3 at rest), Blender's vertex (of rest, n, 3) at its place; glTF
    splits vertices at UV seams, so several may find the same one, but each must find one."""
    d = np.linalg.norm(other_rest[:, None, :] - rest[None, :, :], axis=2)
    near = d.argmin(axis=1)
    assert d[np.arange(len(near)), near].max() < 1e-6 * (np.abs(rest).max() + 1.0)
    assert set(near.tolist()) == set(range(len(rest))), "Blender vertices missing in the glTF"
    return near


def error(truth, played):
    """(The glTF has more vertices than Blender: split at the UV seams test_export.py cuts.)
    Largest distance of a played vertex from Blender's at any frame (objects by name)."""
    assert sorted(played) == sorted(truth)
    return max(float(np.linalg.norm(played[n] - T[:, match(T[0], played[n][0])], axis=2).max())
               for n, T in truth.items())


def load(case):
    meta = json.load(open(os.path.join(RUNTIME, case + ".json")))
    truth = dict(np.load(os.path.join(RUNTIME, case + ".npz")))
    return meta, truth


@pytest.mark.parametrize("case", CASES)
def test_three_js_plays_the_export_bake_as_blender_showed_it(case, tmp_path):
    meta, truth = load(case)
    played = play(os.path.join(RUNTIME, case + ".glb"), meta, tmp_path)
    assert played["validator"]["errors"] == 0, played["validator"]["messages"]
    assert played["animations"], "no animation in the glTF"
    assert sum(len(X[0]) for X in played["frames"].values()) > sum(len(T[0]) for T in truth.values())
    err = error(truth, played["frames"]) / meta["size"]
    print("RUNTIME %s Blender %s: three.js max vertex error / size %.3g"
          % (case, meta["blender"], err))
    assert err <= BOUND


@pytest.mark.parametrize("case", CASES)
def test_without_export_bake_the_slider_is_not_exported(case, tmp_path):
    meta, truth = load(case)
    played = play(os.path.join(RUNTIME, case + ".before.glb"), meta, tmp_path)
    assert played["validator"]["errors"] == 0, played["validator"]["messages"]
    err = error(truth, played["frames"]) / meta["size"]
    print("RUNTIME %s Blender %s: before Bake for Export %.3g" % (case, meta["blender"], err))
    assert err > 0.05  # the character stays at rest: far from what Blender shows
