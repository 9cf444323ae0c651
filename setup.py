"""Builds the Python module glint with CMake (pip install ., see docs/python.md).

Only the native target _glint is built, portably (GLINT_NATIVE=OFF: no
-march=native, so the module runs on any x86-64 CPU, not just the one that
built it), without tests, benchmarks or MPI. Extra CMake arguments can be
given in the environment variable CMAKE_ARGS; CMAKE_BUILD_PARALLEL_LEVEL
sets the build's jobs. GLINT_BUILD_DIR=<folder> packages the module of an
existing CMake build of glint instead of compiling the library again.
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(glint VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        out_dir = Path(self.get_ext_fullpath(ext.name)).resolve().parent
        prebuilt = os.environ.get("GLINT_BUILD_DIR")
        if prebuilt:
            self.copy_prebuilt(Path(prebuilt).resolve(), out_dir)
            return
        build_dir = Path(self.build_temp).resolve() / "cmake"
        build_dir.mkdir(parents=True, exist_ok=True)
        args = [
            "-DCMAKE_BUILD_TYPE=Release",
            "-DGLINT_NATIVE=OFF",
            "-DGLINT_PYTHON=ON",
            "-DGLINT_BUILD_TESTS=OFF",
            "-DGLINT_BUILD_BENCH=OFF",
            "-DGLINT_MPI=OFF",
            f"-DPython_EXECUTABLE={sys.executable}",
            f"-DGLINT_PYTHON_OUTPUT_DIR={out_dir}",
        ]
        if shutil.which("ninja"):
            args.append("-GNinja")
        args += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build_dir)] + args, check=True)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_glint"], check=True)

    def copy_prebuilt(self, build_dir, out_dir):
        """GLINT_BUILD_DIR: a CMake build folder of glint configured with the
        Python module (its own flags: -march=native unless GLINT_NATIVE=OFF).
        Its _glint is brought up to date and packaged; nothing is configured."""
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "_glint"], check=True)
        modules = sorted((build_dir / "python" / "glint").glob("_glint*.so"))
        if not modules:
            sys.exit(f"GLINT_BUILD_DIR={build_dir}: no python/glint/_glint*.so after the build")
        out_dir.mkdir(parents=True, exist_ok=True)
        shutil.copy2(modules[0], Path(self.get_ext_fullpath("glint._glint")))


setup(
    version=version(),
    packages=["glint"],
    package_dir={"": "python"},
    package_data={"glint": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("glint._glint", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
