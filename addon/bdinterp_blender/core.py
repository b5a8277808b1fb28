"""Loads the compiled bdinterp core for this Blender's Python (no bpy): the one place that knows
where the module lives in a zip and what to say when it does not fit."""

import json
import os
import re
import sys
import sysconfig

_HERE = os.path.dirname(os.path.abspath(__file__))
_VENDOR = os.path.join(_HERE, "_vendor")


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
