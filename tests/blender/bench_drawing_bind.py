"""A bound drawing's cost (Blender 4.3+, docs/BENCHMARKS.md): 10000 stroke points bound to a
jittered grid of 5041 vertices (9800 triangles) whose shape key bends it, then updated at 21
values of the key.  Not collected with the suite (its name does not start with test_); run it by
name, e.g. in the Debian 13 chroot:

    bash scripts/test-blender-chroot.sh trixie dist/bdinterp_blender-*-extension.zip -q -s \\
        tests/blender/bench_drawing_bind.py

Prints 'BENCH: bind S s, update median M ms (min m)'.  The update is the module's own update()
with the scene handler taken out, so that each call does the whole work once."""

import time

import bpy
import numpy as np
import pytest

V3 = bpy.app.version >= (4, 3, 0)


def bent_grid(n=70):
    """A jittered n x n grid in XY with the shape key 'Bend' (rolled around the y axis)."""
    rng = np.random.default_rng(2)
    xs, ys = np.meshgrid(np.linspace(0.0, 1.0, n + 1), np.linspace(0.0, 1.0, n + 1))
    uv = np.stack([xs.ravel(), ys.ravel()], axis=1)
    inner = (uv > 0).all(axis=1) & (uv < 1).all(axis=1)
    uv[inner] += rng.uniform(-0.3, 0.3, (inner.sum(), 2)) / n
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    tris = np.concatenate([np.stack([i, i + 1, i + n + 2], 1), np.stack([i, i + n + 2, i + n + 1], 1)])
    me = bpy.data.meshes.new("Grid")
    me.from_pydata(np.column_stack([uv, np.zeros(len(uv))]).tolist(), [], tris.tolist())
    obj = bpy.data.objects.new("Grid", me)
    bpy.context.scene.collection.objects.link(obj)
    obj.shape_key_add(name="Basis")
    bend = obj.shape_key_add(name="Bend")
    angle = uv[:, 0] * np.pi
    co = np.column_stack([np.sin(angle) / np.pi, uv[:, 1], (1 - np.cos(angle)) / np.pi])
    bend.data.foreach_set("co", co.astype(np.float32).ravel())
    return obj, uv


@pytest.mark.skipif(not V3, reason="Grease Pencil v3 is Blender 4.3+")
def test_bench_bound_drawing(addon):
    from bdinterp_blender.view import drawing_bind as db
    obj, _ = bent_grid()
    rng = np.random.default_rng(4)
    points = np.column_stack([rng.uniform(0.001, 0.999, (10000, 2)), np.zeros(10000)])
    gp = bpy.data.grease_pencils_v3.new("Bench") if hasattr(bpy.data, "grease_pencils_v3") \
        else bpy.data.grease_pencils.new("Bench")
    drawing = gp.layers.new("Lines").frames.new(1).drawing
    drawing.add_strokes([len(points)])
    drawing.attributes["position"].data.foreach_set("vector", points.astype(np.float32).ravel())
    drawing.attributes.new("radius", 'FLOAT', 'POINT')  # the version before binds only with one
    gp_obj = bpy.data.objects.new("Bench", gp)
    bpy.context.scene.collection.objects.link(gp_obj)
    started = time.perf_counter()
    addon.bind_drawing(gp_obj, obj)
    bind = time.perf_counter() - started
    for handlers in (bpy.app.handlers.depsgraph_update_post, bpy.app.handlers.frame_change_post):
        for h in [h for h in handlers if "drawing_bind" in getattr(h, "__module__", "")
                  or getattr(h, "__name__", "") in ("on_depsgraph_update", "on_frame_change")]:
            handlers.remove(h)  # the update below is then the only one
    key = obj.data.shape_keys.key_blocks["Bend"]
    times = []
    for s in np.linspace(0.0, 1.0, 21):
        key.value = float(s)
        bpy.context.view_layer.update()
        depsgraph = bpy.context.evaluated_depsgraph_get()
        started = time.perf_counter()
        db.update(gp_obj, depsgraph)
        times.append(time.perf_counter() - started)
    print("BENCH: bind %.3f s, update median %.3f ms (min %.3f)"
          % (bind, 1e3 * np.median(times), 1e3 * min(times)))
