"""Helpers of the scripts that drive a real Blender window (under Xvfb): a bent strip to show, and
a generator of steps run from a timer, one step per redraw, that ends by printing its result."""

import json
import math
import traceback

import bpy


def bent_strip(x_subdivisions, y_subdivisions, scale_y, degrees, key):
    """A grid (size 2, scaled by `scale_y` across) with the shape key `key`: bent by `degrees`
    about Z; made active."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=x_subdivisions, y_subdivisions=y_subdivisions,
                                    size=2.0)
    obj = bpy.context.object
    obj.scale = (1.0, scale_y, 1.0)
    bpy.ops.object.transform_apply(scale=True)
    obj.shape_key_add(name="Basis", from_mix=False)
    mod = obj.modifiers.new("Bend", 'SIMPLE_DEFORM')
    mod.deform_method, mod.deform_axis, mod.angle = 'BEND', 'Z', math.radians(degrees)
    bpy.ops.object.modifier_apply_as_shapekey(modifier="Bend")
    obj.data.shape_keys.key_blocks["Bend"].name = key
    return obj


def click_tabs(window, region, opened):
    """Click down the tab strip of the sidebar `region` until opened() (e.g. the add-on's panel has
    drawn); a generator: each yield lets Blender draw."""
    top = region.y + region.height
    for dy in range(20, min(region.height, 600), 16):
        if opened():
            return
        x, y = region.x + region.width - 9, top - dy
        window.event_simulate('MOUSEMOVE', 'NOTHING', x=x, y=y)
        window.event_simulate('LEFTMOUSE', 'PRESS', x=x, y=y)
        window.event_simulate('LEFTMOUSE', 'RELEASE', x=x, y=y)
        yield


def run_steps(steps, result, interval):
    """Run the generator `steps` from a timer, one step every `interval` seconds (each yield lets
    Blender draw); then print 'JSON:' and `result` (with 'error': the traceback if a step failed)
    and quit Blender."""
    def tick():
        try:
            next(steps)
            return interval
        except StopIteration:
            pass
        except Exception:  # noqa: BLE001 -- report and quit instead of hanging the window
            result["error"] = traceback.format_exc()
        print("JSON:" + json.dumps(result), flush=True)
        bpy.ops.wm.quit_blender()
        return None

    bpy.app.timers.register(tick, first_interval=1.0)
