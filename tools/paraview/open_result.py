# SPDX-License-Identifier: GPL-3.0-or-later
"""Opens a result of the `shadow` command line in ParaView with sensible defaults: any OUTDIR it
writes (`shadow compute`, with point, directional or area lights; `shadow series`, with or
without the sun-hours map; a sun-hours map alone).

Left view: the fragments of one light, lit and shadowed in two colours (for an extended light,
coloured by the visible fraction of the light at each point, 0 to 1, with a legend), with the
plane shadows and the lights (point lights as spheres, directional lights as arrows along the light).
Right view: the input faces coloured by their lit fraction for that light, with a legend.
When OUTDIR holds `sun_hours.vtp` (the exact sun-hours map of `shadow series`), one more view
colours it by `sun_hours` with a legend titled "sun hours", the other faces in grey around it;
a directory with the map and no `report.json` gets that view alone.

A `shadow series` result (report.json with `series`, no `lights`): the faces coloured by their
`sun_hours` over the period (legend "sun hours"; faces that receive no light in grey), beside
`series.pvd` as an animation coloured by `lit_fraction` (press Play; the screenshot shows the
middle instant) when the run wrote it, and the sun-hours map when there is one.

A `shadow irradiance` result (report.json with kind "irradiance", or irradiation.csv or
irradiation_map.vtp beside faces.vtp): the faces coloured by their total irradiation over the
period (`irradiation_total_kwh_m2`, legend "kWh/m²"; faces that receive nothing in grey), beside
irradiation_map.vtp on the same scale when the run wrote one (`--map`).

A `shadow radiosity` result (report.json with kind "radiosity", radiosity.vtp): the elements
coloured by their radiosity (legend "W/m²"), backs culled so that a room shows its inside
(open_radiosity.py, beside this script).

In the ParaView GUI: View > Python Shell > Run Script (edit OUTDIR below, or set the environment
variable LIBSHADOW_RESULT), or start it as `paraview --script=tools/paraview/open_result.py`.
Headless, to save a PNG:

    xvfb-run -a pvpython --force-offscreen-rendering tools/paraview/open_result.py OUTDIR \\
        --light 0 --screenshot result.png
"""
import argparse
import builtins  # a ProgrammableSource's script replaces max, min, sum... in this namespace
import json
import math
import os
import sys
import types

from paraview.simple import (AssignViewToLayout, ColorBy, CreateLayout, CreateView, GetAnimationScene,
                             GetColorTransferFunction, GetScalarBar, Glyph, Hide, ProgrammableSource,
                             PVDReader, Render, SaveScreenshot, Show, Text, Threshold, XMLPolyDataReader)

OUTDIR = os.environ.get("LIBSHADOW_RESULT", "out/default")


def parse_arguments():
    parser = argparse.ArgumentParser(description="Open a libshadow result in ParaView")
    parser.add_argument("outdir", nargs="?", default=OUTDIR)
    parser.add_argument("--light", type=int, default=0, help="light whose shadows are shown")
    parser.add_argument("--screenshot", help="save the layout to this PNG and exit")
    parser.add_argument("--size", type=int, nargs=2, default=[1600, 700])
    parser.add_argument("--describe", help="write the views' layout (model on screen, colour bars, light "
                                           "glyphs) to this JSON file, for tests")
    # ParaView passes its own options to scripts run from the GUI: ignore what we do not know.
    args, _ = parser.parse_known_args(sys.argv[1:])
    return args


def sanitize(name):
    return "".join(c if c.isalnum() or c == "_" else "_" for c in name)


# The model is framed in the left part of each view (frame_model); the colour bars stand in the
# strip on the right, clear of it.
MODEL_SHARE = 0.74
BAR_POSITION = [0.86, 0.1]
BAR_LENGTH = 0.66
VIEW_ASPECT = [1.6]  # width / height of each view, set by main from --size
VIEW_WIDTH = [800]   # pixels
LABEL_ROOM = 100     # pixels left of a bar for its labels
TITLE_ROOM = 66      # pixels right of a bar's left edge: half a short title, centred on the bar
TOP_ROOM = 0.12      # the part of a titled view's height kept clear of the model for its title
TITLED = {}          # view -> its title's lines (add_title), for frame_model and describe
NORTH = {}           # view -> the north arrow's direction (add_north_arrow), for describe
IS_SERIES = [False]  # set by open_series, for describe


def bar_position():
    """The bar's lower left corner: far enough from the right edge for its title."""
    return [builtins.min(BAR_POSITION[0], 1.0 - TITLE_ROOM / VIEW_WIDTH[0]), BAR_POSITION[1]]


