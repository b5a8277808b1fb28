"""Bakes: an animated target key keeps its own animation, bakes are found after renames and
reported stale, chunked progress and cancelling, messages in Blender's terms, distortion colours."""

import json

import bpy
import numpy as np
import pytest

from conftest import (TOL, add_key, bent_strip, evaluated_co, key_names, maxdiff, read_key,
                      triangles)


def test_slider_leaves_keyframed_target_alone(addon):
    obj = bent_strip()
    kb = obj.data.shape_keys.key_blocks["Bend"]
    kb.value = 0.0
    kb.keyframe_insert("value", frame=1)
    kb.value = 1.0
    kb.keyframe_insert("value", frame=10)
    result = addon.bake(obj, target="Bend", count=3)
    assert "keyframes of its own" in result.note and "Bend.bdi.100" in result.note
    drivers = obj.data.shape_keys.animation_data.drivers
    assert drivers.find('key_blocks["Bend"].value') is None
    assert drivers.find('key_blocks["Bend.bdi.100"].value') is not None
    # the target's own animation still plays: at frame 10, slider 0, the mesh is the target
    bpy.context.scene.frame_set(10)
    assert maxdiff(evaluated_co(obj), read_key(obj, "Bend")) < TOL
    # and the slider alone plays source -> target through the copy
    bpy.context.scene.frame_set(1)
    obj["Bend.bdi"] = 1.0
    obj.update_tag()
    assert maxdiff(evaluated_co(obj), read_key(obj, "Bend")) < TOL
    assert "keyframes of its own" in json.loads(obj.bdi.result)["note"]


def test_slider_leaves_driven_target_alone(addon):
    obj = bent_strip()
    obj["mine"] = 0.3
    fc = obj.data.shape_keys.key_blocks["Bend"].driver_add("value")
    var = fc.driver.variables.new()
    var.name, var.targets[0].id_type = "m", 'OBJECT'
    var.targets[0].id, var.targets[0].data_path = obj, '["mine"]'
    fc.driver.expression = "m"
    result = addon.bake(obj, target="Bend", count=2)
    assert "driver of its own" in result.note
    fc = obj.data.shape_keys.animation_data.drivers.find('key_blocks["Bend"].value')
    assert fc.driver.expression == "m" and fc.driver.variables[0].targets[0].data_path == '["mine"]'
    addon.clear(obj, "Bend")  # and clearing leaves it too
    fc = obj.data.shape_keys.animation_data.drivers.find('key_blocks["Bend"].value')
    assert fc is not None and fc.driver.expression == "m"


def test_value_set_by_hand_is_kept(addon):
    obj = bent_strip()
    obj.data.shape_keys.key_blocks["Bend"].value = 0.4
    result = addon.bake(obj, target="Bend", count=2)
    assert "value set by hand" in result.note
    assert obj.data.shape_keys.key_blocks["Bend"].value == pytest.approx(0.4)
    addon.clear(obj, "Bend")
    assert obj.data.shape_keys.key_blocks["Bend"].value == pytest.approx(0.4)


def test_bake_found_after_target_renamed(addon):
    obj = bent_strip()
    first = addon.bake(obj, target="Bend", count=3)
    obj.data.shape_keys.key_blocks["Bend"].name = "Arm"
    from bdinterp_blender.keys import playback
    found = playback.find(obj, "Basis", "Arm")
    assert found is not None and found.status == "renamed" and found.keys == first.keys
    second = addon.bake(obj, target="Arm", count=2)
    names = key_names(obj)
    assert not any(n.startswith("Bend.bdi.") for n in names)  # the old bake was replaced
    assert [n for n in names if ".bdi." in n] == second.keys
    assert second.slider == "Bend.bdi"  # the slider (and any keyframes on it) carries over
    assert addon.clear(obj, "Arm") == second.keys
    assert "Bend.bdi" not in obj.keys()


def test_bake_reported_stale_after_target_edit(addon):
    obj = bent_strip()
    addon.bake(obj, target="Bend", count=2)
    from bdinterp_blender.keys import playback
    assert playback.find(obj, "Basis", "Bend").status == ""
    kb = obj.data.shape_keys.key_blocks["Bend"]
    kb.data[0].co.x += 0.05
    assert playback.find(obj, "Basis", "Bend").status == "stale"


def test_a_bake_given_eight_threads_runs_them(addon):
    """Eight workers on this machine of fewer cores: the 8 factors are one frames() call of a
    worker each, and the solver's stats count the threads that ran."""
    from bdinterp_blender.api import bake_job
    from bdinterp_blender.shapes.solve import core, frames_per_call
    obj = bent_strip()
    factors = [k / 9 for k in range(1, 9)]
    job = bake_job(obj, "Bend", factors=factors, threads=8)
    assert frames_per_call(8) >= len(factors)
    assert job.step() == 8 and job.finished
    assert job.job.solver.stats.threads == 8
    assert job.job.solver.stats.converged
    cores = core().threading_info()["usable_cores"]
    default = bake_job(obj, "Bend", factors=factors)  # a worker per usable core
    default.step()
    assert default.job.solver.stats.threads == min(cores, len(factors))


