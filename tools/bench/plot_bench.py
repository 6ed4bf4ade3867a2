#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots shadow-bench's CSV: compute time against scene size (log-log), one line per scene,
light and thread count, with the fitted exponent of time ~ faces^k in the legend.

    /usr/bin/python3 tools/plot_bench.py docs/benchmarks.csv docs/img/bench-scaling.png
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fit_exponent(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def main(csv_path, png_path):
    series = {}
    with open(csv_path) as f:
        for row in csv.DictReader(f):
            if row["scene"] == "room":
                continue
            key = (row["scene"], row["light"], int(row["threads"]))
            series.setdefault(key, []).append((int(row["faces"]), float(row["compute_s"])))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for (scene, light, threads), points in sorted(series.items()):
        points.sort()
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        k = fit_exponent(xs, ys)
        label = f"{scene}, {light}, {threads} thread{'s' if threads > 1 else ''} (k = {k:.2f})"
        ax.plot(xs, ys, marker="o", linestyle="-" if threads == 1 else "--", label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("faces (6 per box + ground)")
    ax.set_ylabel("exact shadows, compute time (s)")
    ax.set_title("libshadow: time against scene size (time ~ faces^k)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
