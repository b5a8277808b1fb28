"""bdinterp for Blender: bounded-distortion in-betweens for planar meshes with shape keys.

Scripting (see api.py):  ``import bdinterp_blender; bdinterp_blender.bake(obj, target="Key 1")``.
"""

bl_info = {
    "name": "bdinterp: Bounded-Distortion In-betweens",
    "author": "bdinterp developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View > Sidebar > bdinterp",
    "description": "Bake and live-update bounded-distortion in-betweens and pose blends "
                   "of planar meshes with shape keys",
    "category": "Animation",
}

import json
import os
import re
import sys
import sysconfig

_HERE = os.path.dirname(os.path.abspath(__file__))
_VENDOR = os.path.join(_HERE, "_vendor")

# Scripting name: as an extension (Blender 4.2+) this package is imported as
# bl_ext.<repo>.bdinterp_blender, but scripts should be able to write `import bdinterp_blender`.
sys.modules.setdefault("bdinterp_blender", sys.modules[__name__])


def build_info():
    """What the zip was built with (written by scripts/build_addon.py), or {} for a source checkout."""
    try:
        with open(os.path.join(_HERE, "build_info.json"), encoding="utf-8") as f:
            return json.load(f)
    except OSError:
        return {}


def core_status(ext_suffix=None):
    """Return (ok, message) about the compiled core, without importing it.

    Checked by file name so that a Blender whose Python cannot load the shipped module gets a
    readable message in the UI instead of an ImportError traceback at enable time.
    ext_suffix defaults to this interpreter's (e.g. '.cpython-311-x86_64-linux-gnu.so').
    """
    ext_suffix = ext_suffix or sysconfig.get_config_var("EXT_SUFFIX") or ""
    m = re.match(r"\.cpython-(\d)(\d+)-", ext_suffix)
    running = "%s.%s" % m.groups() if m else "%d.%d" % sys.version_info[:2]
    pkg = os.path.join(_VENDOR, "bdinterp")
    if not os.path.isdir(pkg):
        return True, ""  # source checkout: use an installed bdinterp (checked on first use)
    shipped = sorted(n for n in os.listdir(pkg) if n.startswith("_core") and n.endswith((".so", ".pyd")))
    if any(n.endswith(ext_suffix) for n in shipped):
        return True, ""
    info = build_info()
    built = info.get("python", "?")
    return False, (
        "bdinterp: this add-on zip carries a compiled module for Python %s (%s), but this Blender "
        "runs Python %s (needs %s). Install the bdinterp_blender zip built for Python %s."
        % (built, ", ".join(shipped) or "none", running, "_core" + ext_suffix, running))


def load_core():
    """Import and return the bdinterp package (vendored copy first); RuntimeError with a clear
    message if it cannot be loaded. Imported lazily: numpy and the compiled solver are heavy."""
    ok, message = core_status()
    if not ok:
        raise RuntimeError(message)
    if os.path.isdir(_VENDOR) and _VENDOR not in sys.path:
        sys.path.insert(0, _VENDOR)
    try:
        import bdinterp
    except ImportError as exc:
        raise RuntimeError("bdinterp: the compiled core could not be loaded (%s)" % exc) from exc
    return bdinterp


from .api import (bake, blend, clear, compute_frames, set_live, hide_distortion,  # noqa: E402
                  show_distortion, BakeError)

__all__ = ["bake", "blend", "clear", "compute_frames", "set_live", "show_distortion",
           "hide_distortion", "BakeError", "load_core", "core_status", "build_info"]

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
        from . import properties, operators, live as live_mod
        _modules = [properties, operators, ui, live_mod]
    for mod in _modules:
        mod.register()


def unregister():
    for mod in reversed(_modules):
        mod.unregister()
    _modules.clear()
