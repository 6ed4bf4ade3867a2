#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks the layout that tools/paraview/open_result.py --describe wrote: in every view the model
is framed (inside the view, a good part of it) and clear of the colour bars; the bars have a
title and fixed-point labels (0.00 ... 1.00 or hours, not ParaView's 1.0e+00) within their range;
the light glyphs stand near the model (directional lights at its bounding sphere, not far above).
Usage: check_layout.py LAYOUT.json [MIN_SHARE]"""
import json
import re
import sys


def main(path, min_share):
    with open(path) as f:
        layout = json.load(f)
    problems = []
    b = layout["bounds"]
    centre = [(b[2 * i] + b[2 * i + 1]) / 2 for i in range(3)]
    radius = 0.5 * sum((b[2 * i + 1] - b[2 * i]) ** 2 for i in range(3)) ** 0.5
    for tail, _ in layout["glyphs"]:
        distance = sum((t - c) ** 2 for t, c in zip(tail, centre)) ** 0.5
        if distance > 1.5 * radius:
            problems.append(f"a light glyph stands {distance / radius:.2f} model radii from the model's centre")
    for view in layout["views"]:
        x0, x1, y0, y1 = view["model_box"]
        name = view["name"]
        print(f"check_layout: {name}: model box x {x0:.2f}..{x1:.2f}, y {y0:.2f}..{y1:.2f}; "
              f"{len(view['bars'])} colour bar(s)")
        if x0 < 0 or y0 < 0 or x1 > 1 or y1 > 1:
            problems.append(f"{name}: the model's box leaves the view")
        if max(x1 - x0, y1 - y0) < min_share:
            problems.append(f"{name}: the model spans only {100 * max(x1 - x0, y1 - y0):.0f}% of the view")
        # A sun-hours view says what it shows (a title, clear of the model) and where north is.
        if any(bar["title"] == "sun hours" for bar in view["bars"]):
            title = view.get("title") or []
            if not title or "sun hours" not in title[0]:
                problems.append(f"{name}: a sun-hours view without a title naming it ({title})")
            elif y1 > 1 - view.get("top_room", 0) + 0.02:
                problems.append(f"{name}: the model (top {y1:.2f}) runs into the title's band")
            if not view.get("north"):
                problems.append(f"{name}: a sun-hours view without a north arrow")
            if layout.get("series") and not any(" to " in line for line in title[1:]):
                problems.append(f"{name}: a series' sun-hours view without its period ({title})")
        for bar in view["bars"]:
            if not bar["title"].strip():
                problems.append(f"{name}: a colour bar without a title")
            px, py = bar["position"]
            # The bar with its labels: up to 100 pixels to its left.
            room = 100.0 / bar["view_size"][0]
            if x1 > px - room and y1 > py and y0 < py + bar["length"]:
                problems.append(f"{name}: the colour bar '{bar['title']}' at x {px:.2f} overlaps the model "
                                f"(right edge {x1:.2f})")
            if bar["categorical"]:
                continue
            for key in ("label_format", "range_label_format"):
                if not re.fullmatch(r"%\.\d+f", bar[key]):
                    problems.append(f"{name}: '{bar['title']}' {key} is {bar[key]!r}, not fixed-point")
            if bar["automatic_label_format"]:
                problems.append(f"{name}: '{bar['title']}' formats its labels automatically")
            if not bar["custom_labels"]:
                problems.append(f"{name}: '{bar['title']}' has no chosen labels")
            low, high = bar["range"]
            if any(v < low - 1e-9 or v > high + 1e-9 for v in bar["custom_labels"]):
                problems.append(f"{name}: '{bar['title']}' labels {bar['custom_labels']} outside {low}..{high}")
    if problems:
        print("check_layout: FAILED: " + "; ".join(problems))
        return 1
    print("check_layout: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], float(sys.argv[2]) if len(sys.argv) > 2 else 0.4))
