#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow radiosity` (docs/radiosity.md): the furnace (a closed room whose faces all emit E and
# reflect rho has radiosity E / (1 - rho) everywhere) through the CLI, radiosity.vtp's arrays,
# report.json's balance, and bad input (one line naming file and place, exit 2, no report);
# `shadow render --radiosity` on a small room and its refusals.
#
# Usage: bash test_cli_radiosity.sh /path/to/shadow
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-radiosity 1 "SHADOW_BINARY" "$@"
SHADOW=$1

# A 2 x 1 x 1.5 room, fronts inward, every face emitting 10 W/m^2 and reflecting 0.6.
cat >"$WORK/furnace.json" <<'JSON'
{"materials": [{"name": "grey", "reflectance": 0.6, "emittance": 10}],
 "meshes": [{"name": "room", "material": "grey", "polygons": [
   [[0,0,1.5],[0,1,1.5],[2,1,1.5],[2,0,1.5]],
   [[2,0,0],[2,1,0],[0,1,0],[0,0,0]],
   [[0,0,0],[0,0,1.5],[2,0,1.5],[2,0,0]],
   [[0,1,0],[2,1,0],[2,1,1.5],[0,1,1.5]],
   [[2,0,0],[2,0,1.5],[2,1,1.5],[2,1,0]],
   [[0,0,0],[0,1,0],[0,1,1.5],[0,0,1.5]]]}]}
JSON
if "$SHADOW" radiosity "$WORK/furnace.json" -o "$WORK/out" --max-element-area 0.25 --tolerance 1e-4 -t 2 \
     >"$WORK/run.stdout" 2>"$WORK/run.stderr"; then
  pass furnace_runs
else
  fail furnace_runs "$(cat "$WORK/run.stderr")"
fi
if python3 - "$WORK/out/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["summary"]
assert s["converged"] and s["unshot_fraction"] <= 1e-4, s
b = s["balance"]
assert abs(b["emitted_W"] + b["direct_W"] - b["absorbed_W"] - b["escaped_W"] - b["unshot_W"]) <= 1e-9 * b["emitted_W"], b
assert len(r["faces"]) == 6
for f in r["faces"]:
    assert abs(f["radiosity"] - 25.0) < 0.02 * 25.0, f
    assert abs(f["radiosity"] - (10 + 0.6 * f["irradiance"])) < 1e-9 * f["radiosity"], f
PY
then pass furnace_report; else fail furnace_report "report.json"; fi
if grep -aq 'Name="radiosity"' "$WORK/out/radiosity.vtp" && grep -aq 'Name="irradiance"' "$WORK/out/radiosity.vtp" &&
   grep -aq 'Name="face_id"' "$WORK/out/radiosity.vtp" && grep -aq 'Name="element_id"' "$WORK/out/radiosity.vtp"; then
  pass vtp_arrays
else
  fail vtp_arrays "radiosity.vtp lacks an array"
fi
grep -q "balance (W): emitted" "$WORK/run.stdout" && pass summary || fail summary "$(cat "$WORK/run.stdout")"
# scene.vtm opens the elements and the lights in one step.
if grep -q 'name="radiosity" file="radiosity.vtp"' "$WORK/out/scene.vtm" &&
   grep -q 'name="lights" file="lights.vtp"' "$WORK/out/scene.vtm" && [[ -s "$WORK/out/lights.vtp" ]]; then
  pass scene_vtm
else
  fail scene_vtm "$(cat "$WORK/out/scene.vtm" 2>&1)"
fi
# The hierarchical method on the same room: the same furnace within its error, its keys.
"$SHADOW" radiosity "$WORK/furnace.json" -o "$WORK/out-h" --method hierarchical --max-element-area 0.05 \
  --tolerance 1e-4 -t 2 >"$WORK/run-h.stdout" 2>&1
if python3 - "$WORK/out-h/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["summary"]
assert s["method"] == "hierarchical" and s["iterations"] > 0 and s["near_links"] > 0, s
assert r["run"]["options"]["method"] == "hierarchical", r["run"]
for f in r["faces"]:
    assert abs(f["radiosity"] - 25.0) < 0.03 * 25.0, f
    assert f["direct_irradiance_by_light"] == [], f
