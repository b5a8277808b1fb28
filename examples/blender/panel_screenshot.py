"""Draw the add-on's sidebar in a real Blender window and save a screenshot of it.

    xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --enable-event-simulate \
        --python examples/blender/panel_screenshot.py -- [--out addon/docs/panel.png] [--open-all]

Builds a small scene (a strip bent by 90 degrees, four baked in-betweens), opens the sidebar on
the bdinterp tab (clicking down the tab strip, as a user would: Blender 3.4 has no Python access
to the active tab), lets every panel draw, then prints one line 'JSON:{...}' with the draw calls
and errors of each panel, saves the screenshot (--out) and quits.  --open-all opens the
sub-panels that start closed, so that every draw() runs.  Uses the installed add-on, else
addon/ of this checkout.  CI runs it (tests/blender/test_window.py); its image is the README's.
"""

import json
import os
import sys
import traceback

import bpy

ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
OUT = ARGS[ARGS.index("--out") + 1] if "--out" in ARGS else None
calls, errors = {}, {}


def enable_addon():
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import addon_loader
    return addon_loader.enable()


def instrument(ui, open_all):
    """Re-register the panels with draw() wrapped to count calls and keep tracebacks."""
    for cls in reversed(ui.PANELS):
        bpy.utils.unregister_class(cls)
    for cls in ui.PANELS:
        for name in ("draw", "draw_header"):
            fn = cls.__dict__.get(name)
            if fn is not None:
                setattr(cls, name, _wrapped(cls.__name__, name, fn))
        if open_all:
            cls.bl_options = set(getattr(cls, "bl_options", ())) - {'DEFAULT_CLOSED'}
        bpy.utils.register_class(cls)


def _wrapped(panel, name, fn):
    def draw(self, context):
        calls[panel + "." + name] = calls.get(panel + "." + name, 0) + 1
        try:
            fn(self, context)
        except Exception:  # noqa: BLE001 -- recorded, then shown by Blender as usual
            errors.setdefault(panel + "." + name, traceback.format_exc())
            raise
    return draw


def scene(addon):
    from window_steps import bent_strip
    obj = bent_strip(24, 4, 0.2, 90, "Arm_up")
    obj.name = "Arm"
    obj.bdi.target, obj.bdi.count, obj.bdi.easing = "Arm_up", 4, 'EASE_IN_OUT'
    addon.bake(obj, target="Arm_up", count=4, easing="EASE_IN_OUT")
    obj["Arm_up.bdi"] = 0.5
    obj.update_tag()
    for o in list(bpy.data.objects):
        if o != obj:
            bpy.data.objects.remove(o)
    return obj


def view3d():
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == 'VIEW_3D'), key=lambda a: a.width)
    return window, area, next(r for r in area.regions if r.type == 'UI')


def crop(path, keep_right):
    """Keep the right `keep_right` pixels of the image (the sidebar and some of the viewport)."""
    import numpy as np
    img = bpy.data.images.load(path)
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    keep = min(keep_right, w)
    out = bpy.data.images.new("crop", keep, h, alpha=True)
    out.pixels.foreach_set(px.reshape(h, w, 4)[:, w - keep:, :].ravel())
    out.filepath_raw, out.file_format = path, 'PNG'
    out.save()


def steps(addon):
    """Generator driven by a timer: each yield lets Blender draw once."""
    obj = scene(addon)
    window, area, _ = view3d()
    area.spaces.active.show_region_ui = True
    main_region = next(r for r in area.regions if r.type == 'WINDOW')
    with bpy.context.temp_override(window=window, area=area, region=main_region):
        bpy.ops.view3d.view_selected()
    yield
    _, _, region = view3d()
    from window_steps import click_tabs
    yield from click_tabs(window, region, lambda: calls.get("BDINTERP_PT_main.draw"))
    for _ in range(3):
        yield
    result = {"calls": calls, "errors": errors, "object": obj.name}
    if OUT:
        os.makedirs(os.path.dirname(os.path.abspath(OUT)), exist_ok=True)
        with bpy.context.temp_override(window=window, area=area):
            bpy.ops.screen.screenshot_area(filepath=os.path.abspath(OUT))
        crop(os.path.abspath(OUT), keep_right=560)
        result["screenshot"] = os.path.abspath(OUT)
    print("JSON:" + json.dumps(result), flush=True)
    bpy.ops.wm.quit_blender()


def main():
    try:
        addon = enable_addon()
    except Exception:  # noqa: BLE001 -- report and quit instead of leaving a window open
        print("JSON:" + json.dumps({"calls": {}, "errors": {"enable": traceback.format_exc()}}))
        bpy.ops.wm.quit_blender()
        return
    from bdinterp_blender.ui import panels as ui
    instrument(ui, "--open-all" in ARGS)
    bpy.context.preferences.view.show_splash = False
    gen = steps(addon)

    def tick():
        try:
            next(gen)
        except StopIteration:
            return None
        except Exception:  # noqa: BLE001 -- report and quit instead of hanging the window
            print("JSON:" + json.dumps({"calls": calls, "errors": {"script": traceback.format_exc()}}))
            bpy.ops.wm.quit_blender()
            return None
        return 0.2

    bpy.app.timers.register(tick, first_interval=1.0)


main()
