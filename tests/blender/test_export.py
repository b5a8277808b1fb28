"""Bake for Export: the slider's playback as keyframes that Blender's exporters carry.

Three characters (examples/character as one object, examples/cutout as one object and as seven
objects) are baked, their slider keyframed over 24 frames with Blender's default (eased) Bezier
keys, and what Blender shows at each frame is recorded; so is examples/face's head grid after
Bake Grid (n = 2), its angle_x keyframed and its angle_y driven by a keyframed bone. After Bake
for Export Blender shows the same; FBX and Alembic exports re-imported show it too. The glTF files (before and after Bake for
Export) and the recorded frames go to build/runtime/blender-X.Y, where tests/runtime plays them
in three.js on the host (the chroots have no node).
"""

import importlib
import json
import os
import shutil
import sys

import bpy
import numpy as np
import pytest

from conftest import ROOT, fcurves

sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402

FRAMES = (1, 24)
BOUND = 1e-5       # of the character's size, at every frame and vertex
OUT = os.path.join(ROOT, "build", "runtime", "blender-%d.%d" % bpy.app.version[:2])
CASES = ("character", "cutout_one", "cutout_seven", "face_grid")


def seams(obj):
    """A UV map cut along every edge (each face's UVs shifted apart), so that glTF splits vertices."""
    me = obj.data
    uv = me.uv_layers.new(name="UVMap")
    loops = np.array([v for p in me.polygons for v in p.vertices])
    face = np.repeat(np.arange(len(me.polygons)), [p.loop_total for p in me.polygons])
    co = np.array([me.vertices[v].co[:2] for v in loops]) + np.c_[face % 7, face // 7 % 5] * 10.0
    uv.data.foreach_set("uv", co.astype(np.float32).ravel())


def character(bd):
    """examples/character as one object 'Character' with keys Basis and TARGET."""
    io = importlib.import_module(bd.__name__ + ".io")
    V, F = io.read_obj(os.path.join(ROOT, "examples", "character", "source.obj"))[:2]
    Y = io.read_obj(os.path.join(ROOT, "examples", "character", "target.obj"))[0]
    flat = [np.c_[X[:, :2], np.zeros(len(X))] for X in (V, Y)]
    obj = cb.new_object("Character", flat[0], [tuple(int(i) for i in f) for f in F], flat[1])
    bpy.context.view_layer.objects.active = obj
    return [obj]


def face_grid():
    """examples/face with its head grid baked (Bake Grid, n = 2), angle_x keyframed from -30 to 30
    and the neck bone (which drives angle_y) from 0.4 to -0.4 radians."""
    sys.path.insert(0, os.path.join(ROOT, "examples", "face"))
    import face_blender
    obj, paths = face_blender.build()
    bd_addon = importlib.import_module("bdinterp_blender")
    bd_addon.bake_grid(obj, "head", n=2)
    seams(obj)
    neck = bpy.data.objects["Rig"].pose.bones["Neck"]
    for frame, x, turn in ((FRAMES[0], -30.0, 0.4), (FRAMES[1], 30.0, -0.4)):
        obj.bdi_grids["head"].params["angle_x"].amount = x
        obj.keyframe_insert(paths["head"]["angle_x"], frame=frame)
        neck.rotation_euler.z = turn
        neck.keyframe_insert("rotation_euler", index=2, frame=frame)
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = FRAMES
    bpy.ops.object.select_all(action='DESELECT')
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    return [obj]


def build(case, bd):
    """The objects of a case, baked (4 in-betweens), the active one's slider keyframed 0 -> 1."""
    if case == "face_grid":
        return face_grid()
    if case == "character":
        objs = character(bd)
    else:
        pieces = cc.character()[0]
        objs = [cb.one_object(pieces)[0]] if case == "cutout_one" else cb.seven_objects(pieces)
    for obj in objs:
        seams(obj)
    bd_addon = importlib.import_module("bdinterp_blender")
    bd_addon.bake(objs, cb.TARGET, count=4)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = FRAMES
    owner, slider = objs[0], cb.TARGET + ".bdi"
    for frame, value in zip(FRAMES, (0.0, 1.0)):
        owner[slider] = value
        owner.keyframe_insert('["%s"]' % slider, frame=frame)
    return objs


def world_frames(objs):
    """{object name: (frames, n, 3)} of the evaluated world vertices at every frame."""
    scene, out = bpy.context.scene, {o.name: [] for o in objs}
    for f in range(FRAMES[0], FRAMES[1] + 1):
        scene.frame_set(f)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        for obj in objs:
            ev = obj.evaluated_get(depsgraph)
            co = np.empty(len(ev.data.vertices) * 3, dtype=np.float32)
            ev.data.vertices.foreach_get("co", co)
            m = np.array(ev.matrix_world)
            out[obj.name].append(co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3])
    return {k: np.array(v) for k, v in out.items()}


