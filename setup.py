# SPDX-License-Identifier: GPL-3.0-or-later
"""`pip install .`: the libshadow Python module built by this repository's CMake.

setuptools only packages: CMake configures and builds the library and the pybind11 module (the
target libshadow_python, as `cmake --build` does), and the wheel takes the module
(`_libshadow*.so`) with the shared libraries it links, `libshadow.so.N` (compute) and
`libshadow_io.so.N` (file formats), beside it; the module's
RPATH is set to $ORIGIN, so it loads that copy wherever it is installed. `__init__.py` comes from
python/libshadow/.

Environment:
  LIBSHADOW_BUILD_DIR  a CMake build tree to use (configured here when it has no CMakeCache.txt;
                       an existing one, such as build/release, is reused as it is: only
                       libshadow_python is built, nothing when it is up to date). Default:
                       build/pip, configured Release with the tools, tests and examples off.
  CMAKE_ARGS           more -D options for a new configuration (split as a shell would).
  CMAKE_BUILD_PARALLEL_LEVEL  jobs for the build, as for `cmake --build`.
See docs/python.md."""
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))


def version():
    with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
        match = re.search(r"project\(libshadow\s+VERSION\s+([0-9.]+)", f.read())
    if not match:
        raise RuntimeError("no `project(libshadow VERSION ...)` in CMakeLists.txt")
    return match.group(1)


def linked_libshadow(module, build_dir):
    """The libshadow shared libraries (libshadow.so.N, the compute component, and libshadow_io.so.N,
    the file formats) that the built module loads, as the dynamic loader resolves them; empty for
    a module linked with a static libshadow."""
    try:
        out = subprocess.run(["ldd", module], check=True, capture_output=True, text=True).stdout
        found = []
        for line in out.splitlines():
            match = re.match(r"\s*(libshadow(_io)?\.so\.\d+)\s+=>\s+(\S+)", line)
            if match:
                found.append(match.group(3))
        return found
    except (OSError, subprocess.CalledProcessError):  # no ldd: where CMake puts shared libraries
        found = []
        for name in ("libshadow.so.*", "libshadow_io.so.*"):
            candidates = sorted(glob.glob(os.path.join(build_dir, "lib", name)), key=len)
            found += candidates[:1]
        return found


class CMakeBuild(build_ext):
    """Builds the extension with CMake instead of compiling sources itself."""

    def run(self):
        for ext in self.extensions:
            self.build_cmake(ext)

    def build_cmake(self, ext):
        cmake = shutil.which("cmake")
        if cmake is None:
            raise RuntimeError("libshadow needs CMake to build (Debian: cmake); see docs/python.md")
        build_dir = os.path.abspath(os.environ.get("LIBSHADOW_BUILD_DIR") or os.path.join(HERE, "build", "pip"))
        if not os.path.exists(os.path.join(build_dir, "CMakeCache.txt")):
            args = [cmake, "-S", HERE, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
                    "-DLIBSHADOW_BUILD_TOOLS=OFF", "-DLIBSHADOW_BUILD_TESTS=OFF", "-DLIBSHADOW_BUILD_EXAMPLES=OFF",
                    "-DLIBSHADOW_BUILD_BASELINES=OFF", "-DLIBSHADOW_BUILD_TESTING_KIT=OFF", "-DLIBSHADOW_PYTHON=ON",
                    "-DPython3_EXECUTABLE=" + sys.executable]
            if shutil.which("ninja"):
                args += ["-G", "Ninja"]
            args += shlex.split(os.environ.get("CMAKE_ARGS", ""))
            subprocess.run(args, check=True)
        subprocess.run([cmake, "--build", build_dir, "--target", "libshadow_python"], check=True)
        modules = glob.glob(os.path.join(build_dir, "python", "libshadow", "_libshadow*.so"))
        expected = os.path.abspath(self.get_ext_fullpath(ext.name))
        if len(modules) != 1:
            raise RuntimeError("the CMake build in %s has no libshadow Python module (found %d): is pybind11-dev "
                               "installed?" % (build_dir, len(modules)))
        if os.path.basename(modules[0]) != os.path.basename(expected):
            raise RuntimeError("the CMake build in %s made %s, a module for another Python than %s (%s): give that "
                               "build -DPython3_EXECUTABLE=%s, or another LIBSHADOW_BUILD_DIR"
                               % (build_dir, os.path.basename(modules[0]), sys.executable,
                                  os.path.basename(expected), sys.executable))
        os.makedirs(os.path.dirname(expected), exist_ok=True)
        shutil.copyfile(modules[0], expected)
        libraries = linked_libshadow(modules[0], build_dir)
        if not libraries:
            return  # a static libshadow: the module is self-contained
        # Under their SONAMEs, dereferenced (a wheel holds no links), and found through $ORIGIN.
        for library in libraries:
            shutil.copyfile(library, os.path.join(os.path.dirname(expected), os.path.basename(library)))
        with tempfile.TemporaryDirectory(prefix="libshadow-pip-") as scratch:
            script = os.path.join(scratch, "rpath.cmake")
            with open(script, "w", encoding="utf-8") as f:
                f.write('file(RPATH_SET FILE "${MODULE}" NEW_RPATH "$ORIGIN")\n')
            subprocess.run([cmake, "-DMODULE=" + expected, "-P", script], check=True, stdout=subprocess.DEVNULL)


setup(
    version=version(),
    packages=["libshadow"],
    package_dir={"libshadow": "python/libshadow"},
    ext_modules=[Extension("libshadow._libshadow", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