def model_share():
    """The part of a view's width left to the model: up to the bar's labels."""
    return builtins.min(MODEL_SHARE, bar_position()[0] - LABEL_ROOM / VIEW_WIDTH[0])


def style_bar(bar, title, digits=None, labels=None, annotations_left=False):
    """Dark text on the white views, the bar upright in the strip right of the model; with
    `digits`, fixed-point labels (not ParaView's default 1.0e+00), at `labels` if given."""
    bar.Title = title
    bar.ComponentTitle = ""
    bar.TitleColor = [0.1, 0.1, 0.1]
    bar.LabelColor = [0.1, 0.1, 0.1]
    bar.TitleFontSize = 16
    bar.LabelFontSize = 14
    bar.WindowLocation = "Any Location"
    bar.Orientation = "Vertical"

    bar.ScalarBarLength = BAR_LENGTH
    bar.HorizontalTitle = 1
    bar.Position = bar_position()
    # Labels toward the model's side, inside the view.
    bar.TextPosition = ("Ticks right/top, annotations left/bottom" if annotations_left
                        else "Ticks left/bottom, annotations right/top")
    if digits is not None:
        bar.AutomaticLabelFormat = 0
        bar.LabelFormat = "%.{}f".format(digits)
        bar.RangeLabelFormat = "%.{}f".format(digits)
    if labels is not None:
        bar.UseCustomLabels = 1
        bar.CustomLabels = labels
        bar.AddRangeLabels = 0


def model_bounds(source):
    """The bounds of a reader's data: the model, not the light glyphs."""
    source.UpdatePipeline()
    return list(source.GetDataInformation().GetBounds())


def reset_to(view, bounds, share=1.0, height_share=0.95):
    """Look at the centre of `bounds` from where the camera looks now, at the distance where
    their bounding sphere fits `share` of the view's width and 95% of its height (the view's
    own reset takes every visible thing, light glyphs included, and an aspect the offscreen
    view may not have yet)."""
    camera = view.GetActiveCamera()
    centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    radius = builtins.max(0.5 * builtins.sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)) ** 0.5,
                          1e-9)
    position, focal = camera.GetPosition(), camera.GetFocalPoint()
    away = [p - f for p, f in zip(position, focal)]
    length = builtins.sum(c * c for c in away) ** 0.5
    away = [c / length for c in away] if length > 0 else [0.0, -0.6, 0.8]
    half_v = math.radians(camera.GetViewAngle()) / 2
    half_h = math.atan(math.tan(half_v) * VIEW_ASPECT[0] * share)
    half = builtins.min(math.atan(math.tan(half_v) * height_share), half_h)
    distance = radius / math.sin(half)
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*[c + distance * a for c, a in zip(centre, away)])
    view.CenterOfRotation = centre


def frame_model(view, bounds):
    """Fit the model's bounding sphere into the left MODEL_SHARE of the view, leaving the right
    strip to the colour bar."""
    camera = view.GetActiveCamera()
    share = model_share()
    # A titled view keeps its top band for the title: the model fits below it.
    top = TOP_ROOM if view in TITLED else 0.0
    reset_to(view, bounds, share, 0.95 - top)
    aspect = VIEW_ASPECT[0]
    distance = camera.GetDistance()
    visible_height = 2 * distance * math.tan(math.radians(camera.GetViewAngle()) / 2)
    visible_width = visible_height * aspect
    shift = (0.5 - share / 2) * visible_width
    position, focal, up = camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp()
    view_dir = [f - p for f, p in zip(focal, position)]
    right = [view_dir[1] * up[2] - view_dir[2] * up[1], view_dir[2] * up[0] - view_dir[0] * up[2],
             view_dir[0] * up[1] - view_dir[1] * up[0]]
    norm = builtins.max(builtins.sum(c * c for c in right) ** 0.5, 1e-300)
    right = [c / norm for c in right]
    # The screen's up: right x view direction, unit length.
    screen_up = [right[1] * view_dir[2] - right[2] * view_dir[1], right[2] * view_dir[0] - right[0] * view_dir[2],
                 right[0] * view_dir[1] - right[1] * view_dir[0]]
    norm = builtins.max(builtins.sum(c * c for c in screen_up) ** 0.5, 1e-300)
    lift = 0.5 * top * visible_height  # the camera up, so the model moves down below the title
    move = [shift * r + lift * u / norm for r, u in zip(right, screen_up)]
    camera.SetPosition(*[p + m for p, m in zip(position, move)])
    camera.SetFocalPoint(*[f + m for f, m in zip(focal, move)])


