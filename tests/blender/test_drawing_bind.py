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


def jittered_grid(n, seed=1):
    """(vertices (v, 3) in the plane z = 0.3 x, triangles (m, 3)) of an n x n jittered grid."""
    rng = np.random.default_rng(seed)
    xs, ys = np.meshgrid(np.linspace(0.0, 1.0, n + 1), np.linspace(0.0, 1.0, n + 1))
    uv = np.stack([xs.ravel(), ys.ravel()], axis=1)
    inner = (uv > 0).all(axis=1) & (uv < 1).all(axis=1)
    uv[inner] += rng.uniform(-0.3, 0.3, (inner.sum(), 2)) / n
    i = np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]
    i = i.ravel()
    tris = np.concatenate([np.stack([i, i + 1, i + n + 2], 1), np.stack([i, i + n + 2, i + n + 1], 1)])
    return np.column_stack([uv, 0.3 * uv[:, 0]]), tris


def brute_force(P2, C2):
    """The best triangle of every point, testing every triangle: the largest smallest
    barycentric coordinate."""
    out = []
    for p in P2:
        a, b, c = C2[:, 0], C2[:, 1], C2[:, 2]
        det = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
        l1 = ((p - a)[:, 0] * (c - a)[:, 1] - (p - a)[:, 1] * (c - a)[:, 0]) / det
        l2 = ((b - a)[:, 0] * (p - a)[:, 1] - (b - a)[:, 1] * (p - a)[:, 0]) / det
        out.append(np.min([1 - l1 - l2, l1, l2], axis=0).max())
    return np.array(out)


def test_points_are_located_in_the_triangle_that_holds_them(addon):
    """The grid of buckets finds, for a point inside the mesh, a triangle holding it (the one
    testing every triangle finds); a point beside the mesh gets a nearby triangle whose affine map
    gives it back; the point's place is its barycentric image plus its height."""
    from bdinterp_blender.view import drawing_bind as db
    X, tris = jittered_grid(24)
    rng = np.random.default_rng(7)
    inside = np.column_stack([rng.uniform(0.01, 0.99, (300, 2)), np.zeros(300)])
    beside = np.column_stack([rng.uniform(1.02, 1.2, (20, 1)), rng.uniform(0, 1, (20, 1)), np.zeros(20)])
    P = np.concatenate([inside, beside])
    P[:, 2] = 0.3 * P[:, 0] + rng.uniform(-0.05, 0.05, len(P))  # above and below the plane
    tri, bary, height = db.locate(P, X, tris)
    assert np.abs(bary.sum(axis=1) - 1).max() < 1e-12
    C = X[tris[tri]]
    pos, scale = db.place(C, bary, height, np.linalg.norm(np.cross(C[:, 1] - C[:, 0], C[:, 2] - C[:, 0]), axis=1))
    assert np.abs(pos - P).max() < 1e-12 and np.abs(scale - 1).max() < 1e-12
    normal = np.array([-0.3, 0.0, 1.0]) / np.linalg.norm([-0.3, 0.0, 1.0])  # the plane z = 0.3 x
    on_plane = P - np.outer(P @ normal, normal)  # along the normal into it; then x, y go through
    expected = brute_force(on_plane[:300, :2], X[tris][:, :, :2])
    assert (expected >= -1e-12).all()
    got = np.min(bary[:300], axis=1)
    assert (got >= -1e-9).all() and np.abs(got - expected).max() < 1e-9
    assert (bary[300:].min(axis=1) < 0).all()  # outside: the nearest triangle's affine map


def test_locating_is_linear_in_points_and_triangles(addon):
    """10k points on a 20k-triangle mesh: far less than the 2e8 point-triangle tests of checking
    each pair (which took seconds)."""
    import time
    from bdinterp_blender.view import drawing_bind as db
    X, tris = jittered_grid(100)  # 20000 triangles
    rng = np.random.default_rng(3)
    P = np.column_stack([rng.uniform(0, 1, (10000, 2)), np.zeros(10000)])
    P[:, 2] = 0.3 * P[:, 0]
    started = time.perf_counter()
    tri, bary, _ = db.locate(P, X, tris)
    seconds = time.perf_counter() - started
    assert bary.min() > -1e-9
    assert seconds < 1.0, seconds


