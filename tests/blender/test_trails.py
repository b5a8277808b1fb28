"""Motion trails (bdinterp_blender.trails): the points are the solver's frames in world space, for
one transformed object and for examples/cutout's seven-object character; computed here from the
keys with the core directly (its own triangulation, layers and world transforms); the overlay's
ghosts (baked keys, factors, and the frames either side of the current one) likewise."""

import math
import os
import sys

import bpy
import numpy as np
import pytest
from mathutils import Euler, Matrix, Vector

from conftest import ROOT, bent_strip, path_object, read_key, triangles

sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402

EXACT = 1e-9  # relative to the size: the same frames, up to the world transform's roundoff


def world(matrix, co):
    m = np.array(matrix, dtype=np.float64)
    return co @ m[:3, :3].T + m[:3, 3]


def layered(bd, shapes, tris):
    """Layered 3D shapes with every piece put exactly into its plane, as the add-on reads keys
    (float32 coordinates are planar to ~1e-7 only)."""
    layers = bd.Layers.fit(shapes, tris, base=0, tolerance=1e-4)
    return [layers.to_space(x, np.eye(len(shapes))[i]) for i, x in enumerate(layers.to_plane(shapes))]


def core_frames(bd, shapes, tris, ts):
    return bd.Interpolator(layered(bd, shapes, tris), tris).frames(ts)


def test_trails_of_one_transformed_object_are_its_frames_in_world_space(addon, bd):
    obj = bent_strip()
    obj.matrix_world = Matrix.LocRotScale(Vector((1.0, -2.0, 0.5)), Euler((0.4, -0.3, 1.1)),
                                          Vector((2.0, 0.5, 1.5)))
    obj.bdi.target = "Bend"
    co0, co1 = read_key(obj, "Basis"), read_key(obj, "Bend")
    size = float(np.linalg.norm(np.ptp(world(obj.matrix_world, co0), axis=0)))
    vertices = [0, 7, len(co0) - 1]
    points = addon.trails(obj, vertices=vertices, samples=9)
    assert points.shape == (9, 3, 3)
    ts = np.linspace(0.0, 1.0, 9)
    expected = world(obj.matrix_world, core_frames(bd, [co0, co1], triangles(obj), ts))[:, vertices]
    assert np.abs(points - expected).max() < EXACT * size
    # the ends are the keys themselves; the middle bends along an arc, off the linear chord
    assert np.abs(points[0] - world(obj.matrix_world, co0[vertices])).max() < 1e-6 * size
    assert np.abs(points[-1] - world(obj.matrix_world, co1[vertices])).max() < 1e-6 * size
    chord_mid = (points[0] + points[-1]) / 2
    assert np.linalg.norm(points[4, 2] - chord_mid[2]) > 0.01 * size


def test_trails_of_the_seven_object_character_are_the_characters_frames(addon, bd):
    pieces, joints = cc.character()
    objs = cb.seven_objects(pieces)
    objs[0].bdi.target = cb.TARGET
    _, ranges, _ = cb.in_world(objs, ["Basis", cb.TARGET])
    offsets = np.cumsum([0] + [len(o.data.vertices) for o in objs])
    tris = np.concatenate([triangles(o) + a for o, a in zip(objs, offsets)])
    # every object's keys in world coordinates, layered as one mesh (core_frames)
    shapes = [np.concatenate([world(o.matrix_world, read_key(o, k)) for o in objs])
              for k in ("Basis", cb.TARGET)]
    size = cb.size_of(pieces)
    points = addon.trails(objs, samples=17)
    from bdinterp_blender.view import motion_trails
    vertices = motion_trails.default_vertices(motion_trails.Path(objs))
    every = core_frames(bd, shapes, tris, np.linspace(0.0, 1.0, 17))
    expected = every[:, vertices]
    assert points.shape == (17, len(vertices), 3)
    assert np.abs(points - expected).max() < EXACT * size
    # by default: one centre vertex per piece, and a vertex at each of the six joints
    piece_of = {v: name for name, r in ranges.items() for v in r}
    assert sorted({piece_of[int(v)] for v in vertices[:7]}) == sorted(p.name for p in pieces)
    assert 7 < len(vertices) <= 13
    # explicit vertices, counted across the objects: the hand's tip swings along an arc
    hand = ranges["Hand"]
    tip = hand[int(np.argmax(np.linalg.norm(shapes[0][hand] - shapes[0][hand].mean(axis=0), axis=1)))]
    swing = addon.trails(objs, vertices=[tip], samples=17)[:, 0]
    assert np.abs(swing - every[:, tip]).max() < EXACT * size
    assert np.linalg.norm(swing[8] - (swing[0] + swing[-1]) / 2) > 0.1 * size


def test_bad_trail_requests_name_what_is_wrong(addon):
    obj = bent_strip()
    with pytest.raises(addon.BakeError, match="Strip: no target shape key chosen"):
        addon.trails(obj)
    obj.bdi.target = "Bend"
    n = len(obj.data.vertices)
    with pytest.raises(addon.BakeError, match=r"Strip: vertex %d does not exist \(the mesh has %d" % (n, n)):
        addon.trails(obj, vertices=[0, n])
    with pytest.raises(addon.BakeError, match="at least 2 samples"):
        addon.trails(obj, samples=1)
    with pytest.raises(addon.BakeError, match="no shape key named 'Nope'"):
        addon.trails(obj, target="Nope")


