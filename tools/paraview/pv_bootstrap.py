# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs a ParaView Python script with ParaView's own modules first on sys.path.

Used by tools/paraview/pvpython.sh when python3-paraview is unpacked into a private prefix
(scripts/setup-pvpython.sh) rather than installed: pvpython then puts the system's
dist-packages, which hold python3-vtk9's different VTK, ahead of ParaView's own `vtkmodules`,
and importing paraview.simple crashes. Usage: pvpython pv_bootstrap.py SCRIPT.py [ARGS...]
"""
import os
import runpy
import sys

site = os.environ.get("LIBSHADOW_PVPYTHON_SITE")
if site:
    sys.path[:] = [site] + [entry for entry in sys.path if entry != site]

if len(sys.argv) < 2:
    print("pv_bootstrap: usage: pvpython pv_bootstrap.py SCRIPT.py [ARGS...]")
else:
    script = os.path.abspath(sys.argv[1])
    sys.argv = sys.argv[1:]
    sys.path.insert(1, os.path.dirname(script))
    runpy.run_path(script, run_name="__main__")
