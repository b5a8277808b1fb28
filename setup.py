"""Builds the compiled module bdinterp._core with CMake (offline: pip install --no-build-isolation .).

scikit-build-core is not packaged for Debian 12, so a small build_ext drives CMake directly.
"""
import os
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        out_dir = Path(self.get_ext_fullpath(ext.name)).resolve().parent
        build_dir = Path(self.build_temp).resolve() / "cmake"
        build_dir.mkdir(parents=True, exist_ok=True)
        subprocess.run([
            "cmake", str(ROOT), "-DCMAKE_BUILD_TYPE=Release", "-DBDINTERP_TESTS=OFF",
            "-DBDINTERP_PYTHON=ON", f"-DBDINTERP_PYTHON_OUTPUT_DIR={out_dir}",
            f"-DPython_EXECUTABLE={sys.executable}"], cwd=build_dir, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", ".", "--target", "_core", "-j", jobs],
                       cwd=build_dir, check=True)


setup(ext_modules=[CMakeExtension("bdinterp._core")], cmdclass={"build_ext": CMakeBuild})
