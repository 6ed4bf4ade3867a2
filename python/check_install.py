# SPDX-License-Identifier: GPL-3.0-or-later
"""ctest python_install: `cmake --install` into a scratch prefix puts a libshadow that imports
from there (not from the build tree), finds its libshadow.so, and computes the default scene.
Usage: check_install.py BUILD_DIR PREFIX RELATIVE_SITE_PACKAGES SOURCE_DIR CMAKE"""
import os
import shutil
import subprocess
import sys

build, prefix, site, source, cmake = sys.argv[1:6]
shutil.rmtree(prefix, ignore_errors=True)
subprocess.run([cmake, "--install", build, "--prefix", prefix], check=True, stdout=subprocess.DEVNULL)
env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_LIBRARY_PATH")}
env["PYTHONPATH"] = os.path.join(prefix, site)
code = """
import os, sys, libshadow
assert libshadow.__file__.startswith(sys.argv[1]), libshadow.__file__
r = libshadow.compute_shadows(libshadow.load_scene(sys.argv[2]), polygons=False)
assert len(r) > 0 and 0 <= r.lit_fraction.min() and r.lit_fraction.max() <= 1
print("installed libshadow", libshadow.__version__, "at", os.path.dirname(libshadow.__file__))
"""
subprocess.run([sys.executable, "-c", code, prefix, os.path.join(source, "examples", "default", "scene.json")],
               check=True, env=env, cwd="/")
shutil.rmtree(prefix, ignore_errors=True)
