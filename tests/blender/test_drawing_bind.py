"""Grease Pencil strokes bound to examples/cutout's head and arm, the character as one object or as
seven (Blender 4.3+): every point is the barycentric image of its triangle in the mesh as shown
(slider 0, 0.25, 0.5, 1, live mode), each on the piece that holds it, the radius scales with the
triangle, unbinding restores the points exactly, and a saved file keeps the binding working."""

import os
import sys

import bpy
import numpy as np
import pytest

from conftest import ROOT, evaluated_co, triangles

sys.path.insert(0, os.path.join(ROOT, "examples", "cutout"))
import cutout_blender as cb  # noqa: E402
import cutout_character as cc  # noqa: E402

V3 = bpy.app.version >= (4, 3, 0)


def gp_object(points):
    coll = bpy.data.grease_pencils_v3 if hasattr(bpy.data, "grease_pencils_v3") else bpy.data.grease_pencils
    gp = coll.new("Face")
    drawing = gp.layers.new("Lines").frames.new(1).drawing
    drawing.add_strokes([len(points)])
    for p, co in zip(drawing.strokes[0].points, points):
        p.position, p.radius = tuple(co), 0.01
    obj = bpy.data.objects.new("Face", gp)
    bpy.context.scene.collection.objects.link(obj)
    return obj, drawing


def positions(gp_obj):
    from bdinterp_blender.view import drawing_bind
    return np.concatenate([drawing_bind.read(d, "position", 3) for d in drawing_bind.drawings(gp_obj)])


def shown(objs):
    """(world vertices (n, 3) as evaluated, triangles (m, 3)) of the objects one after the other."""
    X = [cb.world(o, evaluated_co(o)) for o in objs]
    offsets = np.cumsum([0] + [len(x) for x in X])
    return np.concatenate(X), np.concatenate([triangles(o) + a for o, a in zip(objs, offsets)])


def expected(gp_obj, objs):
    """Each point as the barycentric image of its stored triangle in the meshes as evaluated, at
    its stored height along the triangle's normal (a stroke drawn in front of its piece stays
    there)."""
    from bdinterp_blender.view import drawing_bind as db
    d = db.drawings(gp_obj)[0]
    tri, bary = db.read(d, db.TRI, 1), db.read(d, db.BARY, 3).astype(float)
    X, tris = shown(objs)
    X = X[tris[tri]]
    normal = np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    return (bary[:, :, None] * X).sum(axis=1) + db.read(d, db.HEIGHT, 1)[:, None] * normal


def pieces_bound(gp_obj, objs):
    """The name of the object whose triangle holds each point, and the smallest barycentric
    coordinate of each (>= 0: inside that triangle)."""
    from bdinterp_blender.view import drawing_bind as db
    d = db.drawings(gp_obj)[0]
    ends = np.cumsum([len(triangles(o)) for o in objs])
    which = np.searchsorted(ends, db.read(d, db.TRI, 1), side="right")
    return [objs[i].name for i in which], db.read(d, db.BARY, 3).min(axis=1)


@pytest.mark.skipif(V3, reason="Blender 4.3+ binds (see the test below)")
def test_binding_says_why_not_before_4_3(addon):
    with pytest.raises(addon.BakeError, match="needs Blender 4.3 or later"):
        addon.bind_drawing(None, None)
    assert not bpy.ops.bdinterp.bind_drawing.poll()  # the panel's button greyed out


def character(kind):
    """(objects, the object live mode runs on, {'Head', 'UpperArm': world rest vertices}, size):
    examples/cutout as one object or as seven (one per piece, each with its own transform)."""
    pieces, _ = cc.character()
    if kind == "one":
        obj, ranges = cb.one_object(pieces)
        objs, live = [obj], obj
        X0 = cb.world(obj, cb.read(obj, "Basis"))
        parts = {name: X0[list(ranges[name])] for name in ("Head", "UpperArm")}
    else:
        objs = cb.seven_objects(pieces)
        live = bpy.data.objects["UpperArm"]  # live mode of one piece on its own
        parts = {name: cb.world(bpy.data.objects[name], cb.read(bpy.data.objects[name], "Basis"))
                 for name in ("Head", "UpperArm")}
    return objs, live, parts, cb.size_of(pieces)


@pytest.mark.skipif(not V3, reason="Grease Pencil v3 is Blender 4.3+")
@pytest.mark.parametrize("kind", ["one", "seven"])
def test_strokes_on_the_head_and_arm_follow_the_mesh(addon, tmp_path, kind):
    objs, live, parts, size = character(kind)
    addon.bake(objs, target=cb.TARGET, count=3)
    head, arm = parts["Head"], parts["UpperArm"]
    pts = np.concatenate([head.mean(axis=0)[None] + [[0.01, 0.02, 0.0]], head[:3] * 0.9 + head.mean(axis=0) * 0.1,
                          arm.mean(axis=0)[None], arm[:2]])
    gp_obj, _ = gp_object(pts)
    drawn = positions(gp_obj).copy()
    assert addon.bind_drawing(gp_obj, objs if kind == "seven" else objs[0]) == len(pts)
    names, inside = pieces_bound(gp_obj, objs)
    assert inside.min() > -1e-9  # every point drawn on a piece: in the triangle that holds it
    if kind == "seven":  # the centres on their own pieces (where pieces overlap, either holds it)
        assert names[0] == "Head" and names[4] == "UpperArm", names
    slider_owner = objs[0]
    for s in (0.0, 0.25, 0.5, 1.0):
        slider_owner[cb.TARGET + ".bdi"] = s
        slider_owner.update_tag()
        bpy.context.view_layer.update()
        assert np.abs(positions(gp_obj) - expected(gp_obj, objs)).max() < 1e-6 * size, s
        if s == 0.0:  # the rest shape: every point where it was drawn
            assert np.abs(positions(gp_obj) - drawn).max() < 1e-6 * size
    moved = np.abs(positions(gp_obj) - drawn).max()
    assert moved > 0.05 * size  # the arm raised: its strokes went with it
    from bdinterp_blender.view import drawing_bind as db
    radius = db.read(db.drawings(gp_obj)[0], "radius", 1)
    assert np.abs(radius - 0.01).max() < 1e-6  # rigid pieces: every triangle keeps its scale
    slider_owner[cb.TARGET + ".bdi"] = 0.0
    addon.set_live(live, target=cb.TARGET, factor=0.3)
    bpy.context.view_layer.update()
    assert np.abs(positions(gp_obj) - expected(gp_obj, objs)).max() < 1e-6 * size
    assert np.abs(positions(gp_obj) - drawn).max() > 0.02 * size  # live mode moves them too
    addon.set_live(live, enable=False)
    live.data.shape_keys.key_blocks["bdi.live"].value = 0.0
    names = [o.name for o in objs]
    path = os.path.join(str(tmp_path), "bound.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    objs, gp_obj = [bpy.data.objects[n] for n in names], bpy.data.objects["Face"]
    objs[0][cb.TARGET + ".bdi"] = 0.5
    objs[0].update_tag()
    bpy.context.view_layer.update()
    assert np.abs(positions(gp_obj) - expected(gp_obj, objs)).max() < 1e-6 * size
    assert np.abs(positions(gp_obj) - drawn).max() > 0.02 * size
    addon.unbind_drawing(gp_obj)
    assert np.array_equal(positions(gp_obj), drawn.astype(np.float32))
