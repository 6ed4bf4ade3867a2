#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Renders a `shadow compute` result to a PNG with VTK: the fragments of one light, lit pieces
in warm light and shadowed pieces in blue-grey, the plane shadow outline, from a three-quarter
view. A quick look without ParaView; it needs Debian's python3-vtk9 and, headless, a virtual
display:

    xvfb-run -a /usr/bin/python3 tools/inspect/render_result.py OUTDIR image.png [--light 0]
"""
import argparse
import os
import sys

import vtk

from check_result import compute_output_problem


def read(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("outdir")
    parser.add_argument("png")
    parser.add_argument("--light", type=int, default=0)
    parser.add_argument("--size", type=int, nargs=2, default=[1200, 800])
    args = parser.parse_args()

    # One line for a folder that is not a compute output (a series' or irradiance run's, a typo),
    # not a traceback under VTK's own errors.
    problem = compute_output_problem(args.outdir, ["fragments.vtp", "lights.vtp"])
    if problem:
        sys.exit(f"render_result: {problem}")
    lights = read(os.path.join(args.outdir, "lights.vtp"))
    count = lights.GetNumberOfPoints()
    if not 0 <= args.light < count:
        sys.exit(f"render_result: --light {args.light}: {args.outdir} has {count} light(s), numbered 0 to {count - 1}")

    fragments = read(os.path.join(args.outdir, "fragments.vtp"))
    # Keep this light's fragments.
    select = vtk.vtkThreshold()
    select.SetInputData(fragments)
    select.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_CELLS, "light_id")
    select.SetLowerThreshold(args.light - 0.5)
    select.SetUpperThreshold(args.light + 0.5)
    select.SetThresholdFunction(vtk.vtkThreshold.THRESHOLD_BETWEEN)
    surface = vtk.vtkGeometryFilter()
    surface.SetInputConnection(select.GetOutputPort())

    colours = vtk.vtkLookupTable()
    colours.SetNumberOfTableValues(2)
    colours.SetTableValue(0, 0.30, 0.34, 0.45, 1.0)  # shadowed
    colours.SetTableValue(1, 0.98, 0.86, 0.62, 1.0)  # lit
    colours.SetTableRange(0, 1)
    colours.Build()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(surface.GetOutputPort())
    mapper.SetScalarModeToUseCellFieldData()
    mapper.SelectColorArray("lit")
    mapper.SetLookupTable(colours)
    mapper.SetScalarRange(0, 1)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetAmbient(0.55)
    actor.GetProperty().SetDiffuse(0.45)

    renderer = vtk.vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(1.0, 1.0, 1.0)
    # Look from the side the shadows fall to: above the scene, opposite the light.
    bounds = surface.GetOutput().GetBounds() if surface.GetOutput() else None
    surface.Update()
    bounds = surface.GetOutput().GetBounds()
    centre = [(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2, (bounds[4] + bounds[5]) / 2]
    size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
    to_light = lights.GetPointData().GetArray("to_light").GetTuple3(args.light)
    horizontal = [-to_light[0], -to_light[1]]
    norm = max((horizontal[0] ** 2 + horizontal[1] ** 2) ** 0.5, 1e-9)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(*centre)
    camera.SetPosition(centre[0] + 1.45 * size * horizontal[0] / norm - 0.45 * size * horizontal[1] / norm,
                       centre[1] + 1.45 * size * horizontal[1] / norm + 0.45 * size * horizontal[0] / norm,
                       centre[2] + 1.25 * size)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCameraClippingRange()

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(*args.size)
    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(args.png)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print("render_result: wrote", args.png)


if __name__ == "__main__":
    main()
