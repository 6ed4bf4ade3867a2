#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow compute` with a 0.53-degree sun disk whose to_light is 1e200 or 1e-200 times a
# direction (valid input: only its direction counts, docs/scene-format.md): exit 0, and report.json's
# fully lit / penumbra / umbra areas equal those of the unit direction to 1e-9
# (docs/area-light-visibility.md; the frame's squared lengths once overflowed to a crash).
#
# Usage: bash test_cli_extended_scale.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-extended 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
EXAMPLES=$2

for scale in 1 1e200 1e-200; do
  python3 - "$EXAMPLES/area-light/sun-disk.json" "$WORK/scene-$scale.json" "$scale" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scale = float(sys.argv[3])
for light in scene["lights"]:
    light["to_light"] = [c * scale for c in light["to_light"]]
json.dump(scene, open(sys.argv[2], "w"))
PY
  status=0
  "$SHADOW" compute "$WORK/scene-$scale.json" -o "$WORK/out-$scale" -t 2 >"$WORK/$scale.stdout" 2>"$WORK/$scale.stderr" ||
    status=$?
  if [[ $status -eq 0 && -s "$WORK/out-$scale/fragments.vtp" ]]; then
    pass "compute_sun_disk_scale_$scale"
  else
    fail "compute_sun_disk_scale_$scale" "status $status: $(head -c 300 "$WORK/$scale.stderr")"
  fi
done

for scale in 1e200 1e-200; do
  if python3 - "$WORK/out-1/report.json" "$WORK/out-$scale/report.json" <<'PY'
import json, sys
def areas(path):
    out = []
    def walk(node):
        if isinstance(node, dict):
            for key, value in sorted(node.items()):
                if key in ("fully_lit_area", "penumbra_area", "umbra_area", "lit_area"):
                    out.append(value)
                else:
                    walk(value)
        elif isinstance(node, list):
            for item in node:
                walk(item)
    walk(json.load(open(path)))
    return out
a, b = areas(sys.argv[1]), areas(sys.argv[2])
assert a and len(a) == len(b), (len(a), len(b))
assert all(abs(x - y) <= 1e-9 * max(1.0, abs(x)) for x, y in zip(a, b)), list(zip(a, b))
assert any(x > 0 for x in a)
PY
  then pass "report_areas_scale_$scale"; else fail "report_areas_scale_$scale" "areas differ from the unit direction's"; fi
done

cli_test_end