def size_of(frames):
    """The character's size: the larger bounding-box diagonal of its first and last frame."""
    every = np.concatenate(list(frames.values()), axis=1)
    return max(float(np.linalg.norm(np.ptp(every[i], axis=0))) for i in (0, -1))


def match(rest, other_rest):
    """For each vertex of other_rest (m, 3), the vertex of rest (n, 3) at its place, checking that
    every vertex of rest is hit and each hit is exact to float32."""
    d = np.linalg.norm(other_rest[:, None, :] - rest[None, :, :], axis=2)
    near = d.argmin(axis=1)
    scale = np.abs(rest).max() + 1.0
    assert d[np.arange(len(near)), near].max() < 1e-5 * scale, "a vertex without a counterpart"
    assert set(near.tolist()) == set(range(len(rest))), "vertices missing"
    return near


def frame_error(truth, frames):
    """Largest distance of a vertex from Blender's at any frame, objects matched by name and
    vertices by rest position."""
    err = 0.0
    for name, T in truth.items():
        X = frames[name]
        near = match(T[0], X[0])
        err = max(err, float(np.linalg.norm(X - T[:, near], axis=2).max()))
    return err


def drivers(objs):
    """(data path, muted) of every shape-key driver of objs."""
    return [[(d.data_path, d.mute) for d in o.data.shape_keys.animation_data.drivers] for o in objs]


def export_gltf(path):
    bpy.ops.export_scene.gltf(filepath=path, export_format='GLB', export_animations=True)


def reimport(export, load):
    """Export the scene with `export(path)`, load the file into an empty scene with `load(path)`, and
    return the imported objects' world frames by name."""
    path = os.path.join(OUT, "roundtrip")
    export(path)
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = FRAMES
    load(path)
    return world_frames([o for o in bpy.context.scene.objects if o.type == 'MESH'])


@pytest.fixture(scope="module", params=CASES)
def baked(request, addon, bd):
    """(case, its .blend after Bake for Export, Blender's frames before it, size, drivers before)."""
    case = request.param
    os.makedirs(OUT, exist_ok=True)
    bpy.ops.wm.read_homefile(use_empty=True)
    objs = build(case, bd)
    truth = world_frames(objs)
    before = drivers(objs)
    export_gltf(os.path.join(OUT, case + ".before.glb"))
    assert bpy.ops.bdinterp.bake_export() == {'FINISHED'}  # the active object and the selected
    path = os.path.join(OUT, case + ".blend")
    bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
    return case, path, truth, size_of(truth), before


def objects(truth):
    return [bpy.data.objects[name] for name in truth]