def place_camera(view, report, light, bounds):
    """Look at the model from above, on the side its shadows fall to."""
    to_light = report["lights"][light].get("to_light")
    reset_to(view, bounds)
    camera = view.GetActiveCamera()
    focal = camera.GetFocalPoint()
    distance = camera.GetDistance()
    dx, dy = (-to_light[0], -to_light[1]) if to_light else (1.0, 1.0)
    norm = builtins.max((dx * dx + dy * dy) ** 0.5, 1e-9)
    dx, dy = dx / norm, dy / norm
    camera.SetPosition(focal[0] + 0.8 * distance * (dx - 0.3 * dy), focal[1] + 0.8 * distance * (dy + 0.3 * dx),
                       focal[2] + 0.7 * distance)
    camera.SetViewUp(0, 0, 1)
    frame_model(view, bounds)


def nice_step(span, most=7):
    """A round label step (1, 2 or 5 times a power of ten) giving at most `most` labels."""
    if span <= 0:
        return 1.0
    step = 10.0 ** math.floor(math.log10(span / most))
    for factor in (1, 2, 5, 10):
        if span / (factor * step) <= most - 1:
            return factor * step
    return 10 * step


def unlit(shown):
    """Draw `shown` in its legend's colours: no headlight shading, which would darken faces seen
    at a slant until their colour read as another value (a south wall of 925 kWh/m2 as about 200)."""
    shown.Ambient = 1.0
    shown.Diffuse = 0.0


def style_sun_hours(shown, source, view, total=None):
    """Colour the map by sun_hours from 0 to the period's total (`total`, else the map's
    `total_hours`): one band per hour up to a day, labels at round hours, the legend titled
    "sun hours"; unlit, so that a colour is its value."""
    unlit(shown)
    ColorBy(shown, ("CELLS", "sun_hours"))
    lut = GetColorTransferFunction("sun_hours")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    lut.NanColor = [0.82, 0.82, 0.80]  # faces that receive no light (series faces.vtp)
    if not total and "total_hours" in source.FieldData.keys():
        total = source.FieldData["total_hours"].GetRange()[0]
    if not total or total <= 0:
        total = builtins.max(source.CellData["sun_hours"].GetRange()[1], 1.0)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, total)
    whole = builtins.abs(total - builtins.round(total)) < 1e-9
    if whole and 1 <= builtins.round(total) <= 24:
        lut.Discretize = 1
        lut.NumberOfTableValues = int(builtins.round(total))  # one band per hour
    shown.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    style_bar(bar, "sun hours")
    step = nice_step(total)
    digits = 0 if whole and step >= 1 else 1
    bar.AutomaticLabelFormat = 0
    bar.LabelFormat = "%.{}f".format(digits)
    bar.RangeLabelFormat = "%.{}f".format(digits)
    bar.UseCustomLabels = 1
    bar.CustomLabels = [k * step for k in range(int(total / step + 1e-9) + 1)]
    bar.AddRangeLabels = 1


def show_sun_hours(outdir, view, read, total=None):
    """sun_hours.vtp coloured by its hours; faces.vtp (when present) in grey for context, less
    the mapped faces (same face ids) so that the two do not fight for the same pixels."""
    sun_hours = read("sun_hours.vtp")
    shown = Show(sun_hours, view)
    style_sun_hours(shown, sun_hours, view, total)
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


def period_of(series):
    """The period of a series, as report.json states it (its first and last instants), short
    enough for the title: lines "2026-06-21 03:00 to 18:00 (UTC)" and "16 instants"."""
    first = str(series.get("first") or series.get("start") or "")
    last = str(series.get("last") or series.get("end") or "")

    def split(t):
        date, _, time = t.partition("T")
        zone = ""
        for mark in ("Z", "+", "-"):
            at = time.find(mark)
            if at >= 0:
                time, zone = time[:at], time[at:]
                break
        return date, time[:5], "UTC" if zone == "Z" else zone

    lines = []
    if first and last:
        (d0, t0, z0), (d1, t1, z1) = split(first), split(last)
        zone = " (%s)" % z0 if z0 and z0 == z1 else ""
        if d0 == d1:
            lines.append("%s %s to %s%s" % (d0, t0, t1, zone))
        else:
            lines.append("%s %s to %s %s%s" % (d0, t0, d1, t1, zone))
    if series.get("instants"):
        lines.append("%d instants" % series["instants"])
    return lines or ["period not recorded"]


