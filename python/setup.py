"""pip install --no-build-isolation ./python: builds the module with the
project's CMake build and packages it (docs/python.md).

The module needs the C++ sources of the repository around this folder, so
this works from a checkout or source archive, not from this folder alone.
The build folder is $CMR_BUILD_DIR, else <repository>/build: an existing
build is reused (only the module's targets are built in it). Configuring a
fresh one needs the Debian packages of tools/setup.sh."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import setup
from setuptools.dist import Distribution
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


class BuildWithCMake(build_py):
    def run(self):
        if not (ROOT / "CMakeLists.txt").exists() or not (ROOT / "bezierize").is_dir():
            raise SystemExit("cmr: the python/ folder must be inside the cmr repository (it builds its C++ sources)")
        build = Path(os.environ.get("CMR_BUILD_DIR", ROOT / "build"))
        if not (build / "CMakeCache.txt").exists():
            subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja",
                                   "-DCMAKE_BUILD_TYPE=Release", f"-DPython3_EXECUTABLE={sys.executable}",
                                   "-DCMR_WITH_PYTHON=ON"])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "_cmr", "cmr_python_package"])
        package = build / "python" / "cmr"
        target = Path(self.build_lib) / "cmr"
        if target.exists():
            shutil.rmtree(target)
        shutil.copytree(package, target, ignore=shutil.ignore_patterns("__pycache__"))


class BinaryDistribution(Distribution):
    """A wheel for this platform and Python (the package holds a compiled module)."""

    def has_ext_modules(self):
        return True


setup(packages=[], cmdclass={"build_py": BuildWithCMake}, distclass=BinaryDistribution)