def test_the_overlay_is_off_by_default_and_draws_the_frames_and_keys(addon, bd):
    from bdinterp_blender.view import onion
    view = bpy.context.scene.bdi_view
    assert not view.ghosts and not view.trails
    obj = bent_strip()
    obj.matrix_world = Matrix.Translation((0.0, 0.0, 2.0)) @ Matrix.Rotation(0.7, 4, 'X')
    addon.bake(obj, target="Bend", count=3)
    obj.bdi.target = "Bend"
    view.ghosts = view.trails = True
    view.ghost_source, view.samples = 'BAKED', 5
    ghosts = onion.build([obj], view)
    names = ["Bend.bdi.025", "Bend.bdi.050", "Bend.bdi.075"]
    keys = np.array([world(obj.matrix_world, read_key(obj, n)) for n in names])
    assert ghosts.factors == [0.25, 0.5, 0.75]
    assert np.abs(ghosts.in_world(ghosts.shapes) - keys).max() < 1e-12
    v = onion.motion_trails.default_vertices(onion.motion_trails.Path(obj))
    assert np.abs(ghosts.in_world(ghosts.ticks) - keys[:, v]).max() < 1e-12  # ticks: the baked keys on the trails
    assert np.abs(ghosts.in_world(ghosts.trails) - addon.trails(obj, samples=5)).max() < 1e-12
    assert np.abs(ghosts.chords - ghosts.trails[[0, -1]]).max() == 0.0
    # the outline: every edge of the strip's border once (a 16 x 4 grid: 2 (16 + 4) edges)
    assert len(ghosts.edges) == 40
    view.ghost_source, view.step = 'FACTORS', 0.2
    ghosts = onion.build([obj], view)
    assert np.allclose(ghosts.factors, [0.2, 0.4, 0.6, 0.8])
    expected = world(obj.matrix_world, core_frames(bd, [read_key(obj, "Basis"), read_key(obj, "Bend")],
                                                   triangles(obj), ghosts.factors))
    assert np.abs(ghosts.in_world(ghosts.shapes) - expected).max() < EXACT * 4
    # selected vertices: none selected is an error the panel shows
    view.trail_vertices = 'SELECTED'
    obj.data.vertices.foreach_set("select", np.zeros(len(obj.data.vertices), dtype=bool))
    with pytest.raises(addon.BakeError, match="no vertex selected"):
        onion.build([obj], view)
    obj.data.vertices[3].select = True
    trails = onion.build([obj], view).trails
    assert np.abs(world(obj.matrix_world, trails) - addon.trails(obj, vertices=[3], samples=5)).max() < 1e-12


def test_ghosts_of_frames_are_the_inbetweens_the_slider_keyframes_show_there(addon, bd):
    from bdinterp_blender.view import onion
    from bdinterp_blender.actions import find_fcurve
    obj = bent_strip()
    addon.bake(obj, target="Bend", count=3)
    obj.bdi.target = "Bend"
    for frame, value in ((1, 0.0), (11, 1.0)):  # linear: 0.1 a frame
        obj["Bend.bdi"] = value
        obj.keyframe_insert('["Bend.bdi"]', frame=frame)
    for point in find_fcurve(obj.animation_data, '["Bend.bdi"]').keyframe_points:
        point.interpolation = 'LINEAR'
    view = bpy.context.scene.bdi_view
    view.ghosts, view.trails, view.ghost_source = True, False, 'FRAMES'
    view.frames_before, view.frames_after, view.frame_step = 2, 1, 2
    ghosts = onion.build([obj], view, frame=6)  # frames 2, 4 and 8
    assert ghosts.offsets == [-4, -2, 2] and ghosts.span == 6
    assert np.allclose(ghosts.factors, [0.1, 0.3, 0.7], atol=1e-6)
    expected = world(obj.matrix_world, core_frames(bd, [read_key(obj, "Basis"), read_key(obj, "Bend")],
                                                   triangles(obj), ghosts.factors))
    assert np.abs(ghosts.in_world(ghosts.shapes) - expected).max() < EXACT * 4
    # the same request at another frame reuses the solver; past the last key the factor stays 1
    again = onion.build([obj], view, frame=12, path=ghosts.path)
    assert again.path is ghosts.path and np.allclose(again.factors, [0.7, 0.9, 1.0], atol=1e-6)  # 8, 10, 14


def test_the_ghosts_are_rebuilt_when_the_anchor_path_changes(addon, bd):
    """The overlay's request covers every setting its Path solves with: an anchor path set after
    the ghosts were drawn changes the request, and the ghosts built for it follow the path."""
    from bdinterp_blender.view import onion
    obj = bent_strip()
    obj.bdi.target = "Bend"
    view = bpy.context.scene.bdi_view
    view.ghosts, view.trails, view.ghost_source, view.step = True, False, 'FACTORS', 0.5
    free, key = onion.build([obj], view), onion.request_key([obj], view)
    pts = [(0.0, 0.0, 0.0), (1.0, 2.0, 0.0), (0.5, 4.0, 0.0)]
    path = path_object(pts)
    obj.bdi.anchor_path = path
    assert onion.request_key([obj], view) != key
    along = onion.build([obj], view)
    p = np.array(pts)
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    ts = np.concatenate([[0], np.cumsum(seg)]) / seg.sum()
    shapes = layered(bd, [read_key(obj, "Basis"), read_key(obj, "Bend")], triangles(obj))
    anchor = bd.AnchorPath(ts, p, np.zeros(3), vertex=None)
    expected = world(obj.matrix_world, bd.Interpolator(shapes, triangles(obj), anchor=anchor)
                     .frames([0.5]))
    assert np.abs(along.in_world(along.shapes) - expected).max() < EXACT * 4
    assert np.abs(free.in_world(free.shapes) - expected).max() > 0.1  # the path moved the ghost
