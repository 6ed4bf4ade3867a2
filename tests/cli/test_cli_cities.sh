#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The urban researcher's journey on models of the shape real cities have (issue 31, items 7 and
# 9): one self-intersecting surface stops a city without --skip-invalid (the error says how to
# go on) and is skipped with it (a warning, a count in the summary and report.json); receivers
# and sun-hours maps chosen by CityJSON object type (`type:TINRelief`) and by `mesh/<id>`.
#
# Usage: bash test_cli_cities.sh /path/to/shadow
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-cities 1 "SHADOW_BINARY" "$@"
SHADOW=$1

# run NAME ARGS...: runs shadow, keeping stdout, stderr and the status in $WORK/NAME.*.
run() {
  local name=$1
  shift
  local status=0
  "$SHADOW" "$@" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  echo "$status" >"$WORK/$name.status"
}

# expect_error NAME RUN OUTDIR PART... (after `run RUN`): exit 2, one line with every PART, no report.json.
expect_error() {
  local name=$1 ran=$2 out=$3
  shift 3
  local stderr status part
  stderr=$(cat "$WORK/$ran.stderr")
  status=$(cat "$WORK/$ran.status")
  if [[ $status -ne 2 || $(wc -l <"$WORK/$ran.stderr") -ne 1 || $stderr != "shadow: error: "* || -e "$out/report.json" ]]; then
    fail "$name" "status $status: $stderr"
    return
  fi
  for part in "$@"; do
    if [[ $stderr != *"$part"* ]]; then
      fail "$name" "stderr lacks '$part': $stderr"
      return
    fi
  done
  pass "$name"
}

# check NAME PYTHON ARGS...: a Python check of files; pass when it exits 0.
check() {
  local name=$1 code=$2
  shift 2
  local output
  if output=$(python3 -c "$code" "$@" 2>&1); then pass "$name"; else fail "$name" "$output"; fi
}

# ---- an OBJ with one self-intersecting face between good ones ----------------------------------
mkdir -p "$WORK/obj"
cat >"$WORK/obj/m.obj" <<'OBJ'
o good
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
f 1 2 3 4
o bowtie
v 3 0 0
v 4 1 0
v 4 0 0
v 3 1 0
f 5 6 7 8
o after
v 6 0 0
v 7 0 0
v 6 1 0
f 9 10 11
OBJ
echo '{"meshes": [{"name": "m", "file": "m.obj"}], "lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]}' \
  >"$WORK/obj/scene.json"
run obj_bowtie compute "$WORK/obj/scene.json" -o "$WORK/out-obj"
expect_error obj_bowtie_stops_and_names_the_flag obj_bowtie "$WORK/out-obj" "m.obj: line 12: face boundary intersects itself" \
  "(--skip-invalid skips such faces"
run obj_skip compute "$WORK/obj/scene.json" -o "$WORK/out-obj" --skip-invalid
if [[ $(cat "$WORK/obj_skip.status") -eq 0 ]] &&
   grep -q 'line 12: skipped (--skip-invalid): the face "bowtie" (mesh "m") is invalid: face boundary intersects itself' \
     "$WORK/obj_skip.stderr" &&
   grep -q '^  skipped: 1 invalid faces (--skip-invalid; report.json: skipped_faces)' "$WORK/obj_skip.stdout"; then
  pass obj_skip_warns_and_counts
else
  fail obj_skip_warns_and_counts "$(cat "$WORK/obj_skip.stderr" "$WORK/obj_skip.stdout")"
fi
check obj_skip_report '
import json, sys
r = json.load(open(sys.argv[1]))
assert r["summary"]["skipped_faces"] == 1, r["summary"]
s = r["skipped_faces"]
assert len(s) == 1 and s[0]["name"] == "bowtie" and s[0]["mesh"] == "m", s
assert s[0]["reason"] == "face boundary intersects itself" and s[0]["source"].endswith("m.obj: line 12"), s
assert [f["id"] for f in r["faces"]] == [0, 1] and r["faces"][1]["name"] == "after", r["faces"]
' "$WORK/out-obj/report.json"

