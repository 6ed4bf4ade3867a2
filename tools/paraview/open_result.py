# SPDX-License-Identifier: GPL-3.0-or-later
"""Opens a `shadow compute` result in ParaView with sensible defaults.

Left view: the fragments of one light, lit and shadowed in two colours, with the plane shadows
and the lights (point lights as spheres, directional lights as arrows along the light).
Right view: the input faces coloured by their lit fraction for that light, with a legend.

In the ParaView GUI: View > Python Shell > Run Script (edit OUTDIR below, or set the environment
variable LIBSHADOW_RESULT), or start it as `paraview --script=tools/paraview/open_result.py`.
Headless, to save a PNG:

    xvfb-run -a pvpython --force-offscreen-rendering tools/paraview/open_result.py OUTDIR \\
        --light 0 --screenshot result.png
"""
import argparse
import json
import os
import sys

from paraview.simple import (AssignViewToLayout, ColorBy, CreateLayout, CreateView,
                             GetColorTransferFunction, GetScalarBar, Glyph, Hide, Render,
                             ResetCamera, SaveScreenshot, Show, Threshold, XMLPolyDataReader)

OUTDIR = os.environ.get("LIBSHADOW_RESULT", "out/default")


def parse_arguments():
    parser = argparse.ArgumentParser(description="Open a libshadow result in ParaView")
    parser.add_argument("outdir", nargs="?", default=OUTDIR)
    parser.add_argument("--light", type=int, default=0, help="light whose shadows are shown")
    parser.add_argument("--screenshot", help="save the layout to this PNG and exit")
    parser.add_argument("--size", type=int, nargs=2, default=[1600, 700])
    # ParaView passes its own options to scripts run from the GUI: ignore what we do not know.
    args, _ = parser.parse_known_args(sys.argv[1:])
    return args


def sanitize(name):
    return "".join(c if c.isalnum() or c == "_" else "_" for c in name)


def style_bar(bar, title):
    """Dark text: the views have white backgrounds."""
    bar.Title = title
    bar.ComponentTitle = ""
    bar.TitleColor = [0.1, 0.1, 0.1]
    bar.LabelColor = [0.1, 0.1, 0.1]
    bar.TitleFontSize = 18
    bar.LabelFontSize = 16
    # The camera looks down on the scene, which fills the lower part of a view: keep the
    # legend out of it.
    bar.WindowLocation = "Upper Right Corner"


def place_camera(view, report, light):
    """Look at the scene from above, on the side its shadows fall to."""
    to_light = report["lights"][light].get("to_light")
    ResetCamera(view)
    camera = view.GetActiveCamera()
    focal = camera.GetFocalPoint()
    distance = camera.GetDistance()
    dx, dy = (-to_light[0], -to_light[1]) if to_light else (1.0, 1.0)
    norm = max((dx * dx + dy * dy) ** 0.5, 1e-9)
    dx, dy = dx / norm, dy / norm
    camera.SetPosition(focal[0] + 0.8 * distance * (dx - 0.3 * dy), focal[1] + 0.8 * distance * (dy + 0.3 * dx),
                       focal[2] + 0.7 * distance)
    camera.SetViewUp(0, 0, 1)
    view.ResetCamera(False)


def main():
    args = parse_arguments()
    outdir = os.path.abspath(args.outdir)
    with open(os.path.join(outdir, "report.json")) as f:
        report = json.load(f)
    light_name = report["lights"][args.light]["name"]

    def read(name):
        return XMLPolyDataReader(registrationName=name, FileName=[os.path.join(outdir, name)])

    fragments = read("fragments.vtp")
    faces = read("faces.vtp")
    lights = read("lights.vtp")
    plane_shadows = read("plane_shadows.vtp")

    layout = CreateLayout("libshadow")
    left = CreateView("RenderView")
    right = CreateView("RenderView")
    AssignViewToLayout(view=left, layout=layout, hint=0)
    AssignViewToLayout(view=right, layout=layout, hint=0)
    for view in (left, right):
        view.Background = [1.0, 1.0, 1.0]
        view.OrientationAxesVisibility = 0
        try:
            view.UseColorPaletteForBackground = 0
        except AttributeError:
            pass

    # Left: this light's fragments, lit or not.
    mine = Threshold(registrationName="fragments of " + light_name, Input=fragments)
    mine.Scalars = ["CELLS", "light_id"]
    mine.LowerThreshold = args.light
    mine.UpperThreshold = args.light
    shown = Show(mine, left)
    ColorBy(shown, ("CELLS", "lit"))
    lit = GetColorTransferFunction("lit")
    lit.InterpretValuesAsCategories = 1
    lit.Annotations = ["0", "shadowed", "1", "lit"]
    lit.IndexedColors = [0.30, 0.34, 0.45, 0.98, 0.86, 0.62]
    shown.SetScalarBarVisibility(left, True)
    style_bar(GetScalarBar(lit, left), light_name)

    plane_mine = Threshold(registrationName="plane shadows of " + light_name, Input=plane_shadows)
    plane_mine.Scalars = ["CELLS", "light_id"]
    plane_mine.LowerThreshold = args.light
    plane_mine.UpperThreshold = args.light
    plane_shown = Show(plane_mine, left)
    plane_shown.ColorArrayName = ["POINTS", ""]
    plane_shown.DiffuseColor = [0.55, 0.1, 0.1]
    Hide(plane_mine, left)  # loaded, one click away in the Pipeline Browser

    # Lights: arrows along the light's travel for directional lights, spheres for point lights.
    size = report.get("summary", {}).get("total_area", 100.0) ** 0.5 / 10.0
    arrows = Glyph(registrationName="lights", Input=lights, GlyphType="Arrow")
    arrows.OrientationArray = ["POINTS", "direction"]
    arrows.ScaleArray = ["POINTS", "No scale array"]
    arrows.ScaleFactor = 3 * size
    arrows_shown = Show(arrows, left)
    arrows_shown.ColorArrayName = ["POINTS", ""]
    arrows_shown.DiffuseColor = [0.9, 0.6, 0.0]

    # Right: faces by lit fraction, with a legend.
    faces_shown = Show(faces, right)
    array = "lit_fraction_" + sanitize(light_name)
    ColorBy(faces_shown, ("CELLS", array))
    fraction = GetColorTransferFunction(array)
    fraction.ApplyPreset("Inferno (matplotlib)", True)
    fraction.RescaleTransferFunction(0.0, 1.0)
    faces_shown.SetScalarBarVisibility(right, True)
    style_bar(GetScalarBar(fraction, right), "lit fraction, " + light_name)

    for view in (left, right):
        place_camera(view, report, args.light)
    Render(left)
    Render(right)
    if args.screenshot:
        SaveScreenshot(args.screenshot, layout, SaveAllViews=1, ImageResolution=args.size)
        if not os.path.isfile(args.screenshot) or os.path.getsize(args.screenshot) == 0:
            print("open_result: failed, no screenshot at " + args.screenshot)
            return
        print("open_result: ok, wrote " + args.screenshot)
    else:
        print("open_result: ok")


main()