def add_title(view, lines):
    """A title, top left, in the band frame_model keeps clear of the model."""
    TITLED[view] = list(lines)
    text = Text(registrationName="title", Text="\n".join(lines))
    shown = Show(text, view)
    shown.WindowLocation = "Upper Left Corner"
    shown.Justification = "Left"
    shown.FontSize = 12
    shown.Color = [0.1, 0.1, 0.1]
    return text


# Arrows as glyphs: `glyphs` is a list of (position, direction) pairs (the lights, the north arrow).
ARROWS_SCRIPT = """
import vtk
points = vtk.vtkPoints()
direction = vtk.vtkDoubleArray()
direction.SetName("direction")
direction.SetNumberOfComponents(3)
verts = vtk.vtkCellArray()
for position, toward in {glyphs}:
    verts.InsertNextCell(1)
    verts.InsertCellPoint(points.InsertNextPoint(*position))
    direction.InsertNextTuple3(*toward)
output = self.GetPolyDataOutput()
output.SetPoints(points)
output.SetVerts(verts)
output.GetPointData().AddArray(direction)
"""


def add_north_arrow(view, bounds, north_axis=0.0):
    """A dark arrow on the ground at the model's south-west corner, pointing to true north (the
    model's y axis turned by `north_axis` degrees, as docs/sun.md says), a fifth of the model's
    size long."""
    a = math.radians(north_axis or 0.0)
    north = [-math.sin(a), math.cos(a), 0.0]
    size = builtins.max(bounds[1] - bounds[0], bounds[3] - bounds[2], 1e-9)
    tail = [bounds[0] + 0.05 * size, bounds[2] + 0.05 * size, bounds[4]]
    source = ProgrammableSource(registrationName="north")
    source.OutputDataSetType = "vtkPolyData"
    source.Script = ARROWS_SCRIPT.format(glyphs=repr([(tail, north)]))
    arrow = Glyph(registrationName="north arrow", Input=source, GlyphType="Arrow")
    arrow.OrientationArray = ["POINTS", "direction"]
    arrow.ScaleArray = ["POINTS", "No scale array"]
    arrow.ScaleFactor = 0.2 * size
    shown = Show(arrow, view)
    shown.ColorArrayName = ["POINTS", ""]
    shown.DiffuseColor = [0.1, 0.1, 0.1]
    NORTH[view] = north
    return arrow


def place_camera_above(view, bounds):
    """Above the model from the south-south-west, looking down at 50 degrees."""
    reset_to(view, bounds)
    camera = view.GetActiveCamera()
    focal = camera.GetFocalPoint()
    distance = camera.GetDistance()
    camera.SetPosition(focal[0] - 0.25 * distance, focal[1] - 0.6 * distance, focal[2] + 0.75 * distance)
    camera.SetViewUp(0, 0, 1)
    frame_model(view, bounds)




def is_extended(light):
    """An area or disk light, or a sun with an angular diameter (report.json's light entry)."""
    return light.get("type") in ("area", "disk") or (light.get("angular_diameter") or 0) > 0


def has_point_array(source, name):
    """Whether a reader's output has the point array `name` (fragments.vtp has `visibility`
    only for scenes with an extended light)."""
    source.UpdatePipeline()
    return source.PointData.GetArray(name) is not None


def light_glyphs(report, centre, radius):
    """(tail, direction) of each light's arrow: a directional light's arrow starts on the
    model's bounding sphere (centre, radius), inside the framed view, and points at its centre,
    along the light's travel; a point or area light's arrow starts at the light, pointing at the centre."""
    origin = report.get("origin", [0.0, 0.0, 0.0])
    glyphs = []
    for light in report["lights"]:
        if light.get("to_light"):
            t = light["to_light"]
            n = builtins.max(builtins.sum(c * c for c in t) ** 0.5, 1e-300)
            u = [c / n for c in t]
            tail = [c + radius * k for c, k in zip(centre, u)]
            glyphs.append((tail, [-k for k in u]))
            continue
        if light.get("position"):
            where = light["position"]
        elif light.get("polygon"):
            where = [builtins.sum(p[i] for p in light["polygon"]) / len(light["polygon"]) for i in range(3)]
        else:
            continue
        tail = [w - o for w, o in zip(where, origin)]
        toward = [c - w for c, w in zip(centre, tail)]
        n = builtins.max(builtins.sum(c * c for c in toward) ** 0.5, 1e-300)
        glyphs.append((tail, [c / n for c in toward]))
    return glyphs


