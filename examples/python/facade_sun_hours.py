# SPDX-License-Identifier: GPL-3.0-or-later
"""Sun hours per facade of two buildings across a street in Berlin, on three days of the year,
plotted with matplotlib (docs/python.md; the picture is docs/img/python-facade-sun-hours.png).

    PYTHONPATH=build/release/python python3 examples/python/facade_sun_hours.py [PICTURE.png]

Without a picture name it prints the table only (matplotlib is needed for the picture alone).
"""
import sys

import numpy as np

import libshadow

# Berlin, local standard time UTC+01:00 (no daylight saving), one sun every 15 minutes.
BERLIN = {"latitude": 52.52, "longitude": 13.405, "elevation": 34, "time_zone": "UTC+01:00", "step_minutes": 15}
DAYS = {"March equinox": "2026-03-20", "June solstice": "2026-06-21", "December solstice": "2026-12-21"}


def box_facades(name, x0, y0, x1, y1, height):
    """The four walls of a box as four meshes (one facade each), their fronts outward, and its roof."""
    walls = {
        "south": [[x0, y0, 0], [x1, y0, 0], [x1, y0, height], [x0, y0, height]],
        "east": [[x1, y0, 0], [x1, y1, 0], [x1, y1, height], [x1, y0, height]],
        "north": [[x1, y1, 0], [x0, y1, 0], [x0, y1, height], [x1, y1, height]],
        "west": [[x0, y1, 0], [x0, y0, 0], [x0, y0, height], [x0, y1, height]],
    }
    meshes = [{"name": "%s %s" % (name, side), "polygons": [np.array(quad, dtype=float)]}
              for side, quad in walls.items()]
    meshes.append({"name": name + " roof",
                   "polygons": [np.array([[x0, y0, height], [x1, y0, height], [x1, y1, height], [x0, y1, height]],
                                         dtype=float)]})
    return meshes


def facade_sun_hours():
    """{day: (facade names, sun hours)}: a 24 m slab south of an 12 m row across a 15 m street
    (+y is north)."""
    meshes = box_facades("slab", 0, 0, 40, 12, 24) + box_facades("row", 0, 27, 40, 37, 12)
    meshes.append({"name": "street", "polygons": [np.array([[-30, -30, 0], [70, -30, 0], [70, 70, 0], [-30, 70, 0]],
                                                            dtype=float)]})
    receivers = [m["name"] for m in meshes if m["name"] != "street"]
    table = {}
    for label, day in DAYS.items():
        scene = libshadow.scene_from_data(meshes, sun=dict(BERLIN, start=day, end=day), receivers=receivers,
                                          name="facade_sun_hours.py")
        result = libshadow.ShadowEngine(scene).compute(polygons=False)
        table[label] = libshadow.sun_hours(result, by="mesh")
    return table


def plot(table, picture):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = next(iter(table.values()))[0]
    x = np.arange(len(names))
    width = 0.8 / len(table)
    fig, ax = plt.subplots(figsize=(9, 4.2), dpi=110)
    for i, (label, (_, hours)) in enumerate(table.items()):
        ax.bar(x + (i - (len(table) - 1) / 2) * width, hours, width, label=label)
    ax.set_xticks(x, names, rotation=35, ha="right")
    ax.set_ylabel("sun hours (lit fraction x hours)")
    ax.set_title("Berlin: sun hours per facade, 24 m slab and 12 m row across a 15 m street")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(picture)


def main(argv):
    table = facade_sun_hours()
    names = next(iter(table.values()))[0]
    print("%-12s" % "facade" + "".join("%20s" % day for day in table))
    for i, name in enumerate(names):
        print("%-12s" % name + "".join("%20.2f" % hours[i] for _, hours in table.values()))
    if len(argv) > 1:
        plot(table, argv[1])
        print("wrote", argv[1])


if __name__ == "__main__":
    main(sys.argv)
