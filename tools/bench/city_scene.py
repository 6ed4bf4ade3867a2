#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the benchmark city (shadow::make_city: the same boxes, bit for bit) as a scene file
with a `sun` block, for timing `shadow series` as a whole process (docs/benchmarks.md).

    python3 tools/bench/city_scene.py --boxes 1000 -o city.json            # a year of hourly suns
    python3 tools/bench/city_scene.py --boxes 10000 --start 2026-03-21 --end 2026-03-21 -o c.json

make_city draws from std::mt19937_64 through libstdc++'s uniform_real_distribution (one 64-bit
draw per number, scaled by 2^-64) and rounds to centimetres; the same steps here give the same
doubles, so the scene is the one shadow-bench times.
"""
import argparse
import json
import math

MASK = (1 << 64) - 1


class Mt19937_64:
    """The 64-bit Mersenne Twister of the C++ standard (std::mt19937_64)."""

    def __init__(self, seed):
        self.mt = [0] * 312
        self.mt[0] = seed & MASK
        for i in range(1, 312):
            self.mt[i] = (6364136223846793005 * (self.mt[i - 1] ^ (self.mt[i - 1] >> 62)) + i) & MASK
        self.index = 312

    def next(self):
        if self.index >= 312:
            for i in range(312):
                x = (self.mt[i] & 0xFFFFFFFF80000000) | (self.mt[(i + 1) % 312] & 0x7FFFFFFF)
                xa = x >> 1
                if x & 1:
                    xa ^= 0xB5026F5AA96619E9
                self.mt[i] = self.mt[(i + 156) % 312] ^ xa
            self.index = 0
        y = self.mt[self.index]
        self.index += 1
        y ^= (y >> 29) & 0x5555555555555555
        y ^= (y << 17) & 0x71D67FFFEDA60000
        y ^= (y << 37) & 0xFFF7EEE000000000
        y ^= y >> 43
        return y & MASK


def uniform(rng, a, b):
    r = float(rng.next()) / 18446744073709551616.0  # generate_canonical: one draw of 64 bits
    if r >= 1.0:
        r = math.nextafter(1.0, 0.0)
    return r * (b - a) + a


def centimetres(v):
    # std::round rounds halves away from zero; the values here are positive.
    return math.floor(v * 100.0 + 0.5) / 100.0


def box_faces(x0, y0, z0, x1, y1, z1):
    return [
        [[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],
        [[x0, y0, z0], [x0, y1, z0], [x1, y1, z0], [x1, y0, z0]],
        [[x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]],
        [[x1, y1, z0], [x0, y1, z0], [x0, y1, z1], [x1, y1, z1]],
        [[x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1]],
        [[x0, y1, z0], [x0, y0, z0], [x0, y0, z1], [x0, y1, z1]],
    ]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--boxes", type=int, default=1000)
    p.add_argument("--seed", type=int, default=2026)
    p.add_argument("--latitude", type=float, default=48.0)
    p.add_argument("--longitude", type=float, default=11.0)
    p.add_argument("--start", default="2026-01-01")
    p.add_argument("--end", default="2026-12-31")
    p.add_argument("--step", type=int, default=60)
    p.add_argument("-o", "--output", required=True)
    a = p.parse_args()
    extent = 500.0 * math.sqrt(a.boxes / 1000.0)  # the benchmark's density
    rng = Mt19937_64(a.seed)
    faces = []
    for _ in range(a.boxes):
        # The order of the draws is make_city's: x, y, w, d, h.
        x = centimetres(uniform(rng, 0.0, extent))
        y = centimetres(uniform(rng, 0.0, extent))
        w = centimetres(uniform(rng, 2.0, 10.0))
        d = centimetres(uniform(rng, 2.0, 10.0))
        h = centimetres(uniform(rng, 3.0, 30.0))
        faces.extend(box_faces(x, y, 0.0, x + w, y + d, h))
    ground = [[[-10.0, -10.0, 0.0], [extent + 10, -10.0, 0.0], [extent + 10, extent + 10, 0.0], [-10.0, extent + 10, 0.0]]]
    scene = {
        "_comment": f"make_city({a.boxes}, {extent}, {a.seed}) from tools/bench/city_scene.py",
        "meshes": [{"name": "ground", "polygons": ground}, {"name": "buildings", "polygons": faces}],
        "sun": {"latitude": a.latitude, "longitude": a.longitude, "time_zone": "UTC+01:00",
                "start": a.start, "end": a.end, "step_minutes": a.step},
    }
    with open(a.output, "w", encoding="utf-8") as out:
        json.dump(scene, out, separators=(",", ":"))
        out.write("\n")


if __name__ == "__main__":
    main()
