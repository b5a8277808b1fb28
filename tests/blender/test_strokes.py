"""Grease Pencil in-betweens by bdinterp (Blender 4.3+): a script-drawn arm of three strokes swinging
by 120 degrees at the shoulder and 60 more at the elbow (examples/strokes/drawn.py, the second key
drawn with other point counts) keeps every stroke's length, turns the upper arm rigidly, keeps the
elbow and wrist closed and blends radius and opacity; the keys stay as drawn; the operator is one
undo step; a stroke-count mismatch is refused with nothing changed.  Blender's own Interpolate
Sequence on the same arm is measured for comparison."""

import json
import os
import sys

import bpy
import numpy as np
import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "examples", "strokes"))
import drawn  # noqa: E402
import gp_strokes as gps  # noqa: E402

V3 = bpy.app.version >= (4, 3, 0)
needs_v3 = pytest.mark.skipif(not V3, reason="Grease Pencil v3 (Blender 4.3+)")
FRAMES = (1, 13)
MIDDLE = 7


def arm(name="Arm"):
    return gps.gp_object(name, {FRAMES[0]: drawn.arm_key(0), FRAMES[1]: drawn.arm_key(1)})


def size(obj):
    pts = np.concatenate([s["points"] for f in FRAMES for s in gps.strokes_at(obj, f)])
    return float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))


def snapshot(obj):
    layer = obj.data.layers[0]
    return [(f.frame_number, [(s["points"].tobytes(), s["radius"].tobytes(), s["opacity"].tobytes())
                              for s in gps.strokes_at(obj, f.frame_number)]) for f in layer.frames]


@needs_v3
def test_arm_inbetweens_keep_their_shape(addon):
    obj = arm()
    before, scale = snapshot(obj), size(obj)
    assert addon.interpolate_drawing(obj, *FRAMES, count=3) == [4, 7, 10]
    layer = obj.data.layers["Arm"]
    kinds = {f.frame_number: f.keyframe_type for f in layer.frames}
    assert kinds == {1: 'KEYFRAME', 4: 'BREAKDOWN', 7: 'BREAKDOWN', 10: 'BREAKDOWN', 13: 'KEYFRAME'}
    keys = [gps.strokes_at(obj, f) for f in FRAMES]
    report = {}
    for frame in (4, 7, 10):
        t = (frame - 1) / 12.0
        strokes = gps.strokes_at(obj, frame)
        assert len(strokes) == 3
        for k, s in enumerate(strokes):
            length = drawn.length(s["points"])
            for key in keys:
                assert abs(length - drawn.length(key[k]["points"])) <= 0.01 * drawn.length(key[k]["points"])
            # both keys are drawn with evenly spaced points: the pairs sit at even arc fractions
            u = np.linspace(0.0, 1.0, len(s["points"]))
            np.testing.assert_allclose(s["radius"], (1 - t) * (0.02 + 0.03 * u) + t * 0.03, atol=1e-6)
            np.testing.assert_allclose(s["opacity"], 1 - 0.5 * t, atol=1e-6)
        elbow = np.linalg.norm(strokes[0]["points"][-1] - strokes[1]["points"][0])
        wrist = np.linalg.norm(strokes[1]["points"][-1] - strokes[2]["points"][0])
        assert max(elbow, wrist) <= 1e-3 * scale
        report[frame] = {"elbow": float(elbow) / scale, "wrist": float(wrist) / scale,
                         "length_kept": [drawn.length(s["points"]) / drawn.length(key["points"])
                                         for s, key in zip(strokes, keys[0])]}
    # half way the upper arm is the first key's turned rigidly by 60 degrees about the shoulder
    upper = gps.strokes_at(obj, MIDDLE)[0]["points"]
    rigid = gps.xz(drawn.turn(drawn.arc((0, 0), -90, 2.0, 0, len(upper)), drawn.SHOULDER_TURN / 2))
    report["upper_arm_off_rigid"] = float(np.abs(upper - rigid).max()) / scale
    assert report["upper_arm_off_rigid"] <= 0.02
    assert snapshot(obj)[0] == before[0] and snapshot(obj)[-1] == before[-1]   # the keys as drawn
    print("JSON:" + json.dumps({"bdinterp_arm": report}))


@needs_v3
def test_a_tail_curling_up_keeps_its_length(addon):
    obj = gps.gp_object("Tail", {FRAMES[0]: drawn.tail_key(0), FRAMES[1]: drawn.tail_key(1)})
    addon.interpolate_drawing(obj, *FRAMES, count=3)
    key = drawn.length(gps.strokes_at(obj, 1)[0]["points"])
    kept = [drawn.length(gps.strokes_at(obj, f)[0]["points"]) / key for f in (4, 7, 10)]
    assert all(abs(k - 1) <= 0.01 for k in kept)
    print("JSON:" + json.dumps({"bdinterp_tail": kept}))


