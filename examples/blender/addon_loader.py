"""Enable the bdinterp add-on for the example scripts, wherever it is installed.

Blender 3.4-4.1 name it 'bdinterp_blender' (legacy add-on), 4.2+ 'bl_ext.<repo>.bdinterp_blender'
when installed as an extension; without either, addon/ of this checkout is registered (it needs
an importable bdinterp).  Returns the add-on's package.
"""

import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def enable():
    import addon_utils
    names = [m.__name__ for m in addon_utils.modules() if m.__name__.split(".")[-1] == "bdinterp_blender"]
    if names and addon_utils.enable(names[0], default_set=True, handle_error=lambda exc: None):
        return sys.modules[names[0]]
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    import bdinterp_blender
    bdinterp_blender.register()
    return bdinterp_blender