def test_progress_per_chunk_and_cancel_writes_nothing(addon):
    # A small mesh: a frame per worker first, then the most frames a call may take.
    obj = bent_strip()
    from bdinterp_blender.shapes.solve import frames_per_call, workers
    first, chunk = workers(), frames_per_call()
    total = first + chunk + 1
    calls = []
    addon.bake(obj, target="Bend", count=total, progress=lambda d, t: calls.append((d, t)))
    assert calls == [(first, total), (first + chunk, total), (total, total)]
    addon.clear(obj, "Bend")
    before = (key_names(obj), sorted(obj.keys()))
    with pytest.raises(ValueError, match="cancelled after %d of %d" % (first, total)):
        addon.bake(obj, target="Bend", count=total, progress=lambda d, t: False)
    assert (key_names(obj), sorted(obj.keys())) == before


@pytest.mark.parametrize("round_seconds, frames", [(0.01, [2, 8, 8, 2]), (0.06, [2, 4, 4, 4, 4, 2]),
                                                   (0.5, [2] * 10)])
def test_a_step_takes_the_rounds_that_fit_in_its_time(addon, monkeypatch, round_seconds, frames):
    """On a clock that a round of frames (one on each of 2 workers) moves by round_seconds, the
    steps after the first take as many rounds as fit in STEP_SECONDS (0.15), at least one, at most
    FRAMES_PER_WORKER (4) frames a worker."""
    from bdinterp_blender.shapes import solve
    clock = [0.0]

    class Slow:
        def frames(self, ts):
            clock[0] += round_seconds * -(-len(ts) // 2)
            return np.zeros((len(ts), 3, 3))

    monkeypatch.setattr(solve.time, "perf_counter", lambda: clock[0])
    from bdinterp_blender.shapes.settings import BakeSettings
    job = solve.FrameJob(solve.Inputs(bent_strip(), BakeSettings("Bend")), [0.5] * 20,
                         threads=2)
    job._solver = Slow()
    steps = []
    while not job.finished:
        before = job.done
        steps.append(job.step() - before)
    assert steps == frames

@pytest.mark.parametrize("method", ["bdi", "arap", "linear"])
def test_chunked_frames_match_single_calls(bd, addon, method):
    obj = bent_strip()
    result = addon.bake(obj, target="Bend", count=11, method=method, drivers=False)
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    for name, t in zip(result.keys, result.factors):
        assert maxdiff(read_key(obj, name), bd.interpolate(S, T, faces, t, method=method)) < TOL


def test_core_errors_name_keys_and_polygons(addon):
    obj = bent_strip()
    bad = read_key(obj, "Basis")
    poly = obj.data.polygons[37]
    bad[poly.vertices[1]] = bad[poly.vertices[0]]
    add_key(obj, "Collapsed", bad)
    with pytest.raises(ValueError) as info:
        addon.bake(obj, target="Collapsed")
    text = str(info.value)
    assert text.startswith("Strip: ") and "'Collapsed'" in text and "shape 1" not in text
    # the polygon named is one of the two sharing the collapsed edge (not a triangle index)
    import re
    named = obj.data.polygons[int(re.search(r"^Strip: key 'Collapsed', polygon (\d+): zero area$",
                                            text).group(1))]
    assert {poly.vertices[0], poly.vertices[1]} <= set(named.vertices)


def test_an_anchor_vertex_out_of_range_is_named_by_the_core(addon):
    """The core alone checks the range (one layer); the add-on names the vertex."""
    obj = bent_strip()
    n = len(obj.data.vertices)
    with pytest.raises(ValueError, match=r"^Strip: vertex %d: the anchor vertex is out of range "
                                         r"\[0, %d\)" % (n, n)):
        addon.bake(obj, target="Bend", anchor=n)


def test_distortion_colours_relative_to_each_face_of_the_inputs(addon, bd):
    """Blue where a face is no worse than in the target, red where it is; per face, not scaled
    by the mesh's single worst face."""
    obj = bent_strip()
    S = read_key(obj, "Basis")
    from bdinterp_blender.view import distortion
    # a result key made by hand: half the faces as in the target, the other half sheared more
    worse = S.copy()
    worse[:, 0] += 0.3 * worse[:, 1] * (worse[:, 0] > 0)
    kb = add_key(obj, "Bend.bdi.050", worse)
    k_res, k_in = distortion.per_face(obj, "Bend.bdi.050")
    rgba = distortion.colors(k_res, k_in)
    blue, red = rgba[:, 2] > 0.9, rgba[:, 0] > 0.9
    assert np.all(blue[k_res <= k_in * (1 + 1e-6)])
    assert np.all(~blue[k_res > 2.0 * k_in]) and np.all(red[k_res >= 2.0 * k_in])
    assert blue.any() and (~blue).any()
    assert kb.name == "Bend.bdi.050"
