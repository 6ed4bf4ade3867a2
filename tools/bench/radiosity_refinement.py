#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Adaptive against uniform radiosity meshes: the element field's error against a fine solution.

For a scene (the built-in box on a sunlit floor, or a scene file), solves radiosity (shooting,
fixed patches) on a fine uniform mesh (the reference), on uniform meshes of AREA / 1, 4, 16, ...
and adaptively from AREA at each tolerance, and prints per run the elements, the estimated
relative error of the element field (`discretization_error`), the measured one, sqrt(sum over
the reference's elements of (H_run at its centroid - H_ref)^2 A over sum of H_ref^2 A), and the
time. With --plot, a log-log picture of measured error against elements (docs/radiosity.md,
"Adaptive refinement").

Usage (PYTHONPATH=build/release/python):
  radiosity_refinement.py [--scene FILE] [--area 0.5] [--patch 2.0] [--reference 0.002]
      [--uniform 1,4,16,64] [--tolerances 0.01,0.005,0.004,0.003,0.002] [--passes 4]
      [--threads 2] [--plot OUT.png] [--label NAME]
"""

import argparse
import json
import sys
import time

import numpy as np

import libshadow


def box_on_floor():
    """The scene of tests/compute/test_radiosity_refinement.cpp."""
    q = lambda *p: [list(v) for v in p]  # noqa: E731
    box = [q((0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2)), q((0, 0, 0), (2, 0, 0), (2, 0, 2), (0, 0, 2)),
           q((2, 0, 0), (2, 2, 0), (2, 2, 2), (2, 0, 2)), q((2, 2, 0), (0, 2, 0), (0, 2, 2), (2, 2, 2)),
           q((0, 2, 0), (0, 0, 0), (0, 0, 2), (0, 2, 2))]
    return libshadow.parse_scene(json.dumps({
        "materials": [{"name": "m", "reflectance": 0.5}],
        "meshes": [{"name": "floor", "material": "m", "polygons": [q((-3, -3, 0), (5, -3, 0), (5, 5, 0), (-3, 5, 0))]},
                   {"name": "box", "material": "m", "polygons": box}],
        "lights": [{"name": "sun", "type": "directional", "to_light": [0.4, 0.3, 0.85], "intensity": 1000}]}))


def field_error(test, ref):
    """Relative L2 error of test's element field against the finer ref, face by face."""
    tt, rt = test["elements"], ref["elements"]
    num = den = 0.0
    for face in np.unique(rt["face_id"]):
        tri = tt["triangles"][tt["face_id"] == face]
        h_test = tt["irradiance"][tt["face_id"] == face]
        mine = rt["face_id"] == face
        centroids = rt["triangles"][mine].mean(axis=1)
        h_ref, area = rt["irradiance"][mine], rt["area"][mine]
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        n = np.cross(b - a, c - a)
        nn = (n * n).sum(1)
        holder = np.full(len(centroids), -1)
        for j in range(len(tri)):
            d = centroids - a[j]
            u = (np.cross(b[j] - a[j], d) @ n[j]) / nn[j]
            v = (np.cross(d, c[j] - a[j]) @ n[j]) / nn[j]
            inside = (u >= -1e-9) & (v >= -1e-9) & (u + v <= 1 + 1e-9) & (holder < 0)
            holder[inside] = j
        if (holder < 0).any():
            sys.exit(f"radiosity_refinement: {(holder < 0).sum()} reference centroids of face {face} in no element")
        num += ((h_test[holder] - h_ref) ** 2 * area).sum()
        den += (h_ref ** 2 * area).sum()
    return float(np.sqrt(num / den))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--scene")
    p.add_argument("--area", type=float, default=0.5)
    p.add_argument("--patch", type=float, default=2.0)
    p.add_argument("--reference", type=float, default=0.002)
    p.add_argument("--uniform", default="1,4,16,64")
    p.add_argument("--tolerances", default="0.01,0.005,0.004,0.003,0.002")
    p.add_argument("--passes", type=int, default=4)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--plot")
    p.add_argument("--label", default="")
    a = p.parse_args()
    scene = libshadow.load_scene(a.scene) if a.scene else box_on_floor()

    def run(**kw):
        t = time.time()
        r = libshadow.radiosity(scene, patch_area=a.patch, tolerance=1e-4, threads=a.threads, method="shooting", **kw)
        r["time"] = time.time() - t
        return r

    ref = run(max_element_area=a.reference)
    print(f"reference: {len(ref['elements']['area'])} elements, {ref['time']:.1f} s")
    print("mesh\telements\testimated\tmeasured\tseconds")
    rows = {"uniform": [], "adaptive": []}
    for k in (int(x) for x in a.uniform.split(",")):
        # A tolerance of 0.5 in one pass: the estimate, never a split.
        r = run(max_element_area=a.area / k, refine_tolerance=0.5, refine_passes=1)
        rows["uniform"].append((len(r["elements"]["area"]), field_error(r, ref)))
        print(f"uniform {a.area / k:.4g}\t{rows['uniform'][-1][0]}\t{r['discretization_error']:.4f}\t"
              f"{rows['uniform'][-1][1]:.4f}\t{r['time']:.1f}", flush=True)
    for tol in (float(x) for x in a.tolerances.split(",")):
        r = run(max_element_area=a.area, refine_tolerance=tol, refine_passes=a.passes)
        rows["adaptive"].append((len(r["elements"]["area"]), field_error(r, ref)))
        print(f"adaptive {tol}\t{rows['adaptive'][-1][0]}\t{r['discretization_error']:.4f}\t"
              f"{rows['adaptive'][-1][1]:.4f}\t{r['time']:.1f}", flush=True)
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4.2))
        for name, marker in (("uniform", "o-"), ("adaptive", "s-")):
            n, e = zip(*sorted(rows[name]))
            ax.loglog(n, [100 * x for x in e], marker, label=f"{name} {a.label}".strip())
        ax.set_xlabel("elements")
        ax.set_ylabel("relative L2 error of the element field, %")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(a.plot, dpi=110)
        print(f"wrote {a.plot}")


if __name__ == "__main__":
    main()
