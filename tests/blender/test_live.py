"""Live mode: keyframed factor/weights, frame stepping, save/reload, rendering, errors."""

import glob
import os

import bpy
import numpy as np
import pytest

from conftest import (TOL, USER_ENV, add_key, bent_strip, evaluated_co, fcurve, fcurves, maxdiff, read_key,
                      run_blender, triangles, two_pieces)

FRAMES = (1, 3, 6, 8, 11)


def keyframe_factor(obj, values):
    for frame, value in values.items():
        obj.bdi.live_factor = value
        obj.keyframe_insert("bdi.live_factor", frame=frame)
    return fcurve(obj.animation_data, "bdi.live_factor")


def check_frames(bd, obj, curve):
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    for frame in FRAMES:
        bpy.context.scene.frame_set(frame)
        t = curve.evaluate(frame)
        assert maxdiff(evaluated_co(obj), bd.interpolate(S, T, faces, t)) < TOL, frame


def test_live_follows_keyframed_factor_and_survives_reload(addon, bd, tmp_path):
    obj = bent_strip()
    obj.bdi.target = "Bend"
    curve = keyframe_factor(obj, {1: 0.0, 6: 0.7, 11: 1.0})
    obj.bdi.live = True
    assert obj.bdi.live and not obj.bdi.live_error
    live_key = obj.data.shape_keys.key_blocks["bdi.live"]
    assert live_key.relative_key.name == "Basis" and live_key.value == 1.0
    check_frames(bd, obj, curve)
    path = os.path.join(str(tmp_path), "live.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects["Strip"]
    assert obj.bdi.live
    check_frames(bd, obj, fcurve(obj.animation_data, "bdi.live_factor"))


def test_live_factor_change_updates_without_frame_change(addon, bd):
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.3)
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    assert maxdiff(evaluated_co(obj), bd.interpolate(S, T, faces, 0.3)) < TOL
    obj.bdi.live_factor = 0.8
    assert maxdiff(evaluated_co(obj), bd.interpolate(S, T, faces, 0.8)) < TOL


def test_live_pose_blend_with_keyframed_weights(addon, bd):
    obj = two_pieces()
    wide = read_key(obj, "Basis") * [1.4, 1.0, 1.0]
    add_key(obj, "Wide", wide)
    addon.set_live(obj, weights={"Move": 0.0, "Wide": 0.0})
    poses = obj.bdi.poses
    for frame, (a, b) in {1: (0.0, 0.0), 5: (0.5, 0.3), 9: (0.2, 0.8)}.items():
        poses[0].weight, poses[1].weight = a, b
        obj.keyframe_insert('bdi.poses[0].weight', frame=frame)
        obj.keyframe_insert('bdi.poses[1].weight', frame=frame)
    shapes = [read_key(obj, n) for n in ("Basis", "Move", "Wide")]
    faces = triangles(obj)
    for frame, (a, b) in {5: (0.5, 0.3), 9: (0.2, 0.8)}.items():
        bpy.context.scene.frame_set(frame)
        w = [1 - a - b, a, b] if a + b <= 1 else [0.0, a / (a + b), b / (a + b)]
        assert maxdiff(evaluated_co(obj), bd.blend(shapes, faces, w)) < TOL, frame


def test_live_turns_off_on_error_with_one_message(addon, capsys):
    obj = bent_strip()
    addon.set_live(obj, target="Bend", factor=0.5)
    kb = obj.data.shape_keys.key_blocks["Bend"]
    kb.data[5].co.z += 0.1  # the target is no longer planar
    for frame in (2, 3, 4, 5):
        bpy.context.scene.frame_set(frame)  # no exception escapes, no message per frame
    assert not obj.bdi.live
    assert "not planar" in obj.bdi.live_error
    assert capsys.readouterr().out.count("live mode turned off") == 1


def test_live_rejects_bad_input_at_enable(addon):
    obj = bent_strip()
    with pytest.raises(ValueError, match="is the source key"):
        addon.set_live(obj, target="Basis")
    assert not obj.bdi.live


