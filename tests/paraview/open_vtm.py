# SPDX-License-Identifier: GPL-3.0-or-later
"""Opens OUTDIR/scene.vtm the way a ParaView user does (File > Open: OpenDataFile) and checks
that ParaView sees the four named blocks, Float64 points and the arrays the docs promise.
Prints "open_vtm: ok" or "open_vtm: FAILED: ...". Usage: pvpython open_vtm.py OUTDIR"""
import os
import sys

from paraview import servermanager
from paraview.simple import OpenDataFile, UpdatePipeline

outdir = sys.argv[1]
problems = []
source = OpenDataFile(os.path.join(outdir, "scene.vtm"))
if source is None:
    problems.append("ParaView has no reader for scene.vtm")
else:
    UpdatePipeline(proxy=source)
    data = servermanager.Fetch(source)
    names = [data.GetMetaData(b).Get(data.NAME()) for b in range(data.GetNumberOfBlocks())]
    if names != ["faces", "fragments", "plane_shadows", "lights"]:
        problems.append(f"blocks {names}")
    expected = {"faces": ["face_id", "mesh", "area"], "fragments": ["face_id", "light_id", "lit", "area"],
                "plane_shadows": ["plane_id", "light_id", "area"]}
    for b, name in enumerate(names):
        block = data.GetBlock(b)
        if block.GetNumberOfPoints() > 0 and block.GetPoints().GetDataType() != 11:  # VTK_DOUBLE
            problems.append(f"block {name}: points are not Float64")
        cells = block.GetCellData()
        for array in expected.get(name, []):
            if cells.GetAbstractArray(array) is None:
                problems.append(f"block {name}: no cell array {array}")
        if name == "lights" and block.GetPointData().GetArray("direction") is None:
            problems.append("block lights: no point array direction")
print("open_vtm: ok" if not problems else "open_vtm: FAILED: " + "; ".join(problems))