# ---- a CityJSON city: two buildings, a BuildingPart with a bow-tie surface, a terrain ----------
mkdir -p "$WORK/city"
cat >"$WORK/city/zurich-like.city.json" <<'CITY'
{"type": "CityJSON", "version": "2.0",
 "transform": {"scale": [0.001, 0.001, 0.001], "translate": [2683000, 1247000, 400]},
 "CityObjects": {
  "b1": {"type": "Building", "geometry": [{"type": "Solid", "lod": "2",
    "boundaries": [[[[0,3,2,1]], [[4,5,6,7]], [[0,1,5,4]], [[1,2,6,5]], [[2,3,7,6]], [[3,0,4,7]]]]}]},
  "p1": {"type": "BuildingPart", "geometry": [{"type": "MultiSurface", "lod": "2",
    "boundaries": [[[8,9,10,11]], [[12,13,14,15]]]}]},
  "t": {"type": "TINRelief", "geometry": [{"type": "MultiSurface", "lod": "1",
    "boundaries": [[[16,17,18,19]]]}]}},
 "vertices": [[0,0,0],[8000,0,0],[8000,6000,0],[0,6000,0],[0,0,9000],[8000,0,9000],[8000,6000,9000],[0,6000,9000],
              [20000,0,0],[22000,2000,0],[22000,0,0],[20000,2000,0],
              [30000,0,0],[32000,0,0],[32000,2000,0],[30000,2000,0],
              [-20000,-20000,-1],[60000,-20000,-1],[60000,30000,-1],[-20000,30000,-1]]}
CITY
cat >"$WORK/city/scene.json" <<'SCENE'
{"meshes": [{"name": "city", "file": "zurich-like.city.json"},
            {"name": "ground", "polygons": [[[2682900, 1246900, 398], [2683100, 1246900, 398], [2683100, 1247100, 398], [2682900, 1247100, 398]]]}],
 "sun": {"latitude": 47.37, "longitude": 8.54, "utc_offset": 1,
         "times": ["2024-06-21T09:00:00", "2024-06-21T12:00:00", "2024-06-21T15:00:00"]}}
SCENE
run city_series series "$WORK/city/scene.json" -o "$WORK/out-city" --quiet
expect_error city_bowtie_stops_and_names_the_flag city_series "$WORK/out-city" \
  'zurich-like.city.json: CityObjects["p1"].geometry[0].boundaries[0]: face boundary intersects itself' \
  "(--skip-invalid skips such faces"
run city_skip series "$WORK/city/scene.json" -o "$WORK/out-city" --skip-invalid --sun-hours-map type:TINRelief
if [[ $(cat "$WORK/city_skip.status") -eq 0 ]] &&
   grep -q 'skipped (--skip-invalid): the face "p1/0" (mesh "city/p1") is invalid' "$WORK/city_skip.stderr" &&
   grep -q '^  skipped: 1 invalid faces' "$WORK/city_skip.stdout" &&
   grep -q '^  sun-hours map: [0-9]* cells on 1 faces (sun_hours.vtp)' "$WORK/city_skip.stdout"; then
  pass city_skip_series_with_a_map_by_type
else
  fail city_skip_series_with_a_map_by_type "$(cat "$WORK/city_skip.stderr" "$WORK/city_skip.stdout")"
fi
# --energyplus-shading asked for on explicit sun times: one error before any computing, saying
# how to give a period instead.
run city_eplus_times series "$WORK/city/scene.json" -o "$WORK/out-eplus-times" --skip-invalid --energyplus-shading
expect_error energyplus_shading_on_explicit_times city_eplus_times "$WORK/out-eplus-times" \
  '--energyplus-shading: energyplus-shading.csv cannot be written for this run: the sun is given as explicit times' \
  '(--from and --to give a period instead)'
# The scene's mesh name of the model file on --sun-hours-map, as the scene's "sun_hours_map" takes
# it: every face of the model (the building's 6, the part's valid 1, the terrain's 1), not the ground.
run city_by_scene_mesh series "$WORK/city/scene.json" -o "$WORK/out-city-mesh" --skip-invalid --sun-hours-map city
if [[ $(cat "$WORK/city_by_scene_mesh.status") -eq 0 ]] &&
   grep -q '^  sun-hours map: [0-9]* cells on 8 faces (sun_hours.vtp)' "$WORK/city_by_scene_mesh.stdout"; then
  pass city_map_by_the_scene_mesh_of_a_model
else
  fail city_map_by_the_scene_mesh_of_a_model "$(cat "$WORK/city_by_scene_mesh.stderr" "$WORK/city_by_scene_mesh.stdout")"
fi
check city_skip_series_report '
import json, sys
r = json.load(open(sys.argv[1]))
assert r["series"]["skipped_faces"] == 1, r["series"]
assert [s["name"] for s in r["skipped_faces"]] == ["p1/0"], r["skipped_faces"]
names = [f["name"] for f in r["faces"]]
assert "p1/1" in names and "p1/0" not in names, names
' "$WORK/out-city/report.json"

