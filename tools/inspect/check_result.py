#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks a `shadow compute` output directory from the outside, with VTK's own Python readers:
every file opens, points are Float64, scene.vtm has its named blocks, the fragments and
plane shadows add up to what report.json says, and the fragments' irradiance is I max(0, n.l)
(/ r^2 for point lights) where lit and 0 in shadow, recomputed from faces.vtp and lights.vtp.

    /usr/bin/python3 tools/inspect/check_result.py OUTDIR      # prints "check_result: ok" or the problems
"""
import json
import math
import os
import sys
from collections import defaultdict

import vtk


def values(array):
    """The values of a one-component VTK array as a list (no numpy: python3-vtk9 does not
    bring it)."""
    return [array.GetValue(i) for i in range(array.GetNumberOfTuples())]


def read_vtp(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        raise RuntimeError(f"{path}: VTK cannot read it")
    return reader.GetOutput()


def compute_output_problem(outdir, names):
    """Why `outdir` is not a `shadow compute` output directory (one line), or None."""
    if not os.path.isdir(outdir):
        return f"{outdir}: no such directory"
    missing = [n for n in names if not os.path.isfile(os.path.join(outdir, n))]
    if not missing:
        return None
    other = [n for n in ("sunlit.csv", "irradiation.csv", "radiosity.vtp") if os.path.isfile(os.path.join(outdir, n))]
    what = (f" (it holds {other[0]}: a `shadow series`, `irradiance` or `radiosity` output, which "
            "tools/paraview/open_result.py opens)") if other else ""
    return f"{outdir}: no {', '.join(missing)}: not a `shadow compute` output directory{what}"


def main(outdir):
    problem = compute_output_problem(
        outdir, ["report.json", "scene.vtm", "fragments.vtp", "faces.vtp", "plane_shadows.vtp", "lights.vtp"])
    if problem:
        print("check_result:", problem, file=sys.stderr)
        return 2
    problems = []

    def check(condition, message):
        if not condition:
            problems.append(message)

    with open(os.path.join(outdir, "report.json")) as f:
        report = json.load(f)

    datasets = {}
    for name in ("fragments", "faces", "plane_shadows", "lights"):
        data = read_vtp(os.path.join(outdir, name + ".vtp"))
        datasets[name] = data
        if data.GetNumberOfPoints() > 0:
            check(data.GetPoints().GetDataType() == vtk.VTK_DOUBLE, f"{name}.vtp: points are not Float64")

    reader = vtk.vtkXMLMultiBlockDataReader()
    reader.SetFileName(os.path.join(outdir, "scene.vtm"))
    reader.Update()
    blocks = reader.GetOutput()
    names = [blocks.GetMetaData(b).Get(vtk.vtkCompositeDataSet.NAME()) for b in range(blocks.GetNumberOfBlocks())]
    check(names == ["faces", "fragments", "plane_shadows", "lights"], f"scene.vtm blocks are {names}")

    # Fragments against the report: per face and light, cells add up to the face's area and the
    # lit cells to its lit area.
    fragments = datasets["fragments"]
    cells = fragments.GetCellData()
    face_id = values(cells.GetArray("face_id"))
    light_id = values(cells.GetArray("light_id"))
    lit = values(cells.GetArray("lit"))
    area = values(cells.GetArray("area"))
    total = defaultdict(float)
    lit_total = defaultdict(float)
    for f, l, is_lit, a in zip(face_id, light_id, lit, area):
        total[(int(f), int(l))] += a
        if is_lit:
            lit_total[(int(f), int(l))] += a
    entries = 0
    for face in report["faces"]:
        for entry in face["lights"]:
            key = (face["id"], entry["light"])
            entries += 1
            tolerance = 1e-12 * max(1.0, face["area"])
            check(math.isclose(total[key], face["area"], abs_tol=tolerance),
                  f"face {key}: fragments add up to {total[key]!r}, report says area {face['area']!r}")
            # An extended light's lit cells are its fully lit and penumbra cells; its lit_area is
            # that of its centre (docs/area-lights.md).
            lit_expected = (entry["fully_lit_area"] + entry["penumbra_area"] if "fully_lit_area" in entry
                            else entry["lit_area"])
            check(math.isclose(lit_total[key], lit_expected, abs_tol=tolerance),
                  f"face {key}: lit fragments add up to {lit_total[key]!r}, report says {lit_expected!r}")
    check(entries > 0, "report.json has no face entries")

    # Plane shadows against the report.
    plane = datasets["plane_shadows"].GetCellData()
    if datasets["plane_shadows"].GetNumberOfCells() > 0:
        by_pair = defaultdict(float)
        for p, l, a in zip(values(plane.GetArray("plane_id")), values(plane.GetArray("light_id")),
                           values(plane.GetArray("area"))):
            by_pair[(int(p), int(l))] += a
        for entry in report["planes"]:
            key = (entry["plane"], entry["light"])
            check(math.isclose(by_pair[key], entry["shadow_area"], rel_tol=1e-12, abs_tol=1e-12),
                  f"plane shadow {key}: cells add up to {by_pair[key]!r}, report says {entry['shadow_area']!r}")

    # Each fragment cell's own polygon, measured here from its Float64 points (Newell's formula),
    # has the area its `area` array claims.
    for c in range(fragments.GetNumberOfCells()):
        ids = fragments.GetCell(c).GetPointIds()
        pts = [fragments.GetPoint(ids.GetId(k)) for k in range(ids.GetNumberOfIds())]
        n = [0.0, 0.0, 0.0]
        for k, p in enumerate(pts):
            q = pts[(k + 1) % len(pts)]
            n[0] += (p[1] - q[1]) * (p[2] + q[2])
            n[1] += (p[2] - q[2]) * (p[0] + q[0])
            n[2] += (p[0] - q[0]) * (p[1] + q[1])
        measured = 0.5 * math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
        check(math.isclose(measured, area[c], rel_tol=1e-9, abs_tol=1e-9),
              f"fragment cell {c}: polygon area {measured!r}, area array says {area[c]!r}")

    # faces.vtp: every input face, its mesh name, and per light the report's lit fraction and area.
    faces = datasets["faces"]
    face_cells = faces.GetCellData()
    check(values(face_cells.GetArray("face_id")) == list(range(faces.GetNumberOfCells())),
          "faces.vtp: face_id is not 0, 1, 2, ... in cell order")
    mesh_names = face_cells.GetAbstractArray("mesh")

    def sanitize(name):
        return "".join(ch if ch.isalnum() or ch == "_" else "_" for ch in name)

    for face in report["faces"]:
        fid = face["id"]
        check(mesh_names.GetValue(fid) == face["mesh"], f"faces.vtp face {fid}: mesh {mesh_names.GetValue(fid)!r}, "
              f"report says {face['mesh']!r}")
        for entry in face["lights"]:
            name = sanitize(report["lights"][entry["light"]]["name"])
            for array, key in ((f"lit_fraction_{name}", "lit_fraction"), (f"lit_area_{name}", "lit_area")):
                data = face_cells.GetArray(array)
                if data is None:
                    check(False, f"faces.vtp: no cell array {array}")
                    continue
                check(data.GetValue(fid) == entry[key],
                      f"faces.vtp face {fid}: {array} = {data.GetValue(fid)!r}, report says {entry[key]!r}")

    # lights.vtp: point lights where the report puts them, directional lights along to_light.
    lights = datasets["lights"]
    check(lights.GetNumberOfPoints() == len(report["lights"]), "lights.vtp: one point per light")
    to_light = lights.GetPointData().GetArray("to_light")
    direction = lights.GetPointData().GetArray("direction")
    # VTK points are relative to report.json's "origin" when it has one (a city model far from 0).
    origin = report.get("origin", [0.0, 0.0, 0.0])
    for i, light in enumerate(report["lights"][:lights.GetNumberOfPoints()]):
        if light["type"] in ("area", "disk"):
            # Extended lights stand at their centre (a disk's position, an area light's centroid).
            if light["type"] == "disk":
                shifted = [p - o for p, o in zip(light["position"], origin)] if "origin" in report else light["position"]
                check(list(lights.GetPoint(i)) == shifted, f"lights.vtp: disk light {i} is not at its position")
        elif light["type"] == "point":
            shifted = [p - o for p, o in zip(light["position"], origin)] if "origin" in report else light["position"]
            check(list(lights.GetPoint(i)) == shifted, f"lights.vtp: light {i} is not at its position")
        else:
            d = light["to_light"]
            norm = math.sqrt(sum(x * x for x in d))
            got = to_light.GetTuple3(i)
            check(all(math.isclose(got[k], d[k] / norm, abs_tol=1e-12) for k in range(3)),
                  f"lights.vtp: light {i} to_light {got}, report says {d}")
            check(all(math.isclose(direction.GetTuple3(i)[k], -got[k], abs_tol=0) for k in range(3)),
                  f"lights.vtp: light {i} direction is not -to_light")

    # Irradiance, recomputed: the face's Newell normal, the light from lights.vtp.
    irradiance = fragments.GetPointData().GetArray("irradiance")
    check(irradiance is not None and irradiance.GetDataType() == vtk.VTK_DOUBLE,
          "fragments.vtp: no Float64 point array irradiance")
    if irradiance is not None and fragments.GetNumberOfCells() > 0:
        faces = datasets["faces"]
        lights = datasets["lights"]
        lpd = lights.GetPointData()

        def face_normal(f):
            ids = faces.GetCell(f).GetPointIds()
            pts = [faces.GetPoint(ids.GetId(i)) for i in range(ids.GetNumberOfIds())]
            n = [0.0, 0.0, 0.0]
            for i, a in enumerate(pts):
                b = pts[(i + 1) % len(pts)]
                n[0] += (a[1] - b[1]) * (a[2] + b[2])
                n[1] += (a[2] - b[2]) * (a[0] + b[0])
                n[2] += (a[0] - b[0]) * (a[1] + b[1])
            length = math.sqrt(sum(c * c for c in n))
            return [c / length for c in n]

        normals = {}
        worst = 0.0
        # Extended lights' irradiance integrates over the visible part of the light (not checked
        # here: docs/area-lights.md).
        extended = {i for i, light in enumerate(report["lights"])
                    if light["type"] in ("area", "disk") or light.get("angular_diameter", 0) > 0}
        for c in range(fragments.GetNumberOfCells()):
            f, l = int(face_id[c]), int(light_id[c])
            if l in extended:
                continue
            if f not in normals:
                normals[f] = face_normal(f)
            n = normals[f]
            point_light = lpd.GetArray("type").GetValue(l) == 1
            strength = lpd.GetArray("intensity").GetValue(l)
            ids = fragments.GetCell(c).GetPointIds()
            for i in range(ids.GetNumberOfIds()):
                pid = ids.GetId(i)
                p = fragments.GetPoint(pid)
                expected = 0.0
                if lit[c]:
                    if point_light:
                        q = lights.GetPoint(l)
                        d = [q[k] - p[k] for k in range(3)]
                        r2 = sum(x * x for x in d)
                        cosine = max(0.0, sum(n[k] * d[k] for k in range(3)) / math.sqrt(r2))
                        expected = strength * cosine / r2
                    else:
                        t = lpd.GetArray("to_light").GetTuple3(l)
                        expected = strength * max(0.0, sum(n[k] * t[k] for k in range(3)))
                got = irradiance.GetValue(pid)
                worst = max(worst, abs(got - expected) / max(1.0, abs(expected)))
        check(worst < 1e-9, f"fragments.vtp: irradiance differs from I max(0, n.l) [/ r^2] by up to {worst:.3g}")

    if problems:
        for p in problems[:20]:
            print("check_result:", p)
        print(f"check_result: failed ({len(problems)} problems)")
        return 1
    print(f"check_result: ok ({fragments.GetNumberOfCells()} fragments, {entries} face-light entries, "
          f"{len(report['planes'])} plane shadows)")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print("usage: check_result.py OUTDIR  (a `shadow compute` output directory)", file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
