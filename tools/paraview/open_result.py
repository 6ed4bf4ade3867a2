# SPDX-License-Identifier: GPL-3.0-or-later
"""Opens a `shadow compute` result in ParaView with sensible defaults.

Left view: the fragments of one light, lit and shadowed in two colours, with the plane shadows
and the lights (point lights as spheres, directional lights as arrows along the light).
Right view: the input faces coloured by their lit fraction for that light, with a legend.
When OUTDIR holds `sun_hours.vtp` (the exact sun-hours map of `shadow series`), one more view
colours it by `sun_hours` with a legend titled "sun hours", the other faces in grey around it;
a directory with the map and no `report.json` gets that view alone.

In the ParaView GUI: View > Python Shell > Run Script (edit OUTDIR below, or set the environment
variable LIBSHADOW_RESULT), or start it as `paraview --script=tools/paraview/open_result.py`.
Headless, to save a PNG:

    xvfb-run -a pvpython --force-offscreen-rendering tools/paraview/open_result.py OUTDIR \\
        --light 0 --screenshot result.png
"""
import argparse
import json
import math
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


def nice_step(span, most=7):
    """A round label step (1, 2 or 5 times a power of ten) giving at most `most` labels."""
    if span <= 0:
        return 1.0
    step = 10.0 ** math.floor(math.log10(span / most))
    for factor in (1, 2, 5, 10):
        if span / (factor * step) <= most - 1:
            return factor * step
    return 10 * step


def style_sun_hours(shown, source, view):
    """Colour the map by sun_hours from 0 to the period's total: one band per hour up to a day,
    labels at round hours, the legend titled "sun hours"."""
    ColorBy(shown, ("CELLS", "sun_hours"))
    lut = GetColorTransferFunction("sun_hours")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    total = None
    if "total_hours" in source.FieldData.keys():
        total = source.FieldData["total_hours"].GetRange()[0]
    if not total or total <= 0:
        total = max(source.CellData["sun_hours"].GetRange()[1], 1.0)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, total)
    whole = abs(total - round(total)) < 1e-9
    if whole and 1 <= round(total) <= 24:
        lut.Discretize = 1
        lut.NumberOfTableValues = int(round(total))  # one band per hour
    shown.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    style_bar(bar, "sun hours")
    step = nice_step(total)
    digits = 0 if whole and step >= 1 else 1
    bar.AutomaticLabelFormat = 0
    bar.LabelFormat = "%.{}f".format(digits)
    bar.RangeLabelFormat = "%.{}f".format(digits)
    bar.ScalarBarLength = 0.5
    bar.UseCustomLabels = 1
    bar.CustomLabels = [k * step for k in range(int(total / step + 1e-9) + 1)]
    bar.AddRangeLabels = 1


def show_sun_hours(outdir, view, read):
    """sun_hours.vtp coloured by its hours; faces.vtp (when present) in grey for context, less
    the mapped faces (same face ids) so that the two do not fight for the same pixels."""
    sun_hours = read("sun_hours.vtp")
    shown = Show(sun_hours, view)
    style_sun_hours(shown, sun_hours, view)
    if os.path.isfile(os.path.join(outdir, "faces.vtp")):
        faces = read("faces.vtp") if "faces.vtp" not in read.cache else read.cache["faces.vtp"]
        low, high = sun_hours.CellData["face_id"].GetRange()
        for method, value in (("Below Lower Threshold", low - 0.5), ("Above Upper Threshold", high + 0.5)):
            others = Threshold(registrationName="faces around the map (%s)" % method.split()[0].lower(), Input=faces)
            others.Scalars = ["CELLS", "face_id"]
            others.ThresholdMethod = method
            others.LowerThreshold = value
            others.UpperThreshold = value
            context = Show(others, view)
            context.ColorArrayName = ["POINTS", ""]
            context.DiffuseColor = [0.82, 0.82, 0.80]
    return sun_hours


def place_camera_above(view):
    """Above the scene from the south-south-west, looking down at 50 degrees."""
    ResetCamera(view)
    camera = view.GetActiveCamera()
    focal = camera.GetFocalPoint()
    distance = camera.GetDistance()
    camera.SetPosition(focal[0] - 0.25 * distance, focal[1] - 0.6 * distance, focal[2] + 0.75 * distance)
    camera.SetViewUp(0, 0, 1)
    view.ResetCamera(False)


def white_view(view):
    view.Background = [1.0, 1.0, 1.0]
    view.OrientationAxesVisibility = 0
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass


def finish(args, layout, views):
    for view in views:
        Render(view)
    if args.screenshot:
        SaveScreenshot(args.screenshot, layout, SaveAllViews=1, ImageResolution=args.size)
        if not os.path.isfile(args.screenshot) or os.path.getsize(args.screenshot) == 0:
            print("open_result: failed, no screenshot at " + args.screenshot)
            return
        print("open_result: ok, wrote " + args.screenshot)
    else:
        print("open_result: ok")


def main():
    args = parse_arguments()
    outdir = os.path.abspath(args.outdir)

    def read(name):
        reader = XMLPolyDataReader(registrationName=name, FileName=[os.path.join(outdir, name)])
        read.cache[name] = reader
        return reader

    read.cache = {}
    has_sun_hours = os.path.isfile(os.path.join(outdir, "sun_hours.vtp"))
    if has_sun_hours and not os.path.isfile(os.path.join(outdir, "report.json")):
        # A sun-hours map alone (e.g. from a series run that wrote no per-light result).
        layout = CreateLayout("libshadow sun hours")
        view = CreateView("RenderView")
        AssignViewToLayout(view=view, layout=layout, hint=0)
        white_view(view)
        show_sun_hours(outdir, view, read)
        place_camera_above(view)
        finish(args, layout, [view])
        return

    with open(os.path.join(outdir, "report.json")) as f:
        report = json.load(f)
    light_name = report["lights"][args.light]["name"]

    fragments = read("fragments.vtp")
    faces = read("faces.vtp")
    lights = read("lights.vtp")
    plane_shadows = read("plane_shadows.vtp")

    layout = CreateLayout("libshadow")
    left = CreateView("RenderView")
    right = CreateView("RenderView")
    if has_sun_hours:
        # Three views side by side: cells 1 | 5 | 6 of the layout's binary tree.
        layout.SplitHorizontal(0, 1.0 / 3.0)
        layout.SplitHorizontal(2, 0.5)
        layout.AssignView(1, left)
        layout.AssignView(5, right)
    else:
        AssignViewToLayout(view=left, layout=layout, hint=0)
        AssignViewToLayout(view=right, layout=layout, hint=0)
    for view in (left, right):
        white_view(view)

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
    views = [left, right]
    if has_sun_hours:
        # A third view: the exact sun-hours map.
        sun_view = CreateView("RenderView")
        layout.AssignView(6, sun_view)
        white_view(sun_view)
        show_sun_hours(outdir, sun_view, read)
        place_camera_above(sun_view)
        views.append(sun_view)
    finish(args, layout, views)


main()
