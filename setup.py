"""Builds the compiled module bdinterp._core (offline: pip install --no-build-isolation .).

scikit-build-core is not packaged for Debian 12, so a small build_ext drives CMake directly.
BDINTERP_CORE chooses the module the wheel carries:
  portable (the default when build/portable has one for this Python, i.e. after `make portable`):
      the self-contained module of scripts/build-portable.sh (Debian 11, static CHOLMOD/OpenBLAS,
      bundled METIS) - the same file the Blender zips ship; refused if older than the sources;
  source: CMake against this machine's libraries (development).
"""
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
PORTABLE = ROOT / "build" / "portable"


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


def portable_module():
    """The portable build's module for this Python, or None; exits if it is stale."""
    suffix = sysconfig.get_config_var("EXT_SUFFIX")
    so = PORTABLE / ("py%d%d" % sys.version_info[:2]) / ("_core" + suffix)
    if not so.exists():
        return None
    # What goes into the module: the C++ sources and the build's CMake code.
    sources = [p for p in (ROOT / "cpp").rglob("*") if p.is_file()] + list(
        (ROOT / "cmake").glob("*.cmake")) + [ROOT / "CMakeLists.txt"]
    newest = max(p.stat().st_mtime for p in sources)
    if so.stat().st_mtime < newest:
        sys.exit("setup.py: %s is older than the C++ sources: run `make portable` "
                 "(or BDINTERP_CORE=source for a build against this machine's libraries)" % so)
    return so


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        out_dir = Path(self.get_ext_fullpath(ext.name)).resolve().parent
        choice = os.environ.get("BDINTERP_CORE", "portable")
        so = portable_module() if choice == "portable" else None
        if so is not None:
            out_dir.mkdir(parents=True, exist_ok=True)
            for lib in [so] + sorted(so.parent.glob("lib*.so*")):  # + bundled METIS ($ORIGIN)
                shutil.copy(lib, out_dir)
            return
        # Beside `make build`'s folder (same depth): with ccache, the sources it compiled there are
        # not compiled again here (the compiler sees the same relative paths).
        build_dir = ROOT / "build-pip"
        build_dir.mkdir(parents=True, exist_ok=True)
        subprocess.run([
            "cmake", str(ROOT), "-DCMAKE_BUILD_TYPE=Release", "-DBDINTERP_TESTS=OFF",
            "-DBDINTERP_PYTHON=ON", f"-DBDINTERP_PYTHON_OUTPUT_DIR={out_dir}",
            f"-DPython_EXECUTABLE={sys.executable}",
            # given each time: a build folder's cache would otherwise keep the last run's choice
            "-DBDINTERP_SUITESPARSE_SOURCE=" + os.environ.get("BDINTERP_SUITESPARSE_SOURCE", "")],
            cwd=build_dir, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", ".", "--target", "_core", "-j", jobs],
                       cwd=build_dir, check=True)


# The portable module keeps the manylinux_2_31 policy (scripts/audit_so.py), so its wheel says so.
PORTABLE_WHEEL = os.environ.get("BDINTERP_CORE", "portable") == "portable" and portable_module()
setup(ext_modules=[CMakeExtension("bdinterp._core")], cmdclass={"build_ext": CMakeBuild},
      options={"bdist_wheel": {"plat_name": "manylinux_2_31_x86_64"}} if PORTABLE_WHEEL else {})