PY
then pass hierarchical; else fail hierarchical "$(cat "$WORK/run-h.stdout")"; fi
grep -q "hierarchical: .* near and .* far links" "$WORK/run-h.stdout" && pass hierarchical_summary ||
  fail hierarchical_summary "$(cat "$WORK/run-h.stdout")"
# Adaptive refinement: a box on a sunlit floor, split where the reflected light rises into the
# corners; report.json says how far, the summary line too; refused with the hierarchical method.
cat >"$WORK/box.json" <<'JSON'
{"materials": [{"name": "m", "reflectance": 0.5}],
 "meshes": [{"name": "floor", "material": "m", "polygons": [[[-3,-3,0],[5,-3,0],[5,5,0],[-3,5,0]]]},
            {"name": "box", "material": "m", "polygons": [
   [[0,0,2],[2,0,2],[2,2,2],[0,2,2]], [[0,0,0],[2,0,0],[2,0,2],[0,0,2]], [[2,0,0],[2,2,0],[2,2,2],[2,0,2]],
   [[2,2,0],[0,2,0],[0,2,2],[2,2,2]], [[0,2,0],[0,0,0],[0,0,2],[0,2,2]]]}],
 "lights": [{"name": "sun", "type": "directional", "to_light": [0.4, 0.3, 0.85], "intensity": 1000}]}
JSON
"$SHADOW" radiosity "$WORK/box.json" -o "$WORK/out-r" --max-element-area 0.5 --patch-area 2 --tolerance 1e-4 \
  --refine-tolerance 0.005 --refine-passes 4 -t 2 >"$WORK/run-r.stdout" 2>"$WORK/run-r.stderr"
if python3 - "$WORK/out-r/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["summary"]
assert s["initial_elements"] == 238 and s["elements"] > 2 * 238 and 1 <= s["refine_passes"] <= 4, s
assert 0 < s["discretization_error"] <= 0.005, s
assert r["run"]["options"]["refine_tolerance"] == 0.005 and r["run"]["options"]["refine_passes"] == 4, r["run"]
assert sum(f["elements"] for f in r["faces"]) == s["elements"]
PY
then pass refine; else fail refine "$(cat "$WORK/run-r.stderr" "$WORK/run-r.stdout")"; fi
grep -q "adaptive refinement: 238 -> .* elements in .* passes" "$WORK/run-r.stdout" && pass refine_summary ||
  fail refine_summary "$(cat "$WORK/run-r.stdout")"
python3 -c 'import json, sys; assert json.load(open(sys.argv[1]))["summary"]["discretization_error"] is None' \
  "$WORK/out/report.json" && pass refine_off_null || fail refine_off_null "discretization_error without refinement"
"$SHADOW" radiosity "$WORK/box.json" -o "$WORK/out-rh" --method hierarchical --refine-tolerance 0.01 \
  >/dev/null 2>"$WORK/run-rh.stderr"
status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/run-rh.stderr") -eq 1 ]] && grep -q "refine_tolerance" "$WORK/run-rh.stderr" &&
   [[ ! -e "$WORK/out-rh/report.json" ]]; then
  pass refine_hierarchical_refused
else
  fail refine_hierarchical_refused "status $status: $(cat "$WORK/run-rh.stderr")"
fi

# A reflectance of 1: one line naming the file and the place, exit 2, nothing written.
sed 's/"reflectance": 0.6/"reflectance": 1/' "$WORK/furnace.json" >"$WORK/bad.json"
status=0
"$SHADOW" radiosity "$WORK/bad.json" -o "$WORK/out-bad" >"$WORK/bad.stdout" 2>"$WORK/bad.stderr" || status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/bad.stderr") -eq 1 &&
      $(cat "$WORK/bad.stderr") == "shadow: error: "*"bad.json"*"materials[0].reflectance"*"[0, 1)"* &&
      ! -e "$WORK/out-bad/report.json" ]]; then
  pass bad_reflectance
else
  fail bad_reflectance "status $status: $(cat "$WORK/bad.stderr")"
fi
status=0
"$SHADOW" radiosity "$WORK/furnace.json" -o "$WORK/out-bad" --max-element-area -1 >/dev/null 2>"$WORK/bad2.stderr" || status=$?
[[ $status -eq 2 && $(wc -l <"$WORK/bad2.stderr") -eq 1 ]] && pass bad_area || fail bad_area "status $status"

