"""Onion skins and motion trails in a real Blender window: screenshots, ghost pixels, redraw cost.

    xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --python \\
        examples/blender/onion_screenshot.py -- [--scene one|seven|grid:VERTICES] [--live] \\
        [--ghosts FACTORS|BAKED|FRAMES] [--chords] [--out shot.png] [--redraws 50] [--changes]

Scenes: examples/cutout's character as one object or as seven objects (its slider at 0, so every
ghost lies after the shown shape), or a bent grid of about VERTICES vertices (the benchmark).
--live: live mode at factor 0.5 instead of a bake.  --ghosts FRAMES: the slider (or live factor)
keyframed 0 at frame 1 and 1 at frame 9, shown at frame 5, two ghosts of frames either side.
Draws the viewport (top view) without and with the overlay, and prints 'JSON:{...}': where the
0.75 ghost's triangles project (region pixels, only those on empty background without the
overlay) and the colour change there (and at the first ghost's), the same at empty corners, the
overlay's draw times (first: the rebuild; then cached redraws) and the region's redraw time
without and with the overlay; --changes: also the draw callback's time right after the object
moved, a colour changed or (--live) the live factor changed.  scripts/bench_overlay.py runs it
for docs/BENCHMARKS.md.
"""

import json
import math
import os
import sys
import time
import traceback

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "cutout"))
ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def arg(name, default=None):
    return ARGS[ARGS.index(name) + 1] if name in ARGS else default


def grid(vertices):
    """A strip of about `vertices` vertices (2:1) with the key 'Pose': bent by 120 degrees."""
    from window_steps import bent_strip
    ny = max(2, int(math.sqrt(vertices / 2.0)))
    return [bent_strip(2 * ny, ny, 0.5, 120, "Pose")]


def animate(owner, live):
    """Keyframe the slider (or in live mode the live factor) of `owner` 0 at frame 1 and 1 at
    frame 9, linear, and go to frame 5: the factor is 0.5 there and moves by 0.125 a frame."""
    from bdinterp_blender.actions import find_fcurve
    data_path = "bdi.live_factor" if live else '["Pose.bdi"]'
    for frame, value in ((1, 0.0), (9, 1.0)):
        if live:
            owner.bdi.live_factor = value
        else:
            owner["Pose.bdi"] = value
        owner.keyframe_insert(data_path, frame=frame)
    for point in find_fcurve(owner.animation_data, data_path).keyframe_points:
        point.interpolation = 'LINEAR'
    bpy.context.scene.frame_set(5)


def scene(addon):
    import cutout_blender as cb
    import cutout_character as cc
    for o in list(bpy.data.objects):  # the startup scene's cube, camera and light
        bpy.data.objects.remove(o)
    kind = arg("--scene", "one")
    if kind.startswith("grid:"):
        objs = grid(int(kind[5:]))
    elif kind == "seven":
        objs = cb.seven_objects(cc.character()[0])
    else:
        objs = [cb.one_object(cc.character()[0])[0]]
    for o in objs:
        o.select_set(True)
    obj = bpy.context.view_layer.objects.active = objs[0]
    obj.bdi.target, obj.bdi.count = "Pose", 3
    if "--live" in ARGS:
        addon.set_live(obj, target="Pose", factor=0.5)
    else:
        addon.bake(objs, target="Pose", count=3)
    view = bpy.context.scene.bdi_view
    if arg("--ghosts") == 'FRAMES':
        animate(obj, "--live" in ARGS)
    view.ghost_source = arg("--ghosts", "FACTORS")
    view.chords = "--chords" in ARGS
    return objs


def view3d():
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == 'VIEW_3D'), key=lambda a: a.width)
    return window, area, next(r for r in area.regions if r.type == 'WINDOW')


def shot(path):
    """Screenshot of the 3D view's area: (pixels (h, w, 4) float, (area x, area y))."""
    import numpy as np
    window, area, _ = view3d()
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.screen.screenshot_area(filepath=path)
    img = bpy.data.images.load(path, check_existing=False)
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4), (area.x, area.y)


