"""Child script for test_window.py: the Bake operator as the UI runs it (INVOKE: modal, the chunks
on a thread of their own), once cancelled with Esc and once to the end, in a real window.

    xvfb-run ... blender --factory-startup --enable-event-simulate --python window_bake.py
Prints 'JSON:{...}' and quits."""

import os
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

result = {}


def strip():
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=60, y_subdivisions=12, size=2.0)
    obj = bpy.context.object
    obj.name = "Strip"
    obj.shape_key_add(name="Basis", from_mix=False)
    mod = obj.modifiers.new("Bend", 'SIMPLE_DEFORM')
    mod.deform_method, mod.deform_axis, mod.angle = 'BEND', 'Z', 1.5
    bpy.ops.object.modifier_apply_as_shapekey(modifier="Bend")
    obj.bdi.target, obj.bdi.count = "Bend", 48  # six chunks of eight
    return obj


def keys(obj):
    return [kb.name for kb in obj.data.shape_keys.key_blocks]


def view3d(window):
    area = max((a for a in window.screen.areas if a.type == 'VIEW_3D'), key=lambda a: a.width)
    return area, next(r for r in area.regions if r.type == 'WINDOW')


def record_step_threads():
    """result['step_threads']: whether each step of the bake ran on the main thread."""
    import threading
    from bdinterp_blender.shapes import solve
    step, result["step_threads"] = solve.FrameJob.step, []

    def recorded(job):
        result["step_threads"].append(threading.current_thread() is threading.main_thread())
        return step(job)
    solve.FrameJob.step = recorded


def steps():
    import addon_loader
    addon_loader.enable()
    window = bpy.context.window_manager.windows[0]
    area, region = view3d(window)
    obj = strip()
    record_step_threads()
    bpy.ops.ed.undo_push(message="scene")
    x, y = region.x + region.width // 2, region.y + region.height // 2
    with bpy.context.temp_override(window=window, area=area, region=region):
        result["invoke"] = sorted(bpy.ops.bdinterp.bake('INVOKE_DEFAULT'))
    yield
    window.event_simulate('MOUSEMOVE', 'NOTHING', x=x, y=y)
    window.event_simulate('ESC', 'PRESS', x=x, y=y)
    window.event_simulate('ESC', 'RELEASE', x=x, y=y)
    for _ in range(60):  # longer than the whole bake takes (ticks_to_bake): it really stopped
        yield
        if len(keys(obj)) > 2:
            break
    result["after_cancel"] = keys(obj)
    result["slider_after_cancel"] = "Bend.bdi" in obj.keys()
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.bdinterp.bake('INVOKE_DEFAULT')
    for tick in range(60):
        yield
        if len(keys(obj)) > 2:
            break
    result["after_bake"], result["ticks_to_bake"] = len(keys(obj)), tick + 1
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.ed.undo()
    yield
    result["after_undo"] = keys(bpy.data.objects["Strip"])


def main():
    sys.path.insert(0, os.path.join(ROOT, "examples", "blender"))
    from window_steps import run_steps
    run_steps(steps(), result, 0.05)


main()
