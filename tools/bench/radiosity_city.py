#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes a generated city of N x N boxes on a ground under one sun, for `shadow radiosity`
(docs/radiosity.md): ground reflectance 0.2, walls and roofs 0.3.

usage: radiosity_city.py OUT.json [--side N] [--spacing M] [--seed S]
"""
import argparse
import json
import random


def box(x0, y0, x1, y1, h):
    """The five visible faces of a box standing on the ground, fronts outward."""
    return [
        [[x0, y0, h], [x1, y0, h], [x1, y1, h], [x0, y1, h]],
        [[x0, y0, 0], [x1, y0, 0], [x1, y0, h], [x0, y0, h]],
        [[x0, y1, 0], [x0, y1, h], [x1, y1, h], [x1, y1, 0]],
        [[x1, y0, 0], [x1, y1, 0], [x1, y1, h], [x1, y0, h]],
        [[x0, y0, 0], [x0, y0, h], [x0, y1, h], [x0, y1, 0]],
    ]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("--side", type=int, default=32, help="boxes per side (32: 1,024 boxes)")
    parser.add_argument("--spacing", type=float, default=20.0, help="metres between box centres")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    polygons = []
    for i in range(args.side):
        for j in range(args.side):
            cx, cy = i * args.spacing, j * args.spacing
            w = rng.uniform(6, 12) / 2
            d = rng.uniform(6, 12) / 2
            h = round(rng.uniform(6, 30), 1)
            polygons += box(round(cx - w, 2), round(cy - d, 2), round(cx + w, 2), round(cy + d, 2), h)
    lo = -args.spacing
    hi = args.side * args.spacing
    scene = {
        "materials": [{"name": "ground", "reflectance": 0.2}, {"name": "walls", "reflectance": 0.3}],
        "meshes": [
            {"name": "ground", "material": "ground", "polygons": [[[lo, lo, 0], [hi, lo, 0], [hi, hi, 0], [lo, hi, 0]]]},
            {"name": "city", "material": "walls", "polygons": polygons},
        ],
        "lights": [{"name": "sun", "type": "directional", "to_light": [0.4, -0.6, 0.8], "intensity": 800}],
    }
    with open(args.out, "w") as f:
        json.dump(scene, f)


if __name__ == "__main__":
    main()