@needs_v3
def test_a_cyclic_stroke_stays_a_ring(addon):
    ring = drawn.arc((1.0, 0.0), 90, 2 * np.pi, 360, 41)[:-1]     # a circle, its closing segment implicit
    squashed = drawn.turn(ring * [1.5, 0.6], 40)
    obj = gps.gp_object("Eye", {f: [(p, np.full(len(p), 0.02), np.ones(len(p)))]
                                for f, p in zip(FRAMES, (ring, squashed[::2]))})
    for f in obj.data.layers[0].frames:
        f.drawing.strokes[0].cyclic = True
    addon.interpolate_drawing(obj, *FRAMES, count=1)
    (mid,) = [f.drawing.strokes[0] for f in obj.data.layers[0].frames if f.frame_number == MIDDLE]
    assert mid.cyclic and len(mid.points) == 40
    points = gps.strokes_at(obj, MIDDLE)[0]["points"]
    closing = np.linalg.norm(points[0] - points[-1])
    assert closing <= 2.0 * np.linalg.norm(points[1] - points[0])   # the ring's own spacing, not a gap


@needs_v3
def test_the_operator_is_one_undo_step(addon):
    obj = arm()
    bpy.context.view_layer.objects.active = obj
    bpy.context.scene.frame_set(5)
    bpy.ops.ed.undo_push(message="before interpolating")
    before = snapshot(obj)
    # As from the UI: EXEC with an undo push (scripts' bpy.ops calls push none by default).
    assert bpy.ops.bdinterp.interpolate_drawing('EXEC_DEFAULT', True, count=2, easing='EASE_IN_OUT') == {'FINISHED'}
    obj = bpy.data.objects["Arm"]
    assert [f.frame_number for f in obj.data.layers[0].frames] == [1, 5, 9, 13]
    bpy.ops.ed.undo()
    assert snapshot(bpy.data.objects["Arm"]) == before


@needs_v3
def test_a_stroke_count_mismatch_is_refused_with_nothing_changed(addon):
    keys = {FRAMES[0]: drawn.arm_key(0), FRAMES[1]: drawn.arm_key(1) + [drawn.arm_key(1)[2]]}
    obj = gps.gp_object("Arm", keys)
    bpy.context.view_layer.objects.active = obj
    bpy.context.scene.frame_set(1)
    before = snapshot(obj)
    message = r"Arm, layer 'Arm': frame 1 has 3 strokes and frame 13 has 4: strokes \[3\] of frame 13 have no partner"
    with pytest.raises(RuntimeError, match=message):
        bpy.ops.bdinterp.interpolate_drawing(count=3)
    with pytest.raises(addon.BakeError, match=message):
        addon.interpolate_drawing(obj, *FRAMES, count=3)
    assert snapshot(obj) == before
    # asked to, the stroke left over fades in where it is drawn
    assert addon.interpolate_drawing(obj, *FRAMES, count=3, fade=True) == [4, 7, 10]
    extra = gps.strokes_at(obj, FRAMES[1])[3]
    for frame in (4, 7, 10):
        strokes = gps.strokes_at(obj, frame)
        assert len(strokes) == 4
        np.testing.assert_array_equal(strokes[3]["points"], extra["points"])
        np.testing.assert_allclose(strokes[3]["opacity"], (frame - 1) / 12.0 * extra["opacity"], atol=1e-6)


@needs_v3
def test_all_layers_and_only_selected_strokes(addon):
    obj = arm()
    tail = obj.data.layers.new("Tail")
    for frame, key in zip(FRAMES, (0, 1)):
        d = tail.frames.new(frame).drawing
        (p, radius, opacity), = drawn.tail_key(key)
        d.add_strokes([len(p)])
        for q, co in zip(d.strokes[0].points, gps.xz(p)):
            q.position = tuple(co)
        d.strokes[0].select = True
    arm_layer = obj.data.layers["Arm"]
    for f in arm_layer.frames:                       # the forearm and hand selected in both keys
        for k, s in enumerate(f.drawing.strokes):
            s.select = k > 0
    obj.data.layers.active = arm_layer
    bpy.context.scene.frame_set(1)
    bpy.ops.object.mode_set(mode='EDIT')            # where strokes are selected
    try:
        assert bpy.ops.bdinterp.interpolate_drawing(layers='ALL', use_selection=True, spacing='STEP',
                                                    step=4) == {'FINISHED'}
    finally:
        bpy.ops.object.mode_set(mode='OBJECT')
    for layer, strokes in ((arm_layer, 2), (tail, 1)):
        assert [f.frame_number for f in layer.frames] == [1, 5, 9, 13]
        assert all(len(f.drawing.strokes) == strokes for f in layer.frames if f.frame_number in (5, 9))
    # the in-betweens' first stroke is the keys' forearm (the second stroke there), its length kept
    key = drawn.length(gps.strokes_at(obj, 1)[1]["points"])
    for frame in (5, 9):
        assert abs(drawn.length(gps.strokes_at(obj, frame)[0]["points"]) - key) <= 0.01 * key