def test_bake_for_export_shows_and_exports_what_the_slider_showed(baked):
    case, path, truth, size, before = baked
    bpy.ops.wm.open_mainfile(filepath=path)
    objs = objects(truth)
    moving = max(float(np.linalg.norm(T - T[0], axis=2).max()) for T in truth.values())
    assert moving > 0.1 * size  # the slider moves the character
    assert not any(m for d in before for _, m in d)
    assert drivers(objs) == [[(p, True) for p, _ in d] for d in before]  # every driver muted
    for obj in objs:  # one linear keyframe a frame on every driven key
        for fc in fcurves(obj.data.shape_keys.animation_data):
            assert [k.co[0] for k in fc.keyframe_points] == list(range(FRAMES[0], FRAMES[1] + 1))
            assert {k.interpolation for k in fc.keyframe_points} == {'LINEAR'}
    assert frame_error(truth, world_frames(objs)) <= BOUND * size
    export_gltf(os.path.join(OUT, case + ".glb"))
    np.savez(os.path.join(OUT, case + ".npz"), **truth)
    with open(os.path.join(OUT, case + ".json"), "w") as f:
        json.dump({"frames": FRAMES, "fps": bpy.context.scene.render.fps, "size": size,
                   "blender": bpy.app.version_string}, f)


def glb_animations(path):
    """The names of a .glb's animations (its JSON chunk)."""
    with open(path, "rb") as f:
        data = f.read()
    length = int.from_bytes(data[12:16], "little")
    return sorted(a.get("name", "") for a in json.loads(data[20:20 + length]).get("animations", []))


def test_bake_for_export_names_the_actions_after_the_slider(baked):
    case, path, truth, _, _ = baked
    bpy.ops.wm.open_mainfile(filepath=path)
    objs = objects(truth)
    slider = "head" if case == "face_grid" else cb.TARGET + ".bdi"  # the grid's name, or the slider
    others = ["RigAction"] if case == "face_grid" else []  # the face's bones have an action too
    names = [o.data.shape_keys.animation_data.action.name for o in objs]
    glb = os.path.join(OUT, case + ".named.glb")
    export_gltf(glb)
    if bpy.app.version >= (4, 4, 0):  # slotted actions: one action, a slot per piece
        assert names == [slider] * len(objs)
        assert len({o.data.shape_keys.animation_data.action_slot.handle for o in objs}) == len(objs)
        assert glb_animations(glb) == sorted([slider] + others)
    else:  # one action per piece, the slider's name then the piece's
        assert names == ["%s|%s" % (slider, o.name) for o in objs]
        assert glb_animations(glb) == sorted(names + others)
        # one clip (docs/KEYFRAMES.md): the active actions merged under the slider's name
        options = bpy.ops.export_scene.gltf.get_rna_type().properties.keys()
        merged = (dict(export_animation_mode='ACTIVE_ACTIONS') if "export_animation_mode" in options
                  else dict(export_nla_strips=False))
        bpy.ops.export_scene.gltf(filepath=glb, export_format='GLB', export_animations=True,
                                  export_nla_strips_merged_animation_name=slider, **merged)
        assert glb_animations(glb) == [slider]


def test_remove_export_bake_restores_the_drivers(baked):
    case, path, truth, size, before = baked
    bpy.ops.wm.open_mainfile(filepath=path)
    objs = objects(truth)
    assert bpy.ops.bdinterp.remove_export() == {'FINISHED'}
    assert drivers(objs) == before
    for obj in objs:
        assert obj.data.shape_keys.animation_data.action is None and "bdi_export" not in obj.keys()
    assert frame_error(truth, world_frames(objs)) <= BOUND * size


def test_fbx_round_trip(baked):
    case, path, truth, size, _ = baked
    bpy.ops.wm.open_mainfile(filepath=path)
    frames = reimport(lambda p: bpy.ops.export_scene.fbx(filepath=p + ".fbx", bake_anim=True),
                      lambda p: bpy.ops.import_scene.fbx(filepath=p + ".fbx"))
    err = frame_error(truth, frames)
    print("FBX %s: max vertex error / size %.3g" % (case, err / size))
    assert err <= BOUND * size


def test_alembic_round_trip(baked):
    case, path, truth, size, _ = baked
    try:
        bpy.ops.wm.alembic_export.get_rna_type()
    except KeyError:  # Debian's Blender 3.4 is built without Alembic
        pytest.skip("this Blender is built without Alembic")
    bpy.ops.wm.open_mainfile(filepath=path)
    frames = reimport(lambda p: bpy.ops.wm.alembic_export(filepath=p + ".abc", start=FRAMES[0],
                                                          end=FRAMES[1]),
                      lambda p: bpy.ops.wm.alembic_import(filepath=p + ".abc"))
    err = frame_error(truth, frames)
    print("Alembic %s: max vertex error / size %.3g" % (case, err / size))
    assert err <= BOUND * size


