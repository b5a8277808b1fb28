"""bdinterp for Blender: bounded-distortion in-betweens for planar meshes with shape keys.

Scripting (see api.py):  ``import bdinterp_blender; bdinterp_blender.bake(obj, target="Key 1")``.

Subpackages by the animator's task, each importing only from the layers before it
(tests/blender/test_structure.py checks it): core (the compiled module's loader), names, actions,
timing, changes (the one pair of scene handlers) -> shapes (keys read, settings, solve: no
writes) -> files (paintings in, Mesh from Image) and keys (what writes shape keys: the slider,
bake jobs, export, characters, live mode) -> view (what the viewport draws) and params (pose
parameters: grids of poses followed live, Bake Grid) -> api (the scripting facade) and strokes (Grease Pencil in-betweens, their operator and panel)
-> ui (properties, operators, panels) -> this file (registration).
"""

# The modules in import order (lowest first): the reload idiom below and the layering test use it.
MODULES = ("core", "names", "actions", "timing", "changes",
           "shapes.pivots", "shapes.mesh_io", "shapes.rig", "shapes.hand_joints", "shapes.settings",
           "shapes.solve",
           "files.painting_files", "files.sprite_mesh", "files.layered_import",
           "keys.playback", "keys.baking", "keys.export", "keys.character", "keys.posing", "keys.live",
           "view.overlay", "view.distortion", "view.motion_trails", "view.ghosts", "view.onion",
           "view.locate", "view.drawing_bind", "view.joint_view",
           "params.live", "params.setup", "params.bake_grid",
           "strokes.drawing", "strokes.ops", "api", "ui.properties", "ui.operators",
           "ui.pose_operators", "ui.panels",
           "ui.pose_grids")

if "api" in locals():  # F3 "Reload Scripts" / addon_utils reload: reload submodules, lowest first
    import importlib
    import sys as _sys
    for _name in MODULES:
        _module = _sys.modules.get(__name__ + "." + _name)
        if _module is not None:
            importlib.reload(_module)

bl_info = {
    "name": "bdinterp: Bounded-Distortion In-betweens",
    "author": "bdinterp developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View > Sidebar > bdinterp",
    "description": "Bake and live-update bounded-distortion in-betweens and pose blends "
                   "of planar meshes with shape keys",
    "category": "Animation",
    "license": "GPL-3.0-or-later",
}

import sys

from .core import alias_package, build_info, core_status, load_core  # noqa: E402

# Scripting name: as an extension (Blender 4.2+) this package is imported as
# bl_ext.<repo>.bdinterp_blender, but scripts should be able to write `import bdinterp_blender`
# (and `import bdinterp_blender.ui.panels`: the same module objects, see core.alias_package).
alias_package(sys.modules[__name__])
from .api import (bake, blend, clear, compute_frames, set_live, hide_distortion,  # noqa: E402
                  show_distortion, BakeError)
from .api import bake_live, bake_for_export, error_bound_factors, remove_export_bake  # noqa: E402
from .api import add_pose, torn_joints  # noqa: E402
from .files.sprite_mesh import mesh_from_image  # noqa: E402
from .files.layered_import import import_layered  # noqa: E402
from .view.motion_trails import trails  # noqa: E402
from .view.drawing_bind import bind_drawing, unbind_drawing  # noqa: E402
from .strokes.drawing import interpolate_drawing  # noqa: E402
from .params.setup import drive_by_bone, pose_grid, pose_grid_report, remove_pose_grid  # noqa: E402
from .params.bake_grid import bake_grid  # noqa: E402

__all__ = ["bake", "bake_live", "bake_for_export", "remove_export_bake", "error_bound_factors", "blend",
           "clear", "compute_frames", "set_live", "show_distortion", "hide_distortion", "BakeError",
           "mesh_from_image", "import_layered", "load_core", "core_status", "build_info", "trails",
           "bind_drawing", "unbind_drawing", "interpolate_drawing", "pose_grid", "drive_by_bone",
           "remove_pose_grid", "bake_grid", "pose_grid_report",
           "add_pose", "torn_joints"]

_modules = []


def register():
    from .ui import panels as ui
    global _modules
    ok, message = core_status()
    if not ok:
        # Degraded mode: only the panel and the preferences explain what is wrong.
        print(message)
        ui.CORE_ERROR = message
        _modules = [ui.degraded]
    else:
        from .ui import properties, operators, pose_operators
        from .view import onion, drawing_bind, joint_view
        from .keys import live as live_mod
        from .files import sprite_mesh, layered_import
        from .strokes import ops as strokes_ops
        from .params import live as grid_live
        from .ui import pose_grids
        _modules = [properties, onion, joint_view, drawing_bind, operators, pose_operators, ui,
                    live_mod, sprite_mesh, layered_import,
                    strokes_ops, grid_live, pose_grids]
    for mod in _modules:
        mod.register()


def unregister():
    for mod in reversed(_modules):
        mod.unregister()
    _modules.clear()
