"""How often a bake reports progress in Blender (docs/BENCHMARKS.md): at each size, a grid bent by
135 degrees is baked into 24 in-betweens by bdinterp_blender.bake, and the seconds between its
progress calls (one per step, each a frames() call) are measured, with the add-on of this checkout.

    PYTHONPATH=python blender --background --factory-startup --python scripts/bench_bake_steps.py \
        [-- --sides 141,200,283]

Prints a Markdown table: vertices, steps, the first step (the solver's precomputation, the cold
first frames), the median and largest of the others, and the whole bake.
"""

import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "addon"))
import bdinterp_blender as addon  # noqa: E402 -- this checkout's add-on, not an installed one


def bent_grid(side):
    """A grid of side x side vertices with the key 'Bend': the columns turned about a far point,
    up to 135 degrees at the right end."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side - 1, y_subdivisions=side - 1, size=2)
    obj = bpy.context.active_object
    obj.shape_key_add(name="Basis")
    co = np.array([v.co[:] for v in obj.data.vertices])
    angle = np.clip((co[:, 0] + 1) / 2, 0, 1) * np.pi * 0.75
    radius = 3 - co[:, 1]
    bent = np.c_[radius * np.sin(angle) - 1, 3 - radius * np.cos(angle), co[:, 2]]
    obj.shape_key_add(name="Bend").data.foreach_set("co", bent.ravel())
    return obj


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    sides = [int(s) for s in argv[1].split(",")] if argv[:1] == ["--sides"] else [141, 200, 283]
    addon.register()
    print("| vertices | steps | first s | median s | largest s | whole bake s |")
    print("|---:|---:|---:|---:|---:|---:|")
    for side in sides:
        bpy.ops.object.select_all(action='SELECT')
        bpy.ops.object.delete()
        obj = bent_grid(side)
        stamps = [time.perf_counter()]
        addon.bake(obj, target="Bend", count=24,
                   progress=lambda done, total: stamps.append(time.perf_counter()))
        gaps = np.diff(stamps)
        print("| %d | %d | %.3f | %.3f | %.3f | %.2f |" % (
            side * side, len(gaps), gaps[0], np.median(gaps[1:]), gaps[1:].max(),
            stamps[-1] - stamps[0]))


main()
