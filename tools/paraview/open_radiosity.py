# SPDX-License-Identifier: GPL-3.0-or-later
"""The radiosity view of open_result.py: a `shadow radiosity` OUTDIR (radiosity.vtp beside a
report.json of kind "radiosity") opened with its elements coloured by their radiosity, W/m².

Kept beside open_result.py (which imports it) so that the script stays short; `views` is
open_result's namespace (its layout, camera and legend helpers), passed in rather than imported
because open_result.py runs as a script.
"""
import builtins
import math
import os
import sys

from paraview.simple import ColorBy, CreateLayout, CreateView, GetColorTransferFunction, GetScalarBar, Render, Show

RADIOSITY_TITLE = "W/m\u00b2"  # the legend: radiosity leaving each element


def is_radiosity(outdir, report):
    """An OUTDIR of `shadow radiosity`: its report says so (kind "radiosity"; an older report
    without a kind has summary.elements and no lights), or, without a report, radiosity.vtp."""
    if report is not None:
        if report.get("kind") is not None:
            return report.get("kind") == "radiosity"
        return "elements" in report.get("summary", {}) and "lights" not in report
    return os.path.isfile(os.path.join(outdir, "radiosity.vtp"))


def summary_line(report):
    """What the title says of the run, from report.json: elements and the unshot part."""
    summary = (report or {}).get("summary", {})
    if summary.get("elements") is None:
        return "summary: see report.json"
    line = "%d elements" % summary["elements"]
    if summary.get("unshot_fraction") is not None:
        line += ", unshot %.2g%%" % (100.0 * summary["unshot_fraction"])
    return line


def open_radiosity(args, outdir, report, read, views):
    """radiosity.vtp coloured by `radiosity` from 0 to a round top (Inferno, legend W/m²), the
    elements' backs culled (light leaves a face's front: a room seen from outside shows inside)."""
    if not os.path.isfile(os.path.join(outdir, "radiosity.vtp")):
        print("open_result: %s: a radiosity result without radiosity.vtp" % outdir)
        sys.exit(2)
    views.VIEW_ASPECT[0] = args.size[0] / args.size[1]
    views.VIEW_WIDTH[0] = args.size[0]
    layout = CreateLayout("libshadow radiosity")
    view = CreateView("RenderView")
    views.arrange(layout, [view])
    views.white_view(view)
    elements = read("radiosity.vtp")
    bounds = views.model_bounds(elements)
    shown = Show(elements, view)
    try:
        shown.BackfaceRepresentation = "Cull Backface"
    except AttributeError:
        pass  # an older ParaView: the room is seen from outside
    # The colour is the value: unlit (the headlight would darken walls seen at a slant).
    shown.Ambient = 1.0
    shown.Diffuse = 0.0
    ColorBy(shown, ("CELLS", "radiosity"))
    lut = GetColorTransferFunction("radiosity")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    lut.AutomaticRescaleRangeMode = "Never"
    high = elements.CellData["radiosity"].GetRange()[1]
    top, step = 1.0, 1.0
    if high == high and high > 0:  # not NaN, something leaves
        step = views.nice_step(high)
        top = step * math.ceil(high / step - 1e-9)
    lut.RescaleTransferFunction(0.0, top)
    shown.SetScalarBarVisibility(view, True)
    digits = 0 if step >= 1 else builtins.min(3, int(math.ceil(-math.log10(step))))
    views.style_bar(GetScalarBar(lut, view), RADIOSITY_TITLE, digits=digits,
                    labels=[k * step for k in range(int(top / step + 1e-9) + 1)])
    views.add_title(view, ["radiosity per element", summary_line(report)])
    Render(view)  # ParaView resets the camera on a view's first render: get that done first
    views.place_camera_above(view, bounds)
    views.finish(args, layout, [view], (bounds, []))
