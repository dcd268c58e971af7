"""Builds the _hemirad extension with CMake for `pip install --no-build-isolation .` (pyproject.toml)."""

import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).parent.resolve()


class CMakeBuild(build_ext):
    """Configures the project with only what the module needs, builds its target, copies the result."""

    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        options = ["-DCMAKE_BUILD_TYPE=Release", f"-DPython3_EXECUTABLE={sys.executable}", "-DHEMIRAD_WITH_PYTHON=ON",
                   "-DHEMIRAD_WITH_TESTS=OFF", "-DHEMIRAD_WITH_BENCH=OFF", "-DHEMIRAD_WITH_GUI=OFF",
                   "-DHEMIRAD_WITH_MPI=OFF"]
        subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build), *options])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "_hemirad", "-j", str(os.cpu_count() or 1)])
        built = next((build / "python" / "hemirad").glob("_hemirad*.so"))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(ext_modules=[Extension("hemirad._hemirad", sources=[])], cmdclass={"build_ext": CMakeBuild})
