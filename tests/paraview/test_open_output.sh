#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# tools/paraview/open_result.py opens what the `shadow` command line writes, one kind of OUTDIR
# per call: the CLI makes it, the script opens it headless (pvpython), saves a screenshot and
# describes its views; then the views must be the kind's (their colour bars by title), the model
# framed and clear of the bars (check_layout.py), and the picture must show the colour maps.
# Kinds:
#   series        shadow series (series.pvd): faces by sun hours | instants by lit fraction
#   series-map    shadow series --sun-hours-map: the same and the exact sun-hours map
#   series-faces  shadow series --every 0 (no series.pvd): faces by sun hours alone
#   area-light    shadow compute on an area light: fragments by visible part | faces by lit fraction
#   irradiance    shadow irradiance on a block and its ground under a weather day written here:
#                 faces by total irradiation (legend "kWh/m²")
#   irradiance-map  the same with --map ground: faces | the irradiation map, on one scale
#   radiosity     shadow radiosity on a small red-and-green room: elements by radiosity (legend "W/m²")
# (`shadow compute` with a sun: paraview_opens_default_result; a sun's disk: paraview_visibility_view.)
# Usage: test_open_output.sh SOURCE_DIR SHADOW_BINARY WORK_DIR KIND
set -euo pipefail
source_dir="$1" shadow="$2" work="$3" kind="$4"
rm -rf "$work"
mkdir -p "$work"
# irradiance_inputs DIR: a 6 m block on a ground square, and one June day of weather (EPW) at
# 48 N: DNI 600 and DHI 100 Wh/m2 from hour 6 to hour 19 (as tests/cli/test_cli_irradiance.sh).
irradiance_inputs() {
  /usr/bin/python3 - "$1/day.epw" <<'PY'
import sys
lines = ["LOCATION,Testtown,XX,FRA,test,000001,48.0,2.0,1.0,0.0", "DESIGN CONDITIONS,0",
         "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0", "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
         "COMMENTS 1,written by test_open_output.sh", "COMMENTS 2,", "DATA PERIODS,1,1,Data,Monday, 6/21,6/21"]
for h in range(1, 25):
    dni, dhi = (600, 100) if 6 <= h <= 19 else (0, 0)
    lines.append(f"2021,6,21,{h},60,x,15,10,70,100000,0,0,300,9999,{dni},{dhi},0,0,0,0,180,2,5,5,20,77777,9,"
                 f"999999999,10,0.1,0,88,0.2,0,0")
open(sys.argv[1], "w").write("\r\n".join(lines) + "\r\n")
PY
  cat >"$1/scene.json" <<'JSON'
{"meshes": [
  {"name": "ground", "polygons": [{"name": "ground", "vertices": [[-10, -10, 0], [20, -10, 0], [20, 20, 0], [-10, 20, 0]]}]},
  {"name": "block", "polygons": [
    {"name": "roof", "vertices": [[0, 0, 8], [6, 0, 8], [6, 6, 8], [0, 6, 8]]},
    {"name": "south wall", "vertices": [[0, 0, 0], [6, 0, 0], [6, 0, 8], [0, 0, 8]]},
    {"name": "north wall", "vertices": [[6, 6, 0], [0, 6, 0], [0, 6, 8], [6, 6, 8]]},
    {"name": "east wall", "vertices": [[6, 0, 0], [6, 6, 0], [6, 6, 8], [6, 0, 8]]},
    {"name": "west wall", "vertices": [[0, 6, 0], [0, 0, 0], [0, 0, 8], [0, 6, 8]]}]}
]}
JSON
}
sun=(series "$source_dir/examples/sun/scene.json" -o "$work/result" -t 2 -q)
case "$kind" in
  series) "$shadow" "${sun[@]}" --every 4; bars='["sun hours"], ["lit fraction"]' ;;
  series-map) "$shadow" "${sun[@]}" --every 4 --sun-hours-map ground; bars='["sun hours"], ["lit fraction"], ["sun hours"]' ;;
  series-faces) "$shadow" "${sun[@]}" --every 0; bars='["sun hours"]' ;;
  irradiance|irradiance-map)
    irradiance_inputs "$work"
    map=()
    bars='["kWh/m\u00b2"]'
    if [[ $kind == irradiance-map ]]; then map=(--map ground); bars='["kWh/m\u00b2"], ["kWh/m\u00b2"]'; fi
    "$shadow" irradiance "$work/scene.json" --weather "$work/day.epw" -o "$work/result" -t 2 -q "${map[@]}" ;;
  radiosity)
    # examples/cornell_room.json without its boxes: about 0.1 s to solve.
    /usr/bin/python3 - "$source_dir/examples/cornell_room.json" "$work/room.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["meshes"] = [m for m in scene["meshes"] if "box" not in m["name"]]
json.dump(scene, open(sys.argv[2], "w"))
PY
    "$shadow" radiosity "$work/room.json" -o "$work/result" --max-element-area 4 --tolerance 0.05 -t 2 -q
    bars='["W/m\u00b2"]' ;;
  area-light) "$shadow" compute "$source_dir/examples/area-light/scene.json" -o "$work/result" -t 2 -q
              bars='["visible part"], ["lit fraction"]' ;;
  *) echo "unknown kind $kind" >&2; exit 2 ;;
esac
log="$work/log.txt"
status=0
"$source_dir/tools/paraview/pvpython.sh" "$source_dir/tools/paraview/open_result.py" "$work/result" \
  --screenshot "$work/view.png" --size 1200 500 --describe "$work/view.json" >"$log" 2>&1 || status=$?
if [[ $status -eq 2 ]] && grep -q "^pvpython.sh: no pvpython" "$log"; then
  cat "$log"
  exit 77  # ctest SKIP_RETURN_CODE: this machine has no ParaView Python
fi
cat "$log"
grep -q "^open_result: ok, wrote " "$log" || { echo "FAIL: open_result.py gave no verdict ($kind)"; exit 1; }
/usr/bin/python3 - "$work/view.json" "$work/view.png" "[$bars]" <<'PY'
import json
import sys

import vtk

layout = json.load(open(sys.argv[1]))
expected = json.loads(sys.argv[3])
titles = [[bar["title"] for bar in view["bars"]] for view in layout["views"]]
print(f"views and their colour bars: {titles}")
assert titles == expected, f"expected {expected}"
reader = vtk.vtkPNGReader()
reader.SetFileName(sys.argv[2])
reader.Update()
image = reader.GetOutput()
width, height, _ = image.GetDimensions()
assert (width, height) == (1200, 500), (width, height)
scalars = image.GetPointData().GetScalars()
# Every view shows a colour map: warm (Inferno) or the lit/shadowed colours, over a good part of it.
views = len(expected)
for v in range(views):
    coloured = total = 0
    for y in range(0, height, 2):
        for x in range(v * width // views, (v + 1) * width // views, 2):
            r, g, b = (int(scalars.GetComponent(y * width + x, c)) for c in range(3))
            total += 1
            coloured += max(r, g, b) - min(r, g, b) > 40
    share = coloured / total
    print(f"view {v}: coloured pixels {100 * share:.1f}%")
    assert share > 0.03, f"view {v} shows almost no colour map"
PY
/usr/bin/python3 "$source_dir/tests/paraview/check_layout.py" "$work/view.json" 0.3
echo "test_open_output: ok ($kind)"