def stroke_without_radius(points):
    """A drawing as a script makes it: add_strokes, positions set, no radius or opacity written."""
    coll = bpy.data.grease_pencils_v3 if hasattr(bpy.data, "grease_pencils_v3") else bpy.data.grease_pencils
    gp = coll.new("Script")
    drawing = gp.layers.new("Lines").frames.new(1).drawing
    drawing.add_strokes([len(points)])
    drawing.attributes["position"].data.foreach_set("vector", np.asarray(points, np.float32).ravel())
    assert drawing.attributes.get("radius") is None
    obj = bpy.data.objects.new("Script", gp)
    bpy.context.scene.collection.objects.link(obj)
    return obj, drawing


def baked_strip_and_drawing(addon, every):
    """(a baked bent strip, a script's drawing on every `every`-th vertex, its drawing, where its
    points were drawn)."""
    from conftest import bent_strip
    obj = bent_strip()
    addon.bake(obj, target="Bend", count=3)
    X = cb.world(obj, cb.read(obj, "Basis"))
    gp_obj, drawing = stroke_without_radius(X[::every] * 0.98 + X.mean(axis=0) * 0.02)
    return obj, gp_obj, drawing, positions(gp_obj).copy()


def show(obj, factor):
    """The strip's slider at `factor`, the scene updated (the handlers run)."""
    obj["Bend.bdi"] = factor
    obj.update_tag()
    bpy.context.view_layer.update()


@pytest.mark.skipif(not V3, reason="Grease Pencil v3 is Blender 4.3+")
def test_a_drawing_without_radius_binds_and_follows(addon):
    from bdinterp_blender.view import drawing_bind as db
    obj, gp_obj, drawing, drawn = baked_strip_and_drawing(addon, 7)
    default = drawing.strokes[0].points[0].radius  # what Blender shows without the attribute
    assert addon.bind_drawing(gp_obj, obj) == len(drawn)
    assert np.allclose(db.read(drawing, db.RADIUS, 1), default)
    show(obj, 1.0)
    assert np.abs(positions(gp_obj) - expected(gp_obj, [obj])).max() < 1e-6
    assert np.abs(positions(gp_obj) - drawn).max() > 0.1
    addon.unbind_drawing(gp_obj)
    assert np.array_equal(positions(gp_obj), drawn)
    assert np.allclose(db.read(drawing, "radius", 1), default)


@pytest.mark.skipif(not V3, reason="Grease Pencil v3 is Blender 4.3+")
def test_a_topology_edit_unbinds_with_a_warning_and_binding_again_works(addon):
    import bmesh
    from bdinterp_blender.view import drawing_bind as db
    obj, gp_obj, _, drawn = baked_strip_and_drawing(addon, 5)
    addon.bind_drawing(gp_obj, obj)
    show(obj, 0.5)
    assert np.abs(positions(gp_obj) - drawn).max() > 0.05
    bm = bmesh.new()  # a user's edit: the last face deleted (its vertices too)
    bm.from_mesh(obj.data)
    bm.faces.ensure_lookup_table()
    bmesh.ops.delete(bm, geom=[bm.faces[-1]], context='FACES')
    bm.to_mesh(obj.data)
    bm.free()
    obj.data.update()
    bpy.context.view_layer.update()  # the handler: no error, the drawing unbound
    assert db.BOUND not in gp_obj and "faces of Strip changed" in gp_obj[db.WARNING]
    assert np.array_equal(positions(gp_obj), drawn)  # every point back where it was drawn
    show(obj, 1.0)
    assert np.array_equal(positions(gp_obj), drawn)
    addon.bind_drawing(gp_obj, obj)  # bound again to the edited mesh: follows it
    assert db.WARNING not in gp_obj
    bpy.context.view_layer.update()
    assert np.abs(positions(gp_obj) - expected(gp_obj, [obj])).max() < 1e-6


