"""The onion-skin overlay's work, counted: the Path is validated and its frames solved again only
when a key, a bake setting or the topology changes; moving the drawn object, selecting, changing
a view setting or a live frame re-solves nothing, and a live frame reads no key's data (one
scene handler, changes.py, tells live mode's own writes apart).  The GPU batches are stubbed (no
GPU in the background): what is counted is the Python side."""

import bpy
import numpy as np
import pytest
from mathutils import Matrix

from conftest import bent_strip, read_key


@pytest.fixture
def overlay_work(addon, monkeypatch):
    """(onion, plan(): the overlay.Plan a redraw would make now, work(): the counters as a dict)."""
    from bdinterp_blender.view import motion_trails, onion, overlay

    def batches(ghosts):  # one stand-in per batch a GPU would hold
        return {"fills": list(range(len(ghosts.shapes))), "outlines": list(range(len(ghosts.shapes))),
                "trails": "trails" if ghosts.trails.size else None, "chords": "chords",
                "ticks": "ticks" if ghosts.ticks.size else None}
    monkeypatch.setattr(overlay, "batches", batches)

    def plan():
        bpy.context.view_layer.update()  # the depsgraph handler sees what changed
        onion.invalidate()
        return onion.plan(bpy.context)

    def work():
        return dict(paths=motion_trails.counters["paths"], solved=motion_trails.counters["solved"],
                    hashed=onion.counters["hashed"], built=onion.counters["built"])
    onion.on_load()
    return onion, plan, work


def strip_with_overlay():
    obj = bent_strip()
    obj.bdi.target = "Bend"
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    view = bpy.context.scene.bdi_view
    view.ghosts, view.trails, view.ghost_source, view.step, view.samples = True, True, 'FACTORS', 0.25, 33
    return obj, view


def test_moving_selecting_and_view_settings_solve_nothing(overlay_work):
    onion, plan, work = overlay_work
    obj, view = strip_with_overlay()
    first = plan()
    start = work()
    assert start["paths"] >= 1 and start["solved"] >= 33  # the trail's 33 samples (the ghosts among them)
    shapes = first.ghosts  # (batch, colour) pairs: two per ghost
    assert len(shapes) == 6
    # moving the object: drawn with its new matrix, nothing solved or built again
    obj.matrix_world = Matrix.Translation((1.0, 2.0, 0.5)) @ Matrix.Rotation(0.4, 4, 'Z')
    moved = plan()
    assert work() == start
    assert np.allclose(np.array(moved.matrix), np.array(obj.matrix_world))
    # the ghosts in world coordinates follow the object
    ghosts = onion.current(bpy.context)[1]
    m = np.array(obj.matrix_world)
    assert np.allclose(ghosts.in_world(ghosts.shapes), ghosts.shapes @ m[:3, :3].T + m[:3, 3])
    # selecting another object and back, changing colours, opacity and chords: nothing again
    other = bent_strip("Other")
    bpy.context.view_layer.objects.active = obj
    other.select_set(False)
    obj.select_set(True)
    view.opacity, view.before_color, view.chords = 0.3, (0.0, 1.0, 0.0), True
    plan()
    assert work() == start
    # a coarser step and fewer samples: built again from frames already solved
    view.step, view.samples = 0.5, 17
    plan()
    now = work()
    assert now["solved"] == start["solved"] and now["paths"] == start["paths"]
    assert now["built"] == start["built"] + 1


def test_a_live_frame_reads_no_key_and_an_edit_or_a_setting_solves_again(overlay_work, addon):
    onion, plan, work = overlay_work
    obj, view = strip_with_overlay()
    plan()
    addon.set_live(obj, target="Bend", factor=0.2)
    plan()
    start = work()
    for factor in (0.3, 0.4, 0.6, 0.9):  # live frames: the live key written and reported
        obj.bdi.live_factor = factor
        plan()
        live = read_key(obj, "bdi.live")
        assert np.abs(live - read_key(obj, "Basis")).max() > 0.01
    assert work() == start, "a live frame solved or read keys"
    # another's edit of the target key: read, found changed, solved again
    key = obj.data.shape_keys.key_blocks["Bend"]
    co = read_key(obj, "Bend")
    co[:, 2] += 0.05
    key.data.foreach_set("co", co.astype(np.float32).ravel())
    obj.data.shape_keys.update_tag()
    plan()
    edited = work()
    assert edited["hashed"] > start["hashed"] and edited["paths"] == start["paths"] + 1
    assert edited["solved"] > start["solved"]
    # a bake setting (the method): solved again
    obj.bdi.method = 'linear'
    plan()
    assert work()["paths"] == edited["paths"] + 1
    # a script's edit that leaves the data as it was: read, not solved again
    after = work()
    key.data.foreach_set("co", co.astype(np.float32).ravel())
    obj.data.shape_keys.update_tag()
    plan()
    same = work()
    assert same["hashed"] == after["hashed"] + 1 and same["paths"] == after["paths"]
    addon.set_live(obj, enable=False)