def describe(path, views, bounds, glyphs, size):
    """The model's box on screen, each colour bar and the light glyphs, as JSON (for tests)."""
    corners = [[bounds[i], bounds[2 + j], bounds[4 + k]] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    out = {"bounds": bounds, "glyphs": glyphs, "views": [], "series": IS_SERIES[0]}
    for name, view, (width, height) in views:
        camera = view.GetActiveCamera()
        matrix = camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1)
        xs, ys = [], []
        for c in corners:
            h = [builtins.sum(matrix.GetElement(r, k) * v for k, v in enumerate(c + [1.0])) for r in range(4)]
            xs.append(0.5 * (h[0] / h[3] + 1))
            ys.append(0.5 * (h[1] / h[3] + 1))
        bars = []
        seen = set()  # several representations may share one colour map, hence one bar
        for rep in view.Representations:
            try:
                if not rep.Visibility or not rep.ColorArrayName or not rep.ColorArrayName[1]:
                    continue
            except AttributeError:
                continue
            if rep.ColorArrayName[1] in seen:
                continue
            seen.add(rep.ColorArrayName[1])
            lut = GetColorTransferFunction(rep.ColorArrayName[1])
            bar = GetScalarBar(lut, view)
            if not bar.Visibility:
                continue
            bars.append({"title": str(bar.Title), "label_format": str(bar.LabelFormat),
                         "range_label_format": str(bar.RangeLabelFormat),
                         "automatic_label_format": int(bar.AutomaticLabelFormat),
                         "custom_labels": list(bar.CustomLabels) if bar.UseCustomLabels else [],
                         "position": list(bar.Position), "length": bar.ScalarBarLength,
                         "categorical": bool(lut.InterpretValuesAsCategories),
                         "range": [lut.RGBPoints[0], lut.RGBPoints[-4]] if len(lut.RGBPoints) >= 4 else [0, 0],
                         "thickness": bar.ScalarBarThickness, "orientation": str(bar.Orientation),
                         "view_size": [width, height]})
        out["views"].append({"name": name, "model_box": [builtins.min(xs), builtins.max(xs), builtins.min(ys), builtins.max(ys)], "bars": bars,
                             "title": TITLED.get(view, []), "top_room": TOP_ROOM if view in TITLED else 0.0,
                             "north": NORTH.get(view)})
    with open(path, "w") as f:
        json.dump(out, f, indent=1)


def white_view(view):
    view.Background = [1.0, 1.0, 1.0]
    view.OrientationAxesVisibility = 0
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass


def finish(args, layout, views, described=None):
    for view in views:
        Render(view)
    if args.describe and described is not None:
        bounds, glyphs = described
        width = args.size[0] / len(views)
        describe(args.describe, [("view %d" % i, v, (width, args.size[1])) for i, v in enumerate(views)], bounds,
                 glyphs, args.size)
    if args.screenshot:
        SaveScreenshot(args.screenshot, layout, SaveAllViews=1, ImageResolution=args.size)
        if not os.path.isfile(args.screenshot) or os.path.getsize(args.screenshot) == 0:
            print("open_result: failed, no screenshot at " + args.screenshot)
            return
        print("open_result: ok, wrote " + args.screenshot)
    else:
        print("open_result: ok")


def arrange(layout, views):
    """One, two or three views side by side, equal widths."""
    if len(views) == 3:
        # Cells 1 | 5 | 6 of the layout's binary tree.
        layout.SplitHorizontal(0, 1.0 / 3.0)
        layout.SplitHorizontal(2, 0.5)
        for cell, view in zip((1, 5, 6), views):
            layout.AssignView(cell, view)
    else:
        for view in views:
            AssignViewToLayout(view=view, layout=layout, hint=0)


