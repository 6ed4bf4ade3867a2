#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plots `shadow-bench compare`'s CSV: error against wall time (log-log), one subplot per scene,
one curve per method (coarse to fine), the exact result as a star on the bottom edge (its error
is zero). Writes one PNG per error measure and prints the scaling table (time and peak memory
against faces for the cities, with fitted exponents) as Markdown.

    /usr/bin/python3 tools/plot_speed_error.py docs/bench-compare.csv docs/img/bench-speed-error
      -> docs/img/bench-speed-error-total.png, docs/img/bench-speed-error-face.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plot_bench import fit_exponent  # noqa: E402  (least-squares slope in log-log, shared)

STYLE = {
    "exact": dict(color="black", marker="*"),
    "fast": dict(color="tab:green", marker="D"),
    "shadow-map": dict(color="tab:blue", marker="s"),
    "ray-sampling": dict(color="tab:orange", marker="o"),
}
FLOOR = 1e-13  # where the exact result (error 0) is drawn; the fast path lands near 1e-10
MEASURES = {
    "total": ("total_lit_rel_error", "total lit area, relative error"),
    "face": ("face_fraction_mean_abs_error", "per-face lit fraction, mean abs. error"),
}


def label(method, name, value):
    if name == "resolution":
        return f"{int(value)}"
    if name == "spacing_m":
        return f"{value:g} m"
    return ""


def main(csv_path, png_prefix):
    rows = list(csv.DictReader(open(csv_path)))
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    for key, (column, ylabel) in MEASURES.items():
        cols = min(4, len(scenes))
        nrows = (len(scenes) + cols - 1) // cols
        fig, axes = plt.subplots(nrows, cols, figsize=(4.2 * cols, 3.6 * nrows), squeeze=False)
        for i, scene in enumerate(scenes):
            ax = axes[i // cols][i % cols]
            mine = [r for r in rows if r["scene"] == scene]
            for method in dict.fromkeys(r["method"] for r in mine):
                pts = [r for r in mine if r["method"] == method]
                style = STYLE.get(method, dict(marker="^"))
                if method == "exact":
                    t = float(pts[0]["total_s"])
                    ax.plot([t], [FLOOR], linestyle="none", markersize=14, clip_on=False, label="exact (error 0)",
                            **style)
                    ax.axvline(t, color="black", linewidth=0.8, linestyle=":")
                    continue
                if method == "fast":
                    # One point: no parameter; its error is measured against exact (and bounded).
                    x = float(pts[0]["total_s"])
                    y = max(float(pts[0][column]), FLOOR)
                    ax.plot([x], [y], linestyle="none", markersize=8, clip_on=False, label="fast (certified bound)",
                            **style)
                    continue
                # coarse to fine: decreasing spacing, increasing resolution
                pts.sort(key=lambda r: float(r["parameter"]) * (-1 if r["parameter_name"] == "resolution" else 1),
                         reverse=True)
                xs = [float(r["total_s"]) for r in pts]
                ys = [max(float(r[column]), FLOOR) for r in pts]
                ax.plot(xs, ys, label=method, **style)
                for r, x, y in zip(pts, xs, ys):
                    ax.annotate(label(method, r["parameter_name"], float(r["parameter"])), (x, y), fontsize=6,
                                textcoords="offset points", xytext=(3, 3))
            ax.axhline(1e-4, color="grey", linewidth=0.6, linestyle="--")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_ylim(FLOOR * 0.7, 1.5)
            faces = mine[0]["faces"]
            ax.set_title(f"{scene} ({int(faces):,} faces)", fontsize=9)
            ax.grid(True, which="major", alpha=0.3)
            ax.tick_params(labelsize=7)
            if i % cols == 0:
                ax.set_ylabel(ylabel, fontsize=8)
            if i // cols == nrows - 1:
                ax.set_xlabel("wall time (s), 2 threads", fontsize=8)
            if i == 0:
                ax.legend(fontsize=7, loc="lower left")
        for j in range(len(scenes), nrows * cols):
            axes[j // cols][j % cols].axis("off")
        fig.suptitle(f"libshadow: speed against error ({ylabel}; dashed: 1e-4)", fontsize=10)
        fig.tight_layout()
        fig.savefig(f"{png_prefix}-{key}.png", dpi=100)
        plt.close(fig)

    # Scaling with N (cities): exact, and each baseline at a fixed parameter.
    fixed = {"exact": None, "shadow-map": 2048.0, "ray-sampling": 0.25}
    print("| method | parameter | sun | faces | total (s) | peak (MiB) |")
    print("|---|---:|---|---:|---:|---:|")
    fits = []
    for method, parameter in fixed.items():
        for sun in ("sun 40", "sun 5"):
            pts = [r for r in rows if r["kind"] == "city" and r["light"] == sun and r["method"] == method and
                   (parameter is None or float(r["parameter"]) == parameter)]
            pts.sort(key=lambda r: int(r["faces"]))
            for r in pts:
                print(f"| {method} | {'-' if parameter is None else f'{parameter:g}'} | {sun} | {int(r['faces']):,} | "
                      f"{float(r['total_s']):.3f} | {float(r['peak_mib']):.0f} |")
            if len(pts) >= 2:
                xs = [int(r["faces"]) for r in pts]
                fits.append((method, parameter, sun, fit_exponent(xs, [float(r["total_s"]) for r in pts]),
                             fit_exponent(xs, [float(r["peak_mib"]) for r in pts])))
    print()
    print("| method | parameter | sun | time exponent k | memory exponent |")
    print("|---|---:|---|---:|---:|")
    for method, parameter, sun, kt, km in fits:
        print(f"| {method} | {'-' if parameter is None else f'{parameter:g}'} | {sun} | {kt:.2f} | {km:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
