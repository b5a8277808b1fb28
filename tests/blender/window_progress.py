"""Child script for test_window.py: the example painting's ten pieces, posed with Add Pose, baked
from the sidebar's Bake button as the UI runs it (INVOKE: modal, on a thread), in a real window;
records what the panel says at each redraw while the bake runs and saves a screenshot of the
window mid-bake (the sidebar open on the bdinterp tab, the status bar).

    xvfb-run ... blender --factory-startup --enable-event-simulate --python window_progress.py \
        -- OUT.png
Prints 'JSON:{...}' and quits."""

import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
COUNT = 12  # in-betweens: several chunks, so that the bake is seen under way

result = {"seen": [], "draws": 0}


def character(bdi):
    """The painting imported, posed (the right arm raised), the torso active with the settings."""
    from render_layers import PAINTING, SCALE, pose
    objs = bdi.import_layered(PAINTING, scale=SCALE)
    pose(bdi, objs)
    torso = bpy.data.objects["torso"]
    bpy.context.view_layer.objects.active = torso
    torso.bdi.count = COUNT
    return objs


def count_draws():
    """result['draws']: how often the add-on's main panel drew (so its tab is known to be open)."""
    from bdinterp_blender.ui import panels as ui
    draw = ui.BDINTERP_PT_main.draw

    def counted(self, context):
        result["draws"] += 1
        draw(self, context)
    ui.BDINTERP_PT_main.draw = counted


def steps(out):
    sys.path.insert(0, os.path.join(ROOT, "examples", "blender"))
    import addon_loader
    bdi = addon_loader.enable()
    from bdinterp_blender.ui import operators
    bpy.context.preferences.view.show_splash = False
    objs = character(bdi)
    count_draws()
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == 'VIEW_3D'), key=lambda a: a.width)
    area.spaces.active.show_region_ui = True
    main = next(r for r in area.regions if r.type == 'WINDOW')
    with bpy.context.temp_override(window=window, area=area, region=main):
        bpy.ops.view3d.view_selected()
    yield
    from window_steps import click_tabs
    yield from click_tabs(window, next(r for r in area.regions if r.type == 'UI'),
                          lambda: result["draws"])
    with bpy.context.temp_override(window=window, area=area, region=main):
        result["invoke"] = sorted(bpy.ops.bdinterp.bake('INVOKE_DEFAULT'))
    for _ in range(600):
        yield
        text = operators.progress_text()
        if text and text not in result["seen"]:
            result["seen"].append(text)
            if "shot" not in result and not text.startswith("Baking 0 "):
                steps_done()  # Blender 3.4's screenshot crashes while another Python thread runs
                with bpy.context.temp_override(window=window):
                    bpy.ops.screen.screenshot(filepath=out)
                result["shot"] = out
        if not text and result["seen"]:
            break
    result["keys"] = len(objs[0].data.shape_keys.key_blocks)
    result["after"] = operators.progress_text()
    yield from torn(objs, window, area, main)


def steps_done():
    """Waits for the bake's step in flight (its thread): no step starts while this callback runs."""
    import threading
    for thread in threading.enumerate():
        if thread is not threading.main_thread() and thread.daemon:
            thread.join(60)


def torn(objs, window, area, main):
    """The forearm pulled off its upper arm: Bake asks first (nothing baked); OK bakes."""
    import numpy as np
    forearm, torso = bpy.data.objects["forearm_r"], bpy.data.objects["torso"]
    kb = forearm.data.shape_keys.key_blocks["Pose"]
    co = np.empty(len(kb.data) * 3, np.float32)
    kb.data.foreach_get("co", co)
    kb.data.foreach_set("co", (co.reshape(-1, 3) + [0.3, 0.0, 0.0]).ravel())
    forearm.data.update()
    yield
    before = torso.bdi.result
    with bpy.context.temp_override(window=window, area=area, region=main):
        result["torn_invoke"] = sorted(bpy.ops.bdinterp.bake('INVOKE_DEFAULT'))
    yield
    result["torn_unbaked"] = torso.bdi.result == before
    report = bdi_torn_report(objs)
    with bpy.context.temp_override(window=window, area=area, region=main):
        result["torn_ok"] = sorted(bpy.ops.bdinterp.confirm_torn('EXEC_DEFAULT', report=report))
    for _ in range(600):
        yield
        if torso.bdi.result != before:
            break
    result["torn_baked"] = torso.bdi.result != before
    result["torn_report"] = report


def bdi_torn_report(objs):
    import bdinterp_blender
    from bdinterp_blender.keys import posing
    return posing.describe(bdinterp_blender.torn_joints(objs, "Pose"))


def main():
    sys.path.insert(0, HERE)
    sys.path.insert(0, os.path.join(ROOT, "examples", "blender"))
    from window_steps import run_steps
    run_steps(steps(os.path.abspath(sys.argv[sys.argv.index("--") + 1])), result, 0.05)


main()