@pytest.mark.skipif(not V3, reason="Grease Pencil v3 is Blender 4.3+")
def test_an_update_reads_the_binding_once_and_locates_nothing(addon):
    """The rest frames are kept: following the mesh locates no point again and reads the
    binding's attributes once (binding placed it); 10k points follow in a few milliseconds."""
    import time
    from conftest import bent_strip
    from bdinterp_blender.view import drawing_bind as db
    obj = bent_strip()
    addon.bake(obj, target="Bend", count=3)
    X = cb.world(obj, cb.read(obj, "Basis"))
    rng = np.random.default_rng(5)
    pick = rng.integers(0, len(X), (10000, 3))
    w = rng.dirichlet(np.ones(3), 10000)
    gp_obj, _ = stroke_without_radius(np.einsum("pi,pij->pj", w, X[pick]))
    addon.bind_drawing(gp_obj, obj)
    located, loaded = db.counters["located"], db.counters["loaded"]
    depsgraph = bpy.context.evaluated_depsgraph_get()
    times = []
    for s in np.linspace(0.0, 1.0, 21):
        show(obj, float(s))
        started = time.perf_counter()
        db.update(gp_obj, depsgraph)
        times.append(time.perf_counter() - started)
    assert db.counters["located"] == located and db.counters["loaded"] == loaded  # read at bind
    assert np.abs(positions(gp_obj) - expected(gp_obj, [obj])).max() < 1e-6
    print("update of 10k points: median %.3f ms" % (1e3 * np.median(times)))
    assert np.median(times) < 0.02  # 2 ms on a quiet machine (docs/BENCHMARKS.md); loose here


@pytest.mark.skipif(not V3, reason="Grease Pencil v3 is Blender 4.3+")
def test_an_edit_mode_change_that_keeps_every_count_unbinds_too(addon):
    """Faces turned over in Edit Mode: as many vertices and corners as before, other faces."""
    import bmesh
    from bdinterp_blender.view import drawing_bind as db
    obj, gp_obj, _, drawn = baked_strip_and_drawing(addon, 5)
    addon.bind_drawing(gp_obj, obj)
    show(obj, 0.5)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode='EDIT')
    bm = bmesh.from_edit_mesh(obj.data)
    bmesh.ops.reverse_faces(bm, faces=list(bm.faces)[:3])
    bmesh.update_edit_mesh(obj.data)
    bpy.context.view_layer.update()  # in Edit Mode: the drawing waits
    assert db.BOUND in gp_obj
    bpy.ops.object.mode_set(mode='OBJECT')
    show(obj, 0.6)
    assert db.BOUND not in gp_obj and "faces of Strip changed" in gp_obj[db.WARNING]
    assert np.array_equal(positions(gp_obj), drawn)


@pytest.mark.skipif(not V3, reason="Grease Pencil v3 is Blender 4.3+")
def test_an_error_while_following_unbinds_once(addon, monkeypatch):
    """Whatever goes wrong in the handler (here: the evaluated mesh cannot be read), the drawing
    is unbound with the error in its warning, and the next updates do nothing."""
    from bdinterp_blender.view import drawing_bind as db
    obj, gp_obj, _, drawn = baked_strip_and_drawing(addon, 5)
    addon.bind_drawing(gp_obj, obj)
    calls = []

    def broken(*args):
        calls.append(args)
        raise MemoryError("no memory for the shown mesh")
    monkeypatch.setattr(db, "shown_mesh", broken)
    show(obj, 0.5)
    assert db.BOUND not in gp_obj and "MemoryError: no memory for the shown mesh" in gp_obj[db.WARNING]
    assert np.array_equal(positions(gp_obj), drawn)
    show(obj, 0.7)
    assert len(calls) == 1