@needs_v3
def test_blenders_own_interpolate_sequence_on_the_arm(addon):
    """Blender's tool moves every point on its chord: the arm shrinks half way (measured here so
    that the comparison in README and the gallery is this Blender's)."""
    report = {}
    for flip in ('NONE', 'AUTO'):
        obj = arm("Arm " + flip)
        scale = size(obj)
        gps.blender_interpolate(obj, FRAMES[0], step=3, flip=flip)
        strokes, key = gps.strokes_at(obj, MIDDLE), gps.strokes_at(obj, FRAMES[0])
        report[flip] = {"length_kept": [drawn.length(s["points"]) / drawn.length(k["points"])
                                        for s, k in zip(strokes, key)],
                        "elbow": float(np.linalg.norm(strokes[0]["points"][-1] - strokes[1]["points"][0])) / scale,
                        "wrist": float(np.linalg.norm(strokes[1]["points"][-1] - strokes[2]["points"][0])) / scale}
        bpy.data.objects.remove(obj)
    # the upper arm's points on chords across a 120-degree turn: cos 60 = half its length
    assert report['NONE']["length_kept"][0] == pytest.approx(0.5, abs=0.02)
    print("JSON:" + json.dumps({"blender_arm": report}))


@pytest.mark.skipif(V3, reason="Blender 4.3+ interpolates drawings (see above)")
def test_before_4_3_the_panel_says_what_it_needs(addon):
    from bdinterp_blender.strokes import drawing
    assert drawing.why_not() == "interpolating drawings needs Blender 4.3 or later (Grease Pencil v3)"
    with pytest.raises(addon.BakeError, match="needs Blender 4.3 or later"):
        addon.interpolate_drawing(None, 1, 13)
    assert hasattr(bpy.types, "BDINTERP_PT_drawing")
    assert not bpy.ops.bdinterp.interpolate_drawing.poll()


def test_the_panel_offers_the_operator_or_says_what_it_needs(addon):
    from test_ui import Layout
    if V3:
        arm()
    else:   # Blender's own Grease Pencil (v2) before 4.3
        obj = bpy.data.objects.new("Drawing", bpy.data.grease_pencils.new("Drawing"))
        bpy.context.scene.collection.objects.link(obj)
        bpy.context.view_layer.objects.active = obj
    log = []
    cls = bpy.types.BDINTERP_PT_drawing
    assert cls.poll(bpy.context)
    cls.draw(type("P", (), {"layout": Layout(log)})(), bpy.context)
    assert log == [("operator", "bdinterp.interpolate_drawing") if V3 else
                   ("label", "Interpolating drawings needs Blender 4.3 or later (Grease Pencil v3)")]


@needs_v3
def test_a_drawing_of_200_strokes(addon):
    """scripts/bench_strokes.py's drawing (200 strokes of 100 points) in Blender: 10 in-betweens,
    every stroke there with its length between the keys' (the time is printed for BENCHMARKS)."""
    import time
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    import bench_strokes
    a, b = bench_strokes.drawing(200, 100)
    keys = {f: [(p, np.full(100, 0.01), np.ones(100)) for p in key] for f, key in zip((1, 12), (a, b))}
    coll = bpy.data.grease_pencils_v3 if hasattr(bpy.data, "grease_pencils_v3") else bpy.data.grease_pencils
    obj = bpy.data.objects.new("Hair", coll.new("Hair"))
    bpy.context.scene.collection.objects.link(obj)
    layer = obj.data.layers.new("Hair")
    for frame, strokes in keys.items():   # written at once (200 x 100 points one by one is slow)
        d = layer.frames.new(frame).drawing
        d.add_strokes([100] * 200)
        d.attributes["position"].data.foreach_set(
            "vector", np.concatenate([gps.xz(p) for p, _, _ in strokes]).astype(np.float32).ravel())
    start = time.perf_counter()
    assert addon.interpolate_drawing(obj, 1, 12, count=10) == list(range(2, 12))
    seconds = time.perf_counter() - start
    for frame in (2, 7, 11):
        d = next(f.drawing for f in layer.frames if f.frame_number == frame)
        assert len(d.strokes) == 200
        P = np.empty(200 * 100 * 3, dtype=np.float32)
        d.attributes["position"].data.foreach_get("vector", P)
        lengths = [drawn.length(p) for p in P.reshape(200, 100, 3)]
        lo, hi = np.minimum(*[[drawn.length(p) for p in k] for k in (a, b)]), np.maximum(
            *[[drawn.length(p) for p in k] for k in (a, b)])
        assert np.all(lengths >= lo * (1 - 1e-4)) and np.all(lengths <= hi * (1 + 1e-4))
    print("JSON:" + json.dumps({"blender_200_strokes_seconds": seconds}))