def render_scene(obj):
    """Tiny deterministic Workbench render of the strip seen from above (alpha = silhouette)."""
    scene = bpy.context.scene
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    cam.data.type, cam.data.ortho_scale = 'ORTHO', 3.2
    cam.location = (0.0, 0.5, 5.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.engine = 'BLENDER_WORKBENCH'
    scene.render.resolution_x = scene.render.resolution_y = 64
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.render.image_settings.file_format = 'PNG'
    scene.display.render_aa = 'OFF'
    scene.display.shading.light = 'FLAT'
    scene.display.shading.color_type = 'SINGLE'
    scene.frame_start, scene.frame_end = 1, 3


def rendered(folder):
    out = []
    for path in sorted(glob.glob(os.path.join(folder, "*.png"))):
        img = bpy.data.images.load(path)
        px = np.empty(len(img.pixels), dtype=np.float32)
        img.pixels.foreach_get(px)
        out.append(px)
    return out


def reference_file(obj, shapes, tmp):
    """Save tmp/ref.blend with keys 'Ref<frame>' holding shapes {frame: (n, 3)}, each keyframed
    (constant) to show on its frame only: the reference of a render test. Returns its path."""
    for frame, co in shapes.items():
        kb = add_key(obj, "Ref%d" % frame, co)
        for f in shapes:
            kb.value = 1.0 if f == frame else 0.0
            kb.keyframe_insert("value", frame=f)
    for fc in fcurves(obj.data.shape_keys.animation_data):
        for kp in fc.keyframe_points:
            kp.interpolation = 'CONSTANT'
    path = os.path.join(tmp, "ref.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path


def render_pair(tmp, live_path, ref_path, failure, differ):
    """Render both files with `blender -b FILE -a` (the add-on enabled for the first; `failure`
    must not be in its output): three frames each, the same pictures (a stray pixel allowed),
    the first and last frames differing in more than `differ` of the pixels."""
    out = []
    for name, path, addons in (("live_out", live_path, ["--addons", "bdinterp_blender"]),
                               ("ref_out", ref_path, [])):
        folder = os.path.join(tmp, name)
        proc = run_blender([path] + addons + ["-o", folder + "/f_####", "-a"],
                           env_drop=() if addons else USER_ENV)
        assert proc.returncode == 0, proc.stderr[-2000:]
        assert failure not in proc.stdout, proc.stdout[-2000:]
        out.append(rendered(folder))
    live, ref = out
    assert len(live) == len(ref) == 3
    for a, b in zip(live, ref):
        assert np.mean(np.abs(a - b) > 1e-3) < 0.002
    assert np.mean(np.abs(live[0] - live[2]) > 1e-3) > differ


def test_live_renders_with_blender_b_a(addon, bd, tmp_path):
    """`blender -b file.blend -a` renders the live result of each frame: the frames equal
    renders of a plain file holding the expected shapes as keyframed shape keys."""
    tmp = str(tmp_path)
    obj = bent_strip()
    render_scene(obj)
    obj.bdi.target = "Bend"
    keyframe_factor(obj, {1: 0.0, 3: 1.0})
    bpy.context.scene.frame_set(1)
    obj.bdi.live = True
    live_path = os.path.join(tmp, "live.blend")
    bpy.ops.wm.save_as_mainfile(filepath=live_path)
    # reference: same scene, live off, the exact in-betweens as ordinary keys switched per frame
    S, T, faces = read_key(obj, "Basis"), read_key(obj, "Bend"), triangles(obj)
    obj.bdi.live = False
    obj.data.shape_keys.key_blocks["bdi.live"].value = 0.0
    ref_path = reference_file(obj, {frame: bd.interpolate(S, T, faces, t)
                                    for frame, t in ((1, 0.0), (2, 0.5), (3, 1.0))}, tmp)
    render_pair(tmp, live_path, ref_path, "live mode turned off", differ=0.02)


def test_key_coordinates_written_and_read_whole_are_blenders_own():
    """mesh_io writes and reads a key through ShapeKey.points where Blender has it (the whole
    array at once): what it writes is what kb.data reads point by point, and the other way."""
    from bdinterp_blender.shapes import mesh_io
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=20, y_subdivisions=30, size=2)
    obj = bpy.context.active_object
    obj.shape_key_add(name="Basis")
    kb = obj.shape_key_add(name="k")
    assert (mesh_io.points(kb) == kb.points) if bpy.app.version >= (4, 1, 0) else \
        (mesh_io.points(kb) == kb.data)
    co = np.random.default_rng(3).normal(size=(len(obj.data.vertices), 3))
    mesh_io.write_co(kb, co)
    assert np.array_equal(read_key(obj, "k"), co.astype(np.float32).astype(np.float64))
    kb.data[7].co = (1.5, -2.25, 0.125)
    assert np.array_equal(mesh_io.read_co(kb)[7], [1.5, -2.25, 0.125])
    assert np.array_equal(mesh_io.read_co(kb), read_key(obj, "k"))