# A face that intersects itself: refused with the --skip-invalid hint, which radiosity now takes
# (it suggested a flag it did not have); the face is left out and listed in report.json.
python3 - "$WORK/furnace.json" "$WORK/bowtie.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["meshes"].append({"name": "bowtie", "polygons": [[[20, 0, 0], [21, 1, 0], [21, 0, 0], [20, 1, 0]]]})
json.dump(scene, open(sys.argv[2], "w"))
PY
status=0
"$SHADOW" radiosity "$WORK/bowtie.json" -o "$WORK/out-bowtie" >/dev/null 2>"$WORK/bowtie.stderr" || status=$?
if [[ $status -eq 2 && $(cat "$WORK/bowtie.stderr") == *"--skip-invalid"* ]] &&
   "$SHADOW" radiosity "$WORK/bowtie.json" -o "$WORK/out-bowtie" --skip-invalid --planarity-tolerance 1e-6 \
     >"$WORK/bowtie.stdout" 2>"$WORK/bowtie.stderr" &&
   grep -q "skipped: 1 invalid faces" "$WORK/bowtie.stdout" &&
   python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); sys.exit(0 if len(r["skipped_faces"]) == 1 and r["skipped_faces"][0]["mesh"] == "bowtie" else 1)' \
     "$WORK/out-bowtie/report.json"; then
  pass skip_invalid
else
  fail skip_invalid "status $status: $(cat "$WORK/bowtie.stderr")"
fi

# shadow render --radiosity (docs/radiosity.md, "Pictures"): a small Cornell-like room (the
# example without its boxes, about 0.1 s to solve), drawn by radiosity and in colour; the PNG's
# size, its many colours, the red wall's pixels red; and the refusals (one line, exit 2).
if "$SHADOW" render --help >/dev/null 2>&1 && { [[ -n ${DISPLAY:-} ]] || command -v xvfb-run >/dev/null; }; then
  cat >"$WORK/room.json" <<'JSON'
{"materials": [{"name": "white", "reflectance": [0.75, 0.75, 0.75]},
               {"name": "red", "reflectance": [0.63, 0.06, 0.04]},
               {"name": "green", "reflectance": [0.15, 0.48, 0.09]}],
 "meshes": [
  {"name": "floor", "material": "white", "polygons": [[[0, 0, 0], [5, 0, 0], [5, 5, 0], [0, 5, 0]]]},
  {"name": "ceiling", "material": "white", "polygons": [[[0, 0, 5], [0, 5, 5], [5, 5, 5], [5, 0, 5]]]},
  {"name": "back", "material": "white", "polygons": [[[0, 5, 0], [5, 5, 0], [5, 5, 5], [0, 5, 5]]]},
  {"name": "front", "material": "white", "polygons": [[[0, 0, 0], [0, 0, 5], [5, 0, 5], [5, 0, 0]]]},
  {"name": "left", "material": "red", "polygons": [[[0, 0, 0], [0, 5, 0], [0, 5, 5], [0, 0, 5]]]},
  {"name": "right", "material": "green", "polygons": [[[5, 0, 0], [5, 0, 5], [5, 5, 5], [5, 5, 0]]]}],
 "lights": [{"name": "lamp", "type": "area", "intensity": 100,
             "polygon": [[2, 2, 4.99], [2, 3, 4.99], [3, 3, 4.99], [3, 2, 4.99]]}]}
JSON
  "$SHADOW" radiosity "$WORK/room.json" -o "$WORK/room" --max-element-area 4 --tolerance 0.05 -t 2 -q ||
    fail room_radiosity "shadow radiosity failed on the room"
  camera=(--eye 2.5,-9,3 --target 2.5,2.5,2.5 --fov 40 --width 400 --height 300)
  for mode in radiosity colour; do
    if "$SHADOW" render "$WORK/room.json" --radiosity "$WORK/room" --radiosity-mode $mode --smooth "${camera[@]}" \
         -o "$WORK/room-$mode.png" >"$WORK/render-$mode.stdout" 2>"$WORK/render-$mode.stderr" &&
       grep -q "elements of .*radiosity.vtp coloured by $mode (smooth)" "$WORK/render-$mode.stdout"; then
      pass "render_radiosity_$mode"
    else
      fail "render_radiosity_$mode" "$(cat "$WORK/render-$mode.stderr" "$WORK/render-$mode.stdout")"
    fi
  done
  # The PNGs read back: 400 x 300, many colours; in colour the red wall (x = 0) is red where the
  # camera sees its middle (the projection written here: eye (2.5, -9, 3), 40 degrees).
  if /usr/bin/python3 - "$WORK/room-radiosity.png" "$WORK/room-colour.png" <<'PY'