def open_series(args, outdir, report, read):
    """A `shadow series` OUTDIR: faces by sun hours, series.pvd by lit fraction (an animation),
    and the sun-hours map when the run made one."""
    series = report["series"]
    IS_SERIES[0] = True
    has_pvd = os.path.isfile(os.path.join(outdir, "series.pvd"))
    has_map = os.path.isfile(os.path.join(outdir, "sun_hours.vtp"))
    count = 1 + has_pvd + has_map
    VIEW_ASPECT[0] = args.size[0] / count / args.size[1]
    VIEW_WIDTH[0] = args.size[0] / count
    # The most sun a face can get over the period: every instant above the horizon, fully lit.
    total = series.get("above_horizon", 0) * series.get("hours_per_instant", 1.0)
    layout = CreateLayout("libshadow series")
    views = [CreateView("RenderView") for _ in range(count)]
    arrange(layout, views)
    for view in views:
        white_view(view)

    faces = read("faces.vtp")
    bounds = model_bounds(faces)
    style_sun_hours(Show(faces, views[0]), faces, views[0], total)
    # What the colours are, over which period, and which way is north.
    period = period_of(series)
    north_axis = series.get("north_axis", 0.0)
    add_title(views[0], ["sun hours per face"] + period)
    add_north_arrow(views[0], bounds, north_axis)
    next_view = 1
    if has_pvd:
        # The instants as a ParaView time series: Play runs through the period.
        instants = PVDReader(registrationName="series.pvd", FileName=os.path.join(outdir, "series.pvd"))
        instants.UpdatePipelineInformation()
        times = list(instants.TimestepValues) if instants.TimestepValues else []
        animation = GetAnimationScene()
        animation.UpdateAnimationUsingDataTimeSteps()
        if times:
            animation.AnimationTime = times[len(times) // 2]
        view = views[next_view]
        next_view += 1
        shown = Show(instants, view)
        unlit(shown)
        ColorBy(shown, ("CELLS", "lit_fraction"))
        fraction = GetColorTransferFunction("lit_fraction")
        fraction.ApplyPreset("Inferno (matplotlib)", True)
        fraction.RescaleTransferFunction(0.0, 1.0)
        fraction.AutomaticRescaleRangeMode = "Never"
        fraction.NanColor = [0.82, 0.82, 0.80]
        shown.SetScalarBarVisibility(view, True)
        style_bar(GetScalarBar(fraction, view), "lit fraction", digits=2, labels=[0.0, 0.25, 0.5, 0.75, 1.0])
    if has_map:
        show_sun_hours(outdir, views[next_view], read, total)
        add_title(views[next_view], ["sun hours (exact map)"] + period)
        add_north_arrow(views[next_view], bounds, north_axis)
    for view in views:
        Render(view)  # ParaView resets the camera on a view's first render: get that done first
        place_camera_above(view, bounds)
    finish(args, layout, views, (bounds, []))


IRRADIATION = "irradiation_total_kwh_m2"
IRRADIATION_TITLE = "kWh/m\u00b2"  # the legend: total irradiation over the run's period


def irradiation_top(sources):
    """The top of the legend: the largest total over the datasets, rounded up to a label step."""
    top = 0.0
    for source in sources:
        low, high = source.CellData[IRRADIATION].GetRange()
        if high == high:  # NaN (no face receives) leaves the range at 0
            top = builtins.max(top, high)
    if top <= 0:
        return 1.0, 1.0
    step = nice_step(top)
    return step * math.ceil(top / step - 1e-9), step


def style_irradiation(shown, view, top, step, bar=True):
    """Colour by the total irradiation from 0 to `top` kWh/m2 (Inferno; faces that receive no
    light, NaN in faces.vtp, in grey), the legend titled with the unit, labels at round values;
    unlit, so that a colour is its value."""
    unlit(shown)
    ColorBy(shown, ("CELLS", IRRADIATION))
    lut = GetColorTransferFunction(IRRADIATION)
    lut.ApplyPreset("Inferno (matplotlib)", True)
    lut.NanColor = [0.82, 0.82, 0.80]
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, top)
    if not bar:
        return  # context around the map: the map's bar already reads the scale
    shown.SetScalarBarVisibility(view, True)
    digits = 0 if step >= 1 else builtins.min(3, int(math.ceil(-math.log10(step))))
    style_bar(GetScalarBar(lut, view), IRRADIATION_TITLE, digits=digits,
              labels=[k * step for k in range(int(top / step + 1e-9) + 1)])


def irradiance_period(run):
    """The period of an irradiance run, from report.json's `run`: "FROM to TO (N hours)" and the sky."""
    period = run.get("period", {})
    lines = []
    if period.get("from") or period.get("to"):
        lines.append("%s to %s" % (period.get("from") or "start", period.get("to") or "end"))
    if period.get("hours") is not None:
        lines.append("%d hours of weather, %s sky" % (period["hours"], run.get("sky", "?")))
    return lines or ["period: see report.json"]


def is_irradiance(outdir, report):
    """An OUTDIR of `shadow irradiance`: its report says so (kind), or its files do (faces.vtp with
    irradiation arrays beside irradiation.csv, or irradiation_map.vtp) when the report is missing."""
    if report is not None:
        return report.get("kind") == "irradiance"
    return (os.path.isfile(os.path.join(outdir, "irradiation_map.vtp")) or
            os.path.isfile(os.path.join(outdir, "irradiation.csv")))


