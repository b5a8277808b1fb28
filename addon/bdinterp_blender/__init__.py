"""bdinterp for Blender: bounded-distortion in-betweens for planar meshes with shape keys.

Scripting (see api.py):  ``import bdinterp_blender; bdinterp_blender.bake(obj, target="Key 1")``.

Modules import one way, lower layers only (tests/blender/test_structure.py): core (loader), names
-> timing, mesh_io -> rig (joints from bones) -> settings (BakeSettings) -> solve (shapes ->
frames, no writes) -> playback, distortion, sprite_mesh -> baking, export, layered_import (each
module of these two layers writes one kind of thing) -> character (several objects baked as one)
-> live -> api (the scripting facade), motion_trails, drawing_bind -> properties, operators,
onion -> ui -> this file (registration).
"""

if "api" in locals():  # F3 "Reload Scripts" / addon_utils reload: reload submodules, lowest first
    import importlib
    for _name in ("core", "names", "actions", "overlay", "painting_files", "pivots", "timing", "mesh_io",
                  "rig", "settings", "solve", "playback", "distortion", "sprite_mesh", "baking",
                  "export", "layered_import", "character", "posing", "live", "api", "motion_trails",
                  "drawing_bind", "properties", "operators", "pose_operators", "onion", "ui"):
        if _name in locals():
            importlib.reload(locals()[_name])

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
# (and `import bdinterp_blender.ui`: the same module objects, see core.alias_package).
alias_package(sys.modules[__name__])
from .api import (bake, blend, clear, compute_frames, set_live, hide_distortion,  # noqa: E402
                  show_distortion, BakeError)
from .api import bake_live, bake_for_export, error_bound_factors, remove_export_bake  # noqa: E402
from .api import add_pose, torn_joints  # noqa: E402
from .sprite_mesh import mesh_from_image  # noqa: E402
from .layered_import import import_layered  # noqa: E402
from .motion_trails import trails  # noqa: E402
from .drawing_bind import bind_drawing, unbind_drawing  # noqa: E402

__all__ = ["bake", "bake_live", "bake_for_export", "remove_export_bake", "error_bound_factors", "blend",
           "clear", "compute_frames", "set_live", "show_distortion", "hide_distortion", "BakeError",
           "mesh_from_image", "import_layered", "load_core", "core_status", "build_info", "trails",
           "bind_drawing", "unbind_drawing", "add_pose", "torn_joints"]

_modules = []


def register():
    from . import ui
    global _modules
    ok, message = core_status()
    if not ok:
        # Degraded mode: only the panel and the preferences explain what is wrong.
        print(message)
        ui.CORE_ERROR = message
        _modules = [ui.degraded]
    else:
        from . import properties, onion, drawing_bind, operators, live as live_mod, sprite_mesh, layered_import
        from . import pose_operators
        _modules = [properties, onion, drawing_bind, operators, pose_operators, ui, live_mod, sprite_mesh,
                    layered_import]
    for mod in _modules:
        mod.register()


def unregister():
    for mod in reversed(_modules):
        mod.unregister()
    _modules.clear()
