#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots `shadow-bench soft`'s CSV: error against wall time (log-log), one column per scene; top
row the mean absolute error of the visible fraction per point, bottom row the per-face fully-lit
area error (over the total area). One curve per method (PCF of each kernel and PCSS over map
resolutions, rays over k), the exact reference as a star on the bottom edge (its error is zero).
Prints the table of docs/soft-shadows.md as Markdown.

    /usr/bin/python3 tools/plot_soft.py docs/bench-soft.csv docs/img/bench-soft-speed-error.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-6  # where errors of 0 are drawn
MEASURES = [
    ("mean_abs_error", "visible fraction, mean abs. error per point"),
    ("fully_lit_area_error", "fully-lit area error / total area"),
]
COLOURS = {"pcf-r0": "tab:blue", "pcf-r1": "tab:cyan", "pcf-r3": "tab:purple", "pcf-r8": "tab:pink",
           "pcss": "tab:green", "rays": "tab:orange", "rays-reference": "tab:red", "exact": "black"}


def label(r):
    p = float(r["parameter"])
    return f"{int(p)}" if r["parameter_name"] == "resolution" else f"k={int(p)}"


def main(csv_path, png_path):
    rows = list(csv.DictReader(open(csv_path)))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(len(MEASURES), len(scenes), figsize=(4.4 * len(scenes), 3.7 * len(MEASURES)),
                             squeeze=False)
    for j, scene in enumerate(scenes):
        mine = [r for r in rows if r["scene"] == scene]
        for i, (column, ylabel) in enumerate(MEASURES):
            ax = axes[i][j]
            for method in dict.fromkeys(r["method"] for r in mine):
                pts = sorted((r for r in mine if r["method"] == method), key=lambda r: float(r["parameter"]))
                colour = COLOURS.get(method, "grey")
                xs = [max(float(r["total_s"]), 1e-4) for r in pts]
                ys = [max(float(r[column]), FLOOR) for r in pts]
                if method == "exact":
                    ax.plot(xs, [FLOOR], marker="*", markersize=14, color=colour, linestyle="none", clip_on=False,
                            label="exact (reference)")
                    ax.axvline(xs[0], color=colour, linewidth=0.8, linestyle=":")
                    continue
                marker = "o" if method.startswith("rays") else ("D" if method == "pcss" else "s")
                ax.plot(xs, ys, marker=marker, color=colour, label=method, markersize=4)
                for r, x, y in zip(pts, xs, ys):
                    ax.annotate(label(r), (x, y), fontsize=5, textcoords="offset points", xytext=(3, 2))
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_ylim(FLOOR * 0.7, 1.5)
            ax.grid(True, which="major", alpha=0.3)
            ax.tick_params(labelsize=7)
            if i == 0:
                ax.set_title(f"{scene}: {mine[0]['light']} ({int(mine[0]['points']):,} points)", fontsize=8)
            if j == 0:
                ax.set_ylabel(ylabel, fontsize=8)
            if i == len(MEASURES) - 1:
                ax.set_xlabel(f"wall time (s), {mine[0]['threads']} threads", fontsize=8)
            if i == 0 and j == 0:
                ax.legend(fontsize=6, loc="lower left", ncol=2)
    fig.suptitle("Soft shadows: speed against error of PCF, PCSS and k rays (reference: exact light_visibility)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(png_path, dpi=100)
    plt.close(fig)

    print("| scene | method | parameter | time (s) | mean abs. error | max abs. error | mean error in penumbra | "
          "lit area err. | fully-lit area err. | umbra area err. |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        param = "-" if r["method"] == "exact" else label(r)
        print(f"| {r['scene']} | {r['method']} | {param} | {float(r['total_s']):.3f} | "
              f"{float(r['mean_abs_error']):.1e} | {float(r['max_abs_error']):.2f} | "
              f"{float(r['penumbra_mean_abs_error']):.1e} | {float(r['lit_area_error']):.1e} | "
              f"{float(r['fully_lit_area_error']):.1e} | {float(r['umbra_area_error']):.1e} |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