# type: in receivers, and the scene key sun_hours_map with mesh/<id> and a scene mesh after a model.
python3 - "$WORK/city/scene.json" "$WORK/city" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
for name, extra in {"typed": {"receivers": ["type:TINRelief", "ground"], "sun_hours_map": ["city/t"]},
                    "ground": {"sun_hours_map": ["ground"]},
                    "bad_type": {"receivers": ["type:Bridge"]}}.items():
    json.dump(dict(scene, **extra), open(f"{sys.argv[2]}/{name}.json", "w"))
PY
run city_typed series "$WORK/city/typed.json" -o "$WORK/out-typed" --skip-invalid
if [[ $(cat "$WORK/city_typed.status") -eq 0 ]] &&
   grep -q '^  sun-hours map: [0-9]* cells on 1 faces' "$WORK/city_typed.stdout"; then
  pass scene_sun_hours_map_takes_mesh_slash_id
else
  fail scene_sun_hours_map_takes_mesh_slash_id "$(cat "$WORK/city_typed.stderr" "$WORK/city_typed.stdout")"
fi
check receivers_by_type '
import json, sys
r = json.load(open(sys.argv[1]))
labels = sorted(f["label"] for f in r["faces"])
assert labels == ["face_8", "t/0"], labels  # 6 box faces, p1/1 (p1/0 skipped), t/0, the ground
' "$WORK/out-typed/report.json"
# The scene's own mesh after a model's meshes: the map is on the ground, not on a city object.
run city_ground series "$WORK/city/ground.json" -o "$WORK/out-ground" --skip-invalid
if grep -q '^  sun-hours map: [0-9]* cells on 1 faces' "$WORK/city_ground.stdout"; then
  pass scene_sun_hours_map_ground_is_one_face
else
  fail scene_sun_hours_map_ground_is_one_face "$(cat "$WORK/city_ground.stderr" "$WORK/city_ground.stdout")"
fi
run bad_type compute "$WORK/city/bad_type.json" -o "$WORK/out-bad-type" --skip-invalid
expect_error unknown_type_in_receivers bad_type "$WORK/out-bad-type" 'bad_type.json: receivers[0]: the type "Bridge" selects no mesh' \
  "the object types present: Building, BuildingPart, TINRelief"
run bad_flag_type series "$WORK/city/scene.json" -o "$WORK/out-bad-flag" --skip-invalid --sun-hours-map type:Bridge
expect_error unknown_type_in_sun_hours_map_flag bad_flag_type "$WORK/out-bad-flag" 'scene.json: --sun-hours-map: the type "Bridge" selects no mesh' \
  "the object types present: Building, BuildingPart, TINRelief"

# The threshold map: --sun-hours-levels writes sun_hours_levels.vtp, the levels' exact areas in
# report.json and the summary; bad levels, and levels without a map, stop before computing.
run city_levels series "$WORK/city/scene.json" -o "$WORK/out-levels" --skip-invalid --sun-hours-map type:TINRelief \
  --sun-hours-levels 4,2
if [[ $(cat "$WORK/city_levels.status") -eq 0 && -s "$WORK/out-levels/sun_hours_levels.vtp" ]] &&
   grep -q '^  at least 2 h of sun: area [0-9.e+]* of [0-9.e+]* ([0-9.]*%)' "$WORK/city_levels.stdout" &&
   grep -q '^  threshold map: [0-9]* cells (sun_hours_levels.vtp)' "$WORK/city_levels.stdout"; then
  pass series_sun_hours_levels_written
else
  fail series_sun_hours_levels_written "$(cat "$WORK/city_levels.stderr" "$WORK/city_levels.stdout")"
fi
check series_sun_hours_levels_report '
import json, sys
m = json.load(open(sys.argv[1]))["sun_hours_map"]
assert [l["hours"] for l in m["levels"]] == [2, 4], m
assert m["levels_file"] == "sun_hours_levels.vtp" and m["faces"] == 1, m
a2, a4 = m["levels"][0]["area"], m["levels"][1]["area"]
assert 0 <= a4 <= a2 <= m["area"] * (1 + 1e-12), m
assert abs(m["levels"][0]["fraction"] - a2 / m["area"]) < 1e-12, m
' "$WORK/out-levels/report.json"
# --sun-hours-levels-only: the threshold map alone, into a copy of the full run's OUTDIR: no
# sun_hours.vtp (the full run's is removed), the same exact level areas to the last bit.
cp -r "$WORK/out-levels" "$WORK/out-levels-only"
run city_levels_only series "$WORK/city/scene.json" -o "$WORK/out-levels-only" --skip-invalid \
  --sun-hours-map type:TINRelief --sun-hours-levels 4,2 --sun-hours-levels-only