import math, sys
import vtk
def pixels(path):
    r = vtk.vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    image = r.GetOutput()
    w, h, _ = image.GetDimensions()
    s = image.GetPointData().GetScalars()
    assert (w, h) == (400, 300), (path, w, h)
    return w, h, lambda x, y: tuple(int(s.GetComponent((h - 1 - y) * w + x, c)) for c in range(3))
def project(p, w, h, eye=(2.5, -9.0, 3.0), target=(2.5, 2.5, 2.5), fov=40.0):
    sub = lambda a, b: [a[i] - b[i] for i in range(3)]
    dot = lambda a, b: sum(a[i] * b[i] for i in range(3))
    cross = lambda a, b: [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    unit = lambda a: [c / math.sqrt(dot(a, a)) for c in a]
    f = unit(sub(target, eye)); r = unit(cross(f, [0, 0, 1])); u = cross(r, f)
    o = sub(p, eye); d = dot(o, f); t = math.tan(math.radians(fov) / 2)
    return int(0.5 * (dot(o, r) / (d * t * w / h) + 1) * w), int((1 - 0.5 * (dot(o, u) / (d * t) + 1)) * h)
for path in sys.argv[1:]:
    w, h, at = pixels(path)
    colours = {at(x, y) for x in range(0, w, 4) for y in range(0, h, 4)}
    assert len(colours) > 30, (path, len(colours))
w, h, at = pixels(sys.argv[2])
red = at(*project((0.0, 3.0, 2.5), w, h))
green = at(*project((5.0, 3.0, 2.5), w, h))
assert red[0] > red[1] + 80 and red[0] > red[2] + 80, red
assert green[1] > green[0] + 50 and green[1] > green[2] + 50, green
print("red wall", red, "green wall", green)
PY
  then pass render_radiosity_png; else fail render_radiosity_png "the pictures' size or colours"; fi
  render_refused() {  # NAME MESSAGE IMAGE ARGS...: one line naming the problem, exit 2, no image
    local name=$1 message=$2 image=$3 status=0
    shift 3
    "$SHADOW" render "$@" -o "$WORK/$image" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
    if [[ $status -eq 2 && $(wc -l <"$WORK/$name.stderr") -eq 1 && $(cat "$WORK/$name.stderr") == *"$message"* &&
          ! -e "$WORK/$image" ]]; then
      pass "$name"
    else
      fail "$name" "status $status: $(cat "$WORK/$name.stderr")"
    fi
  }
  mkdir -p "$WORK/empty" "$WORK/out-kind"
  echo '{"kind": "irradiance", "faces": []}' >"$WORK/out-kind/report.json"
  render_refused render_radiosity_no_result "empty/radiosity.vtp: not found: give the OUTDIR of \`shadow radiosity\`" \
    none.png "$WORK/room.json" --radiosity "$WORK/empty"
  render_refused render_radiosity_other_kind "report.json: kind: not the report of \`shadow radiosity\`" \
    kind.png "$WORK/room.json" --radiosity "$WORK/out-kind"
  render_refused render_radiosity_other_scene "faces[0].mesh: face 0 is of mesh \"floor\" in the result but of mesh \"room\"" \
    other.png "$WORK/furnace.json" -q --radiosity "$WORK/room"
  render_refused render_radiosity_vector "--radiosity: draws a PNG picture" view.svg "$WORK/room.json" \
    --radiosity "$WORK/room"
  render_refused render_smooth_alone "--smooth: applies to a radiosity picture only" alone.png "$WORK/room.json" --smooth
else
  echo "skip render_radiosity: no shadow render or no display"
fi

cli_test_end
