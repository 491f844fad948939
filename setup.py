# SPDX-License-Identifier: MIT
"""Builds the Python package `plancheck` with the project's CMake.

The setuptools + CMake pattern of pybind11's cmake_example: the package's
Python files are src/python/plancheck/, its one extension,
plancheck._plancheck, is the CMake target plancheck_python (src/python),
which links the static core into itself. Metadata: pyproject.toml; the
version is the one of `project(plancheck VERSION ...)` in CMakeLists.txt.

A plain `pip install .` configures its own CMake build under
build/pip/ with only what the module needs (no tests, benchmarks, viewer
or MPI) and builds that one target. PLANCHECK_CMAKE_BUILD_DIR=DIR instead
takes the module already built in the CMake build folder DIR (its
python/plancheck/), for the same python3; tests/python's install test uses
it so as not to compile the core a second time.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
GIVEN_BUILD = os.environ.get("PLANCHECK_CMAKE_BUILD_DIR")


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    m = re.search(r"project\(\s*plancheck\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", text)
    if not m:
        sys.exit("setup.py: no `project(plancheck VERSION x.y.z ...)` in %s" % (ROOT / "CMakeLists.txt"))
    return m.group(1)


class CMakeBuild(build_ext):
    """Builds (or, with PLANCHECK_CMAKE_BUILD_DIR, takes) the CMake target plancheck_python."""

    def build_extension(self, ext):
        name = "_plancheck" + sysconfig.get_config_var("EXT_SUFFIX")
        if GIVEN_BUILD:
            built = Path(GIVEN_BUILD).resolve() / "python" / "plancheck" / name
            if not built.is_file():
                sys.exit("setup.py: PLANCHECK_CMAKE_BUILD_DIR=%s has no python/plancheck/%s: build the target "
                         "plancheck_python there for %s first" % (GIVEN_BUILD, name, sys.executable))
        else:
            build = Path(self.build_temp).resolve() / "cmake"
            configure = [
                "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                "-DPython3_EXECUTABLE=" + sys.executable,
                "-DPLANCHECK_PYTHON=ON", "-DPLANCHECK_BUILD_TESTS=OFF", "-DPLANCHECK_BUILD_BENCH=OFF",
                "-DPLANCHECK_VIEWER=OFF", "-DPLANCHECK_BROWSER_TESTS=OFF", "-DPLANCHECK_MPI=OFF",
                "-DPLANCHECK_INSTALL_TEST=OFF",
            ]
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
            try:  # pybind11 from pip (isolated builds) when there is no system one
                import pybind11
                configure.append("-Dpybind11_DIR=" + pybind11.get_cmake_dir())
            except ImportError:
                pass
            compile_ = ["cmake", "--build", str(build), "--target", "plancheck_python"]
            if "CMAKE_BUILD_PARALLEL_LEVEL" not in os.environ:
                compile_ += ["-j", str(self.parallel or os.cpu_count() or 1)]
            subprocess.run(configure, check=True)
            subprocess.run(compile_, check=True)
            built = build / "python" / "plancheck" / name
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


# setuptools' own work folders: under the CMake build folder given, else build/pip.
work = str(Path(GIVEN_BUILD).resolve() / "pip") if GIVEN_BUILD else "build/pip"
Path(work).mkdir(parents=True, exist_ok=True)  # egg_info wants its folder to exist
setup(
    version=project_version(),
    packages=["plancheck"],
    package_dir={"": "src/python"},
    package_data={"plancheck": ["_plancheck.pyi", "py.typed"]},
    ext_modules=[Extension("plancheck._plancheck", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    options={"build": {"build_base": work}, "egg_info": {"egg_base": work}},
)
