# SPDX-License-Identifier: GPL-3.0-or-later
"""ctest python_pip: `pip install .` works offline on Debian 12 (no scikit-build-core, no PyPI):
pip --no-build-isolation --no-index --no-deps --target DIR builds a wheel with setuptools
(setup.py), which takes the module from this CMake build tree (LIBSHADOW_BUILD_DIR, so nothing is
compiled again) and bundles libshadow.so.N and libshadow_io.so.N beside it, with the module's RPATH $ORIGIN. The installed package imports from DIR,
loads the bundled libshadow.so (not the build tree's), and computes the default scene.
The packaging files are copied to a scratch source folder, so that pip's build leaves nothing in
the repository.
Usage: check_pip.py BUILD_DIR SOURCE_DIR SCRATCH"""
import os
import shutil
import subprocess
import sys

build, source, scratch = sys.argv[1:4]
shutil.rmtree(scratch, ignore_errors=True)
tree, target = os.path.join(scratch, "src"), os.path.join(scratch, "site")
for f in ("setup.py", "pyproject.toml", "README.md", "CMakeLists.txt", "python/libshadow/__init__.py"):
    os.makedirs(os.path.dirname(os.path.join(tree, f)), exist_ok=True)
    shutil.copyfile(os.path.join(source, f), os.path.join(tree, f))
env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_LIBRARY_PATH")}
env["LIBSHADOW_BUILD_DIR"] = build
env["PIP_NO_INPUT"] = "1"
subprocess.run([sys.executable, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps",
                "--no-cache-dir", "--disable-pip-version-check", "--target", target, tree],
               check=True, env=env, cwd=scratch)
installed = sorted(os.listdir(os.path.join(target, "libshadow")))
print("installed:", installed)
assert "__init__.py" in installed and any(n.startswith("_libshadow") for n in installed), installed
assert any(n.startswith("libshadow.so.") for n in installed), installed  # compute
assert any(n.startswith("libshadow_io.so.") for n in installed), installed  # io
module = [n for n in installed if n.startswith("_libshadow")][0]
dynamic = subprocess.run(["readelf", "-d", os.path.join(target, "libshadow", module)], capture_output=True,
                         text=True).stdout
assert "[$ORIGIN]" in dynamic and build not in dynamic, dynamic
env = {k: v for k, v in env.items() if k != "LIBSHADOW_BUILD_DIR"}
env["PYTHONPATH"] = target
code = """
import os, sys, libshadow
assert libshadow.__file__.startswith(sys.argv[1]), libshadow.__file__
r = libshadow.compute_shadows(libshadow.load_scene(sys.argv[2]), polygons=False)
assert len(r) > 0 and 0 <= r.lit_fraction.min() and r.lit_fraction.max() <= 1
# The shared libraries the module loaded are the ones pip put beside it.
maps = [line.split()[-1] for line in open("/proc/self/maps") if "libshadow.so" in line or "libshadow_io.so" in line]
assert any("libshadow_io.so" in m for m in maps) and any("libshadow.so" in m for m in maps), sorted(set(maps))
assert maps and all(m.startswith(os.path.realpath(sys.argv[1])) for m in maps), sorted(set(maps))
print("pip-installed libshadow", libshadow.__version__, "loads", sorted(set(maps))[0])
"""
subprocess.run([sys.executable, "-c", code, target, os.path.join(source, "examples", "default", "scene.json")],
               check=True, env=env, cwd="/")
shutil.rmtree(scratch, ignore_errors=True)