if [[ $(cat "$WORK/city_levels_only.status") -eq 0 && -s "$WORK/out-levels-only/sun_hours_levels.vtp" &&
      ! -e "$WORK/out-levels-only/sun_hours.vtp" ]] &&
   grep -q '^  sun-hours map: threshold map alone on 1 faces' "$WORK/city_levels_only.stdout" &&
   grep -q '^  threshold map: [0-9]* cells (sun_hours_levels.vtp)' "$WORK/city_levels_only.stdout"; then
  pass series_sun_hours_levels_only_written
else
  fail series_sun_hours_levels_only_written "$(cat "$WORK/city_levels_only.stderr" "$WORK/city_levels_only.stdout")"
fi
check series_sun_hours_levels_only_areas_match '
import json, sys
full = json.load(open(sys.argv[1]))["sun_hours_map"]
only = json.load(open(sys.argv[2]))["sun_hours_map"]
assert full["full"] is True and full["file"] == "sun_hours.vtp", full
assert only["full"] is False and only["file"] is None and only["cells"] == 0, only
assert only["levels"] == full["levels"], (only["levels"], full["levels"])
assert only["area"] == full["area"] and only["total_hours"] == full["total_hours"], only
' "$WORK/out-levels/report.json" "$WORK/out-levels-only/report.json"
# --sun-hours-held-segments 0: every lit region computed again, a wave and a band at a time; the
# same exact level areas to the last bit.
run city_levels_held series "$WORK/city/scene.json" -o "$WORK/out-levels-held" --skip-invalid \
  --sun-hours-map type:TINRelief --sun-hours-levels 4,2 --sun-hours-levels-only --sun-hours-held-segments 0
check series_sun_hours_held_segments_areas_match '
import json, sys
only = json.load(open(sys.argv[1]))["sun_hours_map"]
held = json.load(open(sys.argv[2]))["sun_hours_map"]
assert held["full"] is False and held["levels"] == only["levels"], (held["levels"], only["levels"])
' "$WORK/out-levels-only/report.json" "$WORK/out-levels-held/report.json"
run held_without_levels_only series "$WORK/city/scene.json" -o "$WORK/out-held-bad" --skip-invalid \
  --sun-hours-map type:TINRelief --sun-hours-levels 2 --sun-hours-held-segments 10
expect_error sun_hours_held_segments_needs_levels_only held_without_levels_only "$WORK/out-held-bad" \
  '--sun-hours-held-segments: applies to the threshold map alone'
for bad in -1 "" 99999999999999999999999 1e3; do
  run held_bad series "$WORK/city/scene.json" -o "$WORK/out-held-bad-value" --skip-invalid \
    --sun-hours-map type:TINRelief --sun-hours-levels 2 --sun-hours-levels-only --sun-hours-held-segments "$bad"
  expect_error "sun_hours_held_segments_rejects_${bad:-empty}" held_bad "$WORK/out-held-bad-value" \
    '--sun-hours-held-segments' "got \"$bad\""
done
run levels_only_without_levels series "$WORK/city/scene.json" -o "$WORK/out-levels-only-bad" --skip-invalid \
  --sun-hours-map type:TINRelief --sun-hours-levels-only
expect_error sun_hours_levels_only_needs_levels levels_only_without_levels "$WORK/out-levels-only-bad" \
  '--sun-hours-levels-only: needs levels'
run bad_levels series "$WORK/city/scene.json" -o "$WORK/out-bad-levels" --skip-invalid --sun-hours-map type:TINRelief \
  --sun-hours-levels 2,x
expect_error bad_sun_hours_level bad_levels "$WORK/out-bad-levels" '--sun-hours-levels item 2: expected a number of hours, got "x"'
# Given empty (a script's unset variable): an error, not a run without the levels.
run empty_levels series "$WORK/city/scene.json" -o "$WORK/out-empty-levels" --skip-invalid --sun-hours-map type:TINRelief \
  --sun-hours-levels ""
expect_error empty_sun_hours_levels empty_levels "$WORK/out-empty-levels" '--sun-hours-levels item 1: expected a number of hours, got ""'
run levels_without_map series "$WORK/city/scene.json" -o "$WORK/out-levels-no-map" --skip-invalid --sun-hours-levels 2
expect_error sun_hours_levels_need_a_map levels_without_map "$WORK/out-levels-no-map" '--sun-hours-levels: needs a sun-hours map'

# Every command that loads a scene takes the flag.
for command in compute series render; do
  if "$SHADOW" $command --help 2>/dev/null | grep -q -- '--skip-invalid'; then
    pass "${command}_help_lists_skip_invalid"
  elif [[ $command == render ]] && ! "$SHADOW" render --help >/dev/null 2>&1; then
    pass "render_not_built"
  else
    fail "${command}_help_lists_skip_invalid" "no --skip-invalid in shadow $command --help"
  fi
done

cli_test_end
