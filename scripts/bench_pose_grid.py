"""Live update rate of a pose grid in Blender (docs/BENCHMARKS.md): at each size, a grid of
side x side vertices gets a 3 x 3 pose grid (bend -90/0/90 degrees x thickness 0.8/1/1.25, nine
poses) and one parameter is scrubbed through new values, each set as a script sets it (the
property, then one view_layer.update()). Times the whole update and the core's share (the
PoseBlender's blend), with the add-on of this checkout.

    PYTHONPATH=python blender --background --factory-startup --python scripts/bench_pose_grid.py \
        [-- --sides 71,317 --updates 40]

Prints a Markdown table: vertices, updates a second, ms per update, of which core ms and the rest
(Blender's depsgraph and shape key evaluation, the key write, the handler).
"""

import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "addon"))
import bdinterp_blender as addon  # noqa: E402 -- this checkout's add-on, not an installed one


def posed(co, bend, thick):
    """The grid [-1, 1]^2 thickened along y by `thick` and bent along x by `bend` degrees."""
    x, y = co[:, 0] + 1, co[:, 1] * thick
    a = np.radians(bend)
    if a == 0:
        return np.c_[x - 1, y, co[:, 2]]
    r0 = 2.0 / a
    r = r0 - y
    return np.c_[r * np.sin(x / r0) - 1, r0 - r * np.cos(x / r0), co[:, 2]]


def grid_object(side):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side - 1, y_subdivisions=side - 1, size=2)
    obj = bpy.context.active_object
    obj.shape_key_add(name="Basis")
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    keys = {}
    for bend in (-90, 0, 90):
        for i, thick in enumerate((0.8, 1.0, 1.25)):
            name = "Basis" if (bend, i) == (0, 1) else "B%d_T%d" % (bend, i)
            if name != "Basis":
                kb = obj.shape_key_add(name=name)
                kb.value = 0.0
                kb.data.foreach_set("co", posed(co, bend, thick).ravel())
            keys[(bend, i - 1)] = name
    return obj, keys


def timed_core():
    """Wrap PoseBlender.blend to add up its seconds (the core's share)."""
    cls = addon.load_core().pose_grid.PoseBlender
    spent, plain = [0.0], cls.blend

    def blend(self, *args, **kwargs):
        t0 = time.perf_counter()
        try:
            return plain(self, *args, **kwargs)
        finally:
            spent[0] += time.perf_counter() - t0
    cls.blend = blend
    return spent


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    opts = dict(zip(argv[::2], argv[1::2]))
    sides = [int(s) for s in opts.get("--sides", "71,317").split(",")]
    updates = int(opts.get("--updates", "40"))
    addon.register()
    spent = timed_core()
    print("| vertices | updates/s | ms per update | core ms | Blender + handler ms |")
    print("|---:|---:|---:|---:|---:|")
    for side in sides:
        bpy.ops.object.select_all(action='SELECT')
        bpy.ops.object.delete()
        obj, keys = grid_object(side)
        addon.pose_grid(obj, {"bend": [-90, 0, 90], "thick": [-1, 0, 1]}, keys, name="g")
        item = obj.bdi_grids["g"].params["bend"]
        values = np.linspace(-80, 80, updates) + 0.37  # new values, none at a node
        item.amount = values[0] - 1  # the first solve's warm-up is not timed
        bpy.context.view_layer.update()
        spent[0] = 0.0
        t0 = time.perf_counter()
        for v in values:
            item.amount = float(v)
            bpy.context.view_layer.update()
        total = (time.perf_counter() - t0) / updates
        core = spent[0] / updates
        print("| %d | %.1f | %.1f | %.1f | %.1f |" % (len(obj.data.vertices), 1 / total,
                                                    1e3 * total, 1e3 * core, 1e3 * (total - core)))


main()
