"""Loads the compiled bdinterp core for this Blender's Python (no bpy): the one place that knows
where the module lives and what to say when it does not fit.

Two layouts (scripts/build_addon.py):
  legacy zip (Blender 3.4-4.1): the package vendored as bdinterp_blender/_vendor/bdinterp and
      imported as that subpackage, so it stays private to the add-on (no sys.path entry, no global
      `bdinterp` that another add-on's copy could shadow or be shadowed by);
  extension zip (4.2+): Blender installs the wheel for its Python (./wheels/, listed in
      blender_manifest.toml) into the extensions' site-packages; `import bdinterp` finds it.
A source checkout uses whatever `bdinterp` the Python has installed.
"""

import importlib
import importlib.abc
import importlib.util
import json
import os
import platform
import re
import sys
import sysconfig

_HERE = os.path.dirname(os.path.abspath(__file__))
_VENDOR = os.path.join(_HERE, "_vendor")
PACKAGE = __name__.rpartition(".")[0]  # 'bdinterp_blender' or 'bl_ext.<repo>.bdinterp_blender'


def build_info():
    """What the zip was built with (written by scripts/build_addon.py), or {} for a source checkout.
    Keys: version, platform, pythons (['3.11', '3.13', '3.14']), layout ('legacy' | 'extension')."""
    try:
        with open(os.path.join(_HERE, "build_info.json"), encoding="utf-8") as f:
            return json.load(f)
    except OSError:
        return {}


def _core_dir():
    """Directory of the bdinterp package this add-on would import (None: none found), unimported."""
    if os.path.isdir(_VENDOR):
        return os.path.join(_VENDOR, "bdinterp")
    spec = importlib.util.find_spec("bdinterp")
    return os.path.dirname(spec.origin) if spec and spec.origin else None


# What a platform without a shipped module needs to build one (docs/PLATFORMS.md).
_BUILD_HINTS = {
    "windows": "Visual Studio 2019+ and vcpkg's suitesparse (CHOLMOD), eigen3 and pybind11",
    "macos": "Xcode's command-line tools and Homebrew's suite-sparse, eigen and pybind11",
}


def running_platform():
    """Blender's name of this machine's platform: 'linux-x64', 'windows-x64', 'macos-arm64', ..."""
    system = {"win32": "windows", "darwin": "macos"}.get(sys.platform, sys.platform.rstrip("0123456789"))
    machine = platform.machine().lower()
    arch = {"x86_64": "x64", "amd64": "x64", "aarch64": "arm64"}.get(machine, machine)
    return "%s-%s" % (system, arch)


def _platform_message(info, here):
    """The message for a platform this zip has no module for ('' when it has one)."""
    built = info.get("platforms") or [info.get("platform")]
    if not info.get("platform") and not info.get("platforms") or here in built:
        return ""
    hint = _BUILD_HINTS.get(here.split("-")[0], "a C++17 compiler, CMake, Eigen, pybind11 and CHOLMOD")
    return ("bdinterp: this add-on carries its compiled solver for %s only, and this Blender runs on "
            "%s. No %s build is published yet: build bdinterp from source there (docs/PLATFORMS.md; "
            "it needs %s), or use Blender on %s." % (", ".join(built), here, here, hint, built[0]))


def core_status(ext_suffix=None, platform_name=None):
    """Return (ok, message) about the compiled core, without importing it.

    Checked by file name so that a Blender whose Python cannot load the shipped module gets a
    readable message in the UI instead of an ImportError traceback at enable time.
    ext_suffix defaults to this interpreter's (e.g. '.cpython-311-x86_64-linux-gnu.so'),
    platform_name to this machine's (running_platform()).
    """
    ext_suffix = ext_suffix or sysconfig.get_config_var("EXT_SUFFIX") or ""
    m = re.match(r"\.cp(?:ython-)?(\d)(\d+)-", ext_suffix)
    running = "%s.%s" % m.groups() if m else "%d.%d" % sys.version_info[:2]
    info = build_info()
    pkg = _core_dir()
    if not info and pkg is None:
        return True, ""  # source checkout without an installed bdinterp: reported on first use
    wrong_platform = _platform_message(info, platform_name or running_platform())
    if wrong_platform:
        return False, wrong_platform
    shipped = sorted(n for n in os.listdir(pkg) if n.startswith("_core")
                     and n.endswith((".so", ".pyd"))) if pkg and os.path.isdir(pkg) else []
    if any(n.endswith(ext_suffix) for n in shipped):
        return True, ""
    built = ", ".join(info.get("pythons", [])) or "?"
    what = ("wheels of bdinterp" if info.get("layout") == "extension"
            else "a compiled module (%s)" % (", ".join(shipped) or "none"))
    return False, (
        "bdinterp: this add-on carries %s for Python %s, but this Blender runs Python %s "
        "(needs _core%s). Install the bdinterp_blender zip built for Python %s."
        % (what, built, running, ext_suffix, running))


def load_core():
    """Import and return the bdinterp package (the add-on's own copy); RuntimeError with a clear
    message if it cannot be loaded. Imported lazily: numpy and the compiled solver are heavy."""
    ok, message = core_status()
    if not ok:
        raise RuntimeError(message)
    name = PACKAGE + "._vendor.bdinterp" if os.path.isdir(_VENDOR) else "bdinterp"
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise RuntimeError("bdinterp: the compiled core could not be loaded (%s)" % exc) from exc


class _Loaded(importlib.abc.Loader):
    """Loader of a module that is already imported under its real name."""

    def __init__(self, module):
        self.module, self.spec = module, module.__spec__

    def create_module(self, spec):
        return self.module

    def exec_module(self, module):
        module.__spec__ = self.spec  # importlib set the alias's spec; keep the real one


class _AliasFinder(importlib.abc.MetaPathFinder):
    """Resolves `alias.sub` to the already-imported `real.sub`, so that `import
    bdinterp_blender.ui.panels` under an extension gives bl_ext.<repo>.bdinterp_blender.ui.panels;
    without it Python loads the file again and the copy's state (e.g. CORE_ERROR) diverges."""

    def __init__(self, alias, real):
        self.alias, self.real = alias, real

    def find_spec(self, fullname, path=None, target=None):
        if not fullname.startswith(self.alias + "."):
            return None
        module = importlib.import_module(self.real + fullname[len(self.alias):])
        return importlib.util.spec_from_loader(fullname, _Loaded(module))


def alias_package(module, alias="bdinterp_blender"):
    """Make the package `module` (an extension's bl_ext.<repo>.bdinterp_blender) importable as
    `alias`, submodules included, for scripts that write `import bdinterp_blender`."""
    sys.modules[alias] = module
    if module.__name__ == alias:
        return
    sys.meta_path[:] = [f for f in sys.meta_path
                        if not (isinstance(f, _AliasFinder) and f.alias == alias)]
    sys.meta_path.insert(0, _AliasFinder(alias, module.__name__))
    for name in [n for n in sys.modules if n.startswith(alias + ".")]:
        del sys.modules[name]  # copies loaded before the alias (or from a replaced build)
