#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks the screenshot that tools/paraview/open_result.py saved: the requested size, a scene
that fills a good part of it, and both fragment colours (lit: sand, shadowed: blue-grey) and the
lit-fraction colour map present. Usage: check_screenshot.py IMAGE.png WIDTH HEIGHT"""
import sys

import vtk


def main(path, width, height):
    reader = vtk.vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    dims = image.GetDimensions()
    problems = []
    if (dims[0], dims[1]) != (width, height):
        problems.append(f"size {dims[0]}x{dims[1]}, expected {width}x{height}")
    scalars = image.GetPointData().GetScalars()
    components = scalars.GetNumberOfComponents()
    pixels = scalars.GetNumberOfTuples()
    background = sand = blue_grey = 0
    colours = set()
    for i in range(0, pixels):
        r, g, b = (scalars.GetComponent(i, c) for c in range(3))
        colours.add((r >> 3, g >> 3, b >> 3) if isinstance(r, int) else (int(r) >> 3, int(g) >> 3, int(b) >> 3))
        if r > 245 and g > 245 and b > 245:
            background += 1
        elif r > 150 and r > g > b + 40:
            sand += 1
        elif b > r + 15 and b > 40:
            blue_grey += 1
    scene_share = 1.0 - background / pixels
    print(f"check_screenshot: {dims[0]}x{dims[1]}, {components} components, scene covers "
          f"{100 * scene_share:.1f}%, sand {sand} px, blue-grey {blue_grey} px, {len(colours)} colours")
    if scene_share < 0.15:
        problems.append(f"the scene covers only {100 * scene_share:.1f}% of the picture")
    if sand < 0.01 * pixels:
        problems.append("almost no lit (sand) fragments visible")
    if blue_grey < 0.01 * pixels:
        problems.append("almost no shadowed (blue-grey) fragments visible")
    if len(colours) < 50:
        problems.append(f"only {len(colours)} distinct colours: no shading or colour map")
    if problems:
        print("check_screenshot: FAILED: " + "; ".join(problems))
        return 1
    print("check_screenshot: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], int(sys.argv[2]), int(sys.argv[3])))