def ghost_pixels(ghosts, factor=0.75):
    """Region pixel positions of the triangle centroids of the ghost at `factor`."""
    import numpy as np
    from bpy_extras.view3d_utils import location_3d_to_region_2d
    _, area, region = view3d()
    i = int(np.argmin(np.abs(np.array(ghosts.factors) - factor)))
    centres = ghosts.in_world(ghosts.shapes[i][ghosts.faces].mean(axis=1))
    rv3d = area.spaces.active.region_3d
    pts = [location_3d_to_region_2d(region, rv3d, c) for c in centres[:: max(1, len(centres) // 400)]]
    return [(int(p.x) + region.x, int(p.y) + region.y) for p in pts if p is not None
            and 2 <= p.x < region.width - 2 and 2 <= p.y < region.height - 2]


def changes(ghosts, factor, base, img, origin):
    """The colour changes (without -> with the overlay) where the triangles of the ghost at
    `factor` project onto empty background."""
    import numpy as np
    pts = [(x - origin[0], y - origin[1]) for x, y in ghost_pixels(ghosts, factor)]
    background = np.median(base[:, :, :3].reshape(-1, 3), axis=0)
    empty = [(x, y) for x, y in pts if abs(base[y, x, :3] - background).max() < 0.01]
    return [[float(c) for c in img[y, x, :3] - base[y, x, :3]] for x, y in empty]


def redraw_seconds(iterations):
    window, area, region = view3d()
    started = time.perf_counter()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.wm.redraw_timer(type='DRAW', iterations=iterations)
    return (time.perf_counter() - started) / iterations


def steps(addon, out):
    """Generator driven by a timer: each yield lets Blender draw once."""
    from bdinterp_blender.view import onion
    objs = scene(addon)
    window, area, region = view3d()
    area.spaces.active.overlay.show_floor = False
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.view3d.view_axis(type='TOP')
        bpy.ops.view3d.view_all()
    yield
    redraws = int(arg("--redraws", "30"))
    out["redraw_off"] = redraw_seconds(redraws)
    base, (ax, ay) = shot(os.path.abspath(arg("--out", "/tmp/onion.png")) + ".off.png")
    view = bpy.context.scene.bdi_view
    view.ghosts = view.trails = True
    onion.timings.clear()
    yield
    yield
    ghosts = onion._cache["ghosts"]
    out["error"] = ghosts.error if ghosts is not None else "no ghosts built"
    out["redraw_on"] = redraw_seconds(redraws)
    times = list(onion.timings)
    out["draw_first"], out["draw_cached"] = times[0], sorted(times[1:])[len(times) // 2 - 1]
    out["draw_cached_max"] = max(times[1:])
    out["vertices"] = sum(len(o.data.vertices) for o in objs)
    import gpu
    out["renderer"] = gpu.platform.renderer_get()
    img, _ = shot(os.path.abspath(arg("--out", "/tmp/onion.png")))
    out["ghost_change"] = changes(ghosts, 0.75, base, img, (ax, ay))
    out["ghost_points"] = len(out["ghost_change"])
    out["first_change"] = changes(ghosts, min(ghosts.factors), base, img, (ax, ay))
    h, w = img.shape[:2]
    corners = [(8, h // 2), (w - 8, h // 2)]
    out["corner_change"] = max(float(abs(img[y, x, :3] - base[y, x, :3]).max()) for x, y in corners)
    out["factors"] = list(map(float, ghosts.factors))
    out["trails"] = list(ghosts.trails.shape)
    if "--changes" in ARGS:
        out.update(redraws_after_changes(objs[0], view, redraws))


def redraws_after_changes(obj, view, redraws):
    """Median seconds of the overlay's draw callback in a redraw right after the object moved, a
    colour changed, or (live mode) the live factor changed: what those changes cost the overlay."""
    from bdinterp_blender.view import onion

    def median(change):
        onion.timings.clear()
        for i in range(redraws):
            change(i)
            bpy.context.view_layer.update()  # the depsgraph handler sees it, as after a user's edit
            redraw_seconds(1)
        times = sorted(onion.timings)
        return times[len(times) // 2] if times else None
    out = {"draw_moved": median(lambda i: setattr(obj, "location", (1e-3 * (i + 1), 0.0, 0.0))),
           "draw_recoloured": median(lambda i: setattr(view, "opacity", 0.5 + 0.01 * (i % 2)))}
    if "--live" in ARGS:
        out["draw_live"] = median(lambda i: setattr(obj.bdi, "live_factor", 0.5 + 1e-3 * (i + 1)))
    return out


def main():
    from window_steps import run_steps
    out = {}
    try:
        import addon_loader
        addon = addon_loader.enable()
        bpy.context.preferences.view.show_splash = False
    except Exception:  # noqa: BLE001 -- report and quit instead of leaving a window open
        print("JSON:" + json.dumps({"error": traceback.format_exc()}), flush=True)
        bpy.ops.wm.quit_blender()
        return
    run_steps(steps(addon, out), out, 0.3)


main()
