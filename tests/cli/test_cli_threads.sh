#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow compute` writes the same bytes for any thread count (docs/numeric-contract.md,
# "Vertices written are the exact points rounded once to nearest"): every .vtp and .vtm file of
# the bundled examples, and of rotated boxes at UTM-like coordinates (faces that are not exactly
# planar in doubles, the lazy exact route), with --threads 1 and --threads 2. report.json differs
# only in its `run` object (the options name the thread count), so its faces are compared.
#
# Usage: bash test_cli_threads.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-threads 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
EXAMPLES=$2

# Rotated boxes on a rotated ground, a sun and a lamp, far from the origin.
python3 - "$WORK/rotated.json" <<'PY'
import json, math, random, sys
rng = random.Random(20261129)
axis = [0.3, 0.5, 0.8]
n = math.sqrt(sum(a * a for a in axis))
ux, uy, uz = (a / n for a in axis)
c, s = math.cos(0.7), math.sin(0.7)
R = [[c + ux * ux * (1 - c), ux * uy * (1 - c) - uz * s, ux * uz * (1 - c) + uy * s],
     [uy * ux * (1 - c) + uz * s, c + uy * uy * (1 - c), uy * uz * (1 - c) - ux * s],
     [uz * ux * (1 - c) - uy * s, uz * uy * (1 - c) + ux * s, c + uz * uz * (1 - c)]]
offset = [512345.25, 4012345.5, 301.234]
def place(p, shift=True):
    q = [sum(R[r][k] * p[k] for k in range(3)) for r in range(3)]
    return [q[r] + offset[r] for r in range(3)] if shift else q
def box(x0, y0, z0, x1, y1, z1):
    v = lambda x, y, z: place([x, y, z])
    return [[v(x0, y0, z0), v(x0, y1, z0), v(x1, y1, z0), v(x1, y0, z0)],
            [v(x0, y0, z1), v(x1, y0, z1), v(x1, y1, z1), v(x0, y1, z1)],
            [v(x0, y0, z0), v(x1, y0, z0), v(x1, y0, z1), v(x0, y0, z1)],
            [v(x1, y0, z0), v(x1, y1, z0), v(x1, y1, z1), v(x1, y0, z1)],
            [v(x1, y1, z0), v(x0, y1, z0), v(x0, y1, z1), v(x1, y1, z1)],
            [v(x0, y1, z0), v(x0, y0, z0), v(x0, y0, z1), v(x0, y1, z1)]]
boxes = []
for _ in range(12):
    x, y = rng.uniform(-15, 12), rng.uniform(-15, 12)
    boxes += box(x, y, 0, x + rng.uniform(1, 4), y + rng.uniform(1, 4), rng.uniform(1, 8))
ground = [[place([-20, -20, 0]), place([20, -20, 0]), place([20, 20, 0]), place([-20, 20, 0])]]
scene = {"meshes": [{"name": "ground", "polygons": ground}, {"name": "boxes", "polygons": boxes}],
         "lights": [{"name": "sun", "type": "directional", "to_light": place([0.3, 0.4, 0.8], False)},
                    {"name": "lamp", "type": "point", "position": place([2, 3, 25])}]}
json.dump(scene, open(sys.argv[1], "w"))
PY

scenes=("$EXAMPLES/default/scene.json" "$EXAMPLES/area-light/scene.json" "$EXAMPLES/area-light/sun-disk.json"
        "$EXAMPLES/cityjson/scene.json" "$EXAMPLES/gallery/sun_and_lamp.json" "$WORK/rotated.json")
for scene in "${scenes[@]}"; do
  name=$(basename "$(dirname "$scene")")-$(basename "$scene" .json)
  [[ "$scene" == "$WORK"/* ]] && name=$(basename "$scene" .json)
  ok=1
  for t in 1 2; do
    if ! "$SHADOW" compute "$scene" -o "$WORK/$name-$t" --threads "$t" --quiet >"$WORK/$name-$t.log" 2>&1; then
      fail "$name" "--threads $t failed: $(head -c 300 "$WORK/$name-$t.log")"
      ok=0
    fi
  done
  ((ok)) || continue
  differ=""
  for f in "$WORK/$name-1"/*.vtp "$WORK/$name-1"/*.vtm; do
    cmp -s "$f" "$WORK/$name-2/$(basename "$f")" || differ+=" $(basename "$f")"
  done
  if ! cmp -s <(python3 -c 'import json,sys; print(json.dumps(json.load(open(sys.argv[1]))["faces"]))' "$WORK/$name-1/report.json") \
              <(python3 -c 'import json,sys; print(json.dumps(json.load(open(sys.argv[1]))["faces"]))' "$WORK/$name-2/report.json"); then
    differ+=" report.json(faces)"
  fi
  if [[ -z "$differ" ]]; then
    pass "$name: the same bytes with 1 and 2 threads"
  else
    fail "$name" "differs between --threads 1 and 2:$differ"
  fi
done

cli_test_end