def open_irradiance(args, outdir, report, read):
    """A `shadow irradiance` OUTDIR: the faces coloured by their total irradiation over the
    period (kWh/m2), and the irradiation map (cells cut along the beam's shadows) when the run
    wrote one, both on one scale."""
    run = (report or {}).get("run", {})
    has_faces = os.path.isfile(os.path.join(outdir, "faces.vtp"))
    has_map = os.path.isfile(os.path.join(outdir, "irradiation_map.vtp"))
    sources = ([("faces.vtp", "total irradiation per face")] if has_faces else []) + \
              ([("irradiation_map.vtp", "total irradiation (map)")] if has_map else [])
    if not sources:
        print("open_result: %s: an irradiance result without faces.vtp or irradiation_map.vtp" % outdir)
        sys.exit(2)
    count = len(sources)
    VIEW_ASPECT[0] = args.size[0] / count / args.size[1]
    VIEW_WIDTH[0] = args.size[0] / count
    layout = CreateLayout("libshadow irradiance")
    views = [CreateView("RenderView") for _ in range(count)]
    arrange(layout, views)
    readers = [read(name) for name, _ in sources]
    top, step = irradiation_top(readers)
    bounds = model_bounds(readers[0])
    period = irradiance_period(run)
    for view, reader, (name, title) in zip(views, readers, sources):
        white_view(view)
        style_irradiation(Show(reader, view), view, top, step)
        if name == "irradiation_map.vtp" and has_faces:
            # The faces the map does not cover, on the same scale (their own value), around it.
            low, high = reader.CellData["face_id"].GetRange()
            for method, value in (("Below Lower Threshold", low - 0.5), ("Above Upper Threshold", high + 0.5)):
                others = Threshold(registrationName="faces around the map (%s)" % method.split()[0].lower(),
                                   Input=readers[0])
                others.Scalars = ["CELLS", "face_id"]
                others.ThresholdMethod = method
                others.LowerThreshold = value
                others.UpperThreshold = value
                style_irradiation(Show(others, view), view, top, step, bar=False)
        add_title(view, [title] + period)
        add_north_arrow(view, bounds, run.get("north_axis", 0.0))
    for view in views:
        Render(view)  # ParaView resets the camera on a view's first render: get that done first
        place_camera_above(view, bounds)
    finish(args, layout, views, (bounds, []))