def state(objs):
    """Everything Bake for Export could change: custom properties, actions, driver mutes."""
    return [(sorted(o.keys()), drivers([o]),
             [a.name for a in bpy.data.actions]) for o in objs]


def test_bake_for_export_refuses_without_a_bake_or_an_animated_slider(addon, bd):
    from bdinterp_blender import BakeError, bake, bake_for_export
    obj = character(bd)[0]
    with pytest.raises(BakeError, match="'Character' has no baked in-betweens"):
        bake_for_export(obj)
    bake(obj, cb.TARGET, count=2)
    before = state([obj])
    with pytest.raises(BakeError, match="slider 'Pose.bdi' on 'Character' is not animated"):
        bake_for_export([obj])
    with pytest.raises(RuntimeError, match="is not animated"):  # the operator reports it
        bpy.ops.bdinterp.bake_export()
    assert state([obj]) == before
    obj.keyframe_insert('["Pose.bdi"]', frame=1)
    before = state([obj])
    with pytest.raises(BakeError, match="frame range 5..4 is empty"):
        bake_for_export(obj, frame_start=5, frame_end=4)
    assert state([obj]) == before


def test_bake_for_export_keys_the_given_range_and_replaces_an_earlier_one(addon, bd):
    from bdinterp_blender import bake, bake_for_export
    obj = character(bd)[0]
    bake(obj, cb.TARGET, count=2)
    for frame, value in ((3, 0.0), (7, 1.0)):
        obj["Pose.bdi"] = value
        obj.keyframe_insert('["Pose.bdi"]', frame=frame)
    bpy.context.scene.frame_set(5)
    bake_for_export(obj, frame_start=3, frame_end=10)
    bake_for_export(obj, frame_start=2, frame_end=8)  # replaces: drivers, not its own keys, sampled
    assert bpy.context.scene.frame_current == 5
    curves = fcurves(obj.data.shape_keys.animation_data)
    assert len(curves) == 3  # two in-betweens and the target
    slider = obj.animation_data.action
    for fc in curves:
        kb = obj.data.shape_keys.path_resolve(fc.data_path.rsplit(".", 1)[0])
        driver = obj.data.shape_keys.animation_data.drivers.find(fc.data_path)
        assert [k.co[0] for k in fc.keyframe_points] == list(range(2, 9))
        for k in fc.keyframe_points:  # the driver's expression at the slider's value, by hand
            s = fcurves(obj.animation_data)[0].evaluate(k.co[0])
            expected = eval(driver.driver.expression, {"min": min, "max": max}, {"s": s})
            assert abs(k.co[1] - expected) < 1e-6, (kb.name, k.co[0])
    assert slider is not None


def test_a_character_follows_a_vertex_anchor_of_its_active_object(addon):
    # The paper's vertex anchor moves on the chord between its source and target positions; the
    # active object's vertices come first in the character, so its index is the object's own.
    from bdinterp_blender import bake
    pieces = cc.character()[0]
    objs = cb.seven_objects(pieces)
    hand = bpy.data.objects["Hand"]
    order = [hand] + [o for o in objs if o != hand]
    r = bake(order, cb.TARGET, count=3, anchor=2)
    assert r.objects == 7
    m = np.array(hand.matrix_world)
    src, tgt = (cb.read(hand, k)[2] @ m[:3, :3].T + m[:3, 3] for k in ("Basis", cb.TARGET))
    size = cb.size_of(pieces)
    assert np.linalg.norm(tgt - src) > 0.1 * size
    for name, t in zip(cb.baked(hand), r.factors):
        X = cb.read(hand, name)[2] @ m[:3, :3].T + m[:3, 3]
        assert np.linalg.norm(X - ((1 - t) * src + t * tgt)) < 1e-5 * size, name