def main():
    args = parse_arguments()
    try:  # open_radiosity.py beside this script (the GUI's Run Script does not put it on the path)
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    except NameError:
        pass
    import open_radiosity
    outdir = os.path.abspath(args.outdir)

    def read(name):
        reader = XMLPolyDataReader(registrationName=name, FileName=[os.path.join(outdir, name)])
        read.cache[name] = reader
        return reader

    read.cache = {}
    has_sun_hours = os.path.isfile(os.path.join(outdir, "sun_hours.vtp"))
    if has_sun_hours and not os.path.isfile(os.path.join(outdir, "report.json")):
        # A sun-hours map alone (e.g. from a series run that wrote no per-light result).
        VIEW_ASPECT[0] = args.size[0] / args.size[1]
        VIEW_WIDTH[0] = args.size[0]
        layout = CreateLayout("libshadow sun hours")
        view = CreateView("RenderView")
        AssignViewToLayout(view=view, layout=layout, hint=0)
        white_view(view)
        sun_hours = show_sun_hours(outdir, view, read)
        add_title(view, ["sun hours (exact map)", "period: see report.json"])
        add_north_arrow(view, model_bounds(sun_hours))
        Render(view)
        place_camera_above(view, model_bounds(sun_hours))
        finish(args, layout, [view], (model_bounds(sun_hours), []))
        return

    report = None
    if os.path.isfile(os.path.join(outdir, "report.json")):
        with open(os.path.join(outdir, "report.json")) as f:
            report = json.load(f)
    if open_radiosity.is_radiosity(outdir, report):
        open_radiosity.open_radiosity(args, outdir, report, read, types.SimpleNamespace(**globals()))
        return
    if is_irradiance(outdir, report):
        open_irradiance(args, outdir, report, read)
        return
    if report is None:
        print("open_result: %s: no report.json" % outdir)
        sys.exit(2)
    if "series" in report and "lights" not in report:
        open_series(args, outdir, report, read)
        return
    if not 0 <= args.light < len(report["lights"]):
        print("open_result: --light %d: the result has %d lights (0 to %d)" %
              (args.light, len(report["lights"]), len(report["lights"]) - 1))
        sys.exit(2)
    light_name = report["lights"][args.light]["name"]

    fragments = read("fragments.vtp")
    faces = read("faces.vtp")
    lights = read("lights.vtp")
    plane_shadows = read("plane_shadows.vtp")

    VIEW_ASPECT[0] = args.size[0] / (3 if has_sun_hours else 2) / args.size[1]
    VIEW_WIDTH[0] = args.size[0] / (3 if has_sun_hours else 2)
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
    if is_extended(report["lights"][args.light]) and has_point_array(fragments, "visibility"):
        # An extended light (docs/area-light-visibility.md): the exact visible fraction of the
        # light at every fragment vertex, interpolated across the cells: the penumbra's gradient.
        ColorBy(shown, ("POINTS", "visibility"))
        visibility = GetColorTransferFunction("visibility")
        visibility.ApplyPreset("Inferno (matplotlib)", True)
        visibility.RescaleTransferFunction(0.0, 1.0)
        visibility.AutomaticRescaleRangeMode = "Never"
        shown.SetScalarBarVisibility(left, True)
        style_bar(GetScalarBar(visibility, left), "visible part", digits=2,
                  labels=[0.0, 0.25, 0.5, 0.75, 1.0])
    else:
        ColorBy(shown, ("CELLS", "lit"))
        lit = GetColorTransferFunction("lit")
        lit.InterpretValuesAsCategories = 1
        lit.Annotations = ["0", "shadowed", "1", "lit"]
        lit.IndexedColors = [0.30, 0.34, 0.45, 0.98, 0.86, 0.62]
        shown.SetScalarBarVisibility(left, True)
        style_bar(GetScalarBar(lit, left), "light " + light_name, annotations_left=True)

    plane_mine = Threshold(registrationName="plane shadows of " + light_name, Input=plane_shadows)
    plane_mine.Scalars = ["CELLS", "light_id"]
    plane_mine.LowerThreshold = args.light
    plane_mine.UpperThreshold = args.light
    plane_shown = Show(plane_mine, left)
    plane_shown.ColorArrayName = ["POINTS", ""]
    plane_shown.DiffuseColor = [0.55, 0.1, 0.1]
    Hide(plane_mine, left)  # loaded, one click away in the Pipeline Browser

    # Lights: arrows for directional lights, pointing at the model from its bounding sphere
    # (lights.vtp puts a sun a scene diagonal away, which would shrink the model in the view);
    # point and area lights where they are.
    bounds = model_bounds(faces)
    centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    radius = builtins.max(0.5 * builtins.sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)) ** 0.5, 1e-9)
    glyphs = light_glyphs(report, centre, radius)
    placed = ProgrammableSource(registrationName="lights (placed at the model)")
    placed.OutputDataSetType = "vtkPolyData"
    placed.Script = ARROWS_SCRIPT.format(glyphs=repr(glyphs))
    arrows = Glyph(registrationName="lights", Input=placed, GlyphType="Arrow")
    arrows.OrientationArray = ["POINTS", "direction"]
    arrows.ScaleArray = ["POINTS", "No scale array"]
    arrows.ScaleFactor = 0.3 * radius
    arrows_shown = Show(arrows, left)
    arrows_shown.ColorArrayName = ["POINTS", ""]
    arrows_shown.DiffuseColor = [0.9, 0.6, 0.0]

    # Right: faces by lit fraction, with a legend.
    faces_shown = Show(faces, right)
    unlit(faces_shown)
    array = "lit_fraction_" + sanitize(light_name)
    ColorBy(faces_shown, ("CELLS", array))
    fraction = GetColorTransferFunction(array)
    fraction.ApplyPreset("Inferno (matplotlib)", True)
    fraction.RescaleTransferFunction(0.0, 1.0)
    fraction.AutomaticRescaleRangeMode = "Never"
    faces_shown.SetScalarBarVisibility(right, True)
    style_bar(GetScalarBar(fraction, right), "lit fraction", digits=2,
              labels=[0.0, 0.25, 0.5, 0.75, 1.0])

    for view in (left, right):
        Render(view)  # ParaView resets the camera on a view's first render: get that done first
        place_camera(view, report, args.light, bounds)
    views = [left, right]
    if has_sun_hours:
        # A third view: the exact sun-hours map.
        sun_view = CreateView("RenderView")
        layout.AssignView(6, sun_view)
        white_view(sun_view)
        sun_hours = show_sun_hours(outdir, sun_view, read)
        add_title(sun_view, ["sun hours (exact map)"])
        add_north_arrow(sun_view, model_bounds(sun_hours))
        Render(sun_view)
        place_camera_above(sun_view, model_bounds(sun_hours))
        views.append(sun_view)
    finish(args, layout, views, (bounds, glyphs))


main()
