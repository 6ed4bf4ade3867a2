#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The journeys of issue 31 at the command line, where a result could be silently wrong:
# - energyplus-shading.csv names surfaces as EnergyPlus matches them (upper case) and is written
#   for an EnergyPlus model (or when asked: --energyplus-shading, "energyplus_shading": true),
#   not for a city or an OBJ scene; the summary says which files were written;
# - a CityJSON file whose "type" comes after 64 KiB is CityJSON, as SCENE and as a mesh file;
#   JSON that is no model, and an OBJ file without faces, are errors (one line, exit 2);
# - progress lines in a log (stderr not a terminal), every LIBSHADOW_PROGRESS_INTERVAL seconds
#   (30 by default; 0 here so that the test is fast), none with --quiet.
#
# Usage: bash test_cli_workflows.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-workflows 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
EXAMPLES=$(cd "$2" && pwd)

# expect_error NAME PART ARGS...: exit 2, exactly one line on stderr containing PART, no report.json.
expect_error() {
  local name=$1 part=$2
  shift 2
  local status=0
  "$SHADOW" "$@" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  if [[ $status -eq 2 && $(wc -l <"$WORK/$name.stderr") -eq 1 && $(cat "$WORK/$name.stderr") == "shadow: error: "*"$part"* ]] &&
     ! find "$WORK" -path "*out-$name*" -name report.json | grep -q .; then
    pass "$name"
  else
    fail "$name" "status $status: $(cat "$WORK/$name.stderr")"
  fi
}

# ---- the energy modeller: an IDF in, EnergyPlus-ready shading out ------------------------------
idf="$EXAMPLES/energyplus/box-office.idf"
status=0
"$SHADOW" series "$idf" -o "$WORK/idf" --from 2023-06-21 --to 2023-06-21 --every 0 -t 2 \
  >"$WORK/idf.stdout" 2>"$WORK/idf.stderr" || status=$?
[[ $status -eq 0 ]] && pass "series on an IDF" || fail "series on an IDF" "exit $status: $(cat "$WORK/idf.stderr")"
# EnergyPlus 9.6 upper-cases names and then matches the header case-sensitively.
header=$(head -n 1 "$WORK/idf/energyplus-shading.csv" 2>/dev/null | tr -d '\r')
expected="Surface Name,WALL-SOUTH,WINDOW-SOUTH,DOOR-SOUTH,WALL-EAST,WINDOW-EAST,WALL-NORTH,WALL-WEST,ROOF"
[[ $header == "$expected" ]] && pass "energyplus-shading.csv names in upper case" ||
  fail "energyplus-shading.csv names" "header: $header"
# sunlit.csv and report.json keep the model's own names.
sunlit=$(head -n 1 "$WORK/idf/sunlit.csv" | tr -d '\r')
[[ $sunlit == "time,Wall-South,Window-South,Door-South,"* ]] && grep -q '"name": "Wall-South"' "$WORK/idf/report.json" &&
  pass "sunlit.csv and report.json keep the model's names" || fail "model names" "$sunlit"
grep -q "^    energyplus-shading.csv$" "$WORK/idf.stdout" && grep -q "^    sunlit.csv$" "$WORK/idf.stdout" &&
  pass "summary lists energyplus-shading.csv" || fail "summary lists the files" "$(cat "$WORK/idf.stdout")"

# The same model as a mesh file of a scene with a sun block: still an EnergyPlus model.
python3 - "$EXAMPLES/energyplus/scene.json" "$WORK/placed.json" "$idf" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["meshes"][0]["file"] = sys.argv[3]
del scene["lights"]
scene["sun"] = {"latitude": 41.98, "longitude": -87.92, "time_zone": "UTC-06:00", "start": "2023-06-21",
                "end": "2023-06-21", "step_minutes": 60}
json.dump(scene, open(sys.argv[2], "w"))
PY
"$SHADOW" series "$WORK/placed.json" -o "$WORK/placed" --every 0 -t 2 -q 2>"$WORK/placed.stderr" ||
  fail "series on a scene with an IDF mesh" "exit $?: $(cat "$WORK/placed.stderr")"
[[ $(head -n 1 "$WORK/placed/energyplus-shading.csv" 2>/dev/null | tr -d '\r') == "$expected" ]] &&
  pass "an IDF as a mesh file gets energyplus-shading.csv" || fail "IDF mesh file" "$(ls "$WORK/placed")"

# ---- not an EnergyPlus model: no energyplus-shading.csv unless asked -------------------------------
sun="$EXAMPLES/sun/scene.json"
"$SHADOW" series "$sun" -o "$WORK/sun" --every 0 -t 2 >"$WORK/sun.stdout" 2>"$WORK/sun.stderr" ||
  fail "series on examples/sun" "exit $?"
if [[ ! -e "$WORK/sun/energyplus-shading.csv" && -f "$WORK/sun/sunlit.csv" ]] &&
   grep -q "no energyplus-shading.csv (not an EnergyPlus model; --energyplus-shading writes one)" "$WORK/sun.stdout" &&
   ! grep -q "^    energyplus-shading.csv" "$WORK/sun.stdout" &&
   python3 -c 'import json,sys; e=json.load(open(sys.argv[1]))["series"]["energyplus"]; assert not e["written"] and "not asked for" in e["note"], e' \
     "$WORK/sun/report.json"; then
  pass "no energyplus-shading.csv for a scene that is no EnergyPlus model"
else
  fail "unasked energyplus-shading.csv" "$(ls "$WORK/sun"): $(cat "$WORK/sun.stdout")"
fi
"$SHADOW" series "$sun" -o "$WORK/sun-asked" --every 0 -t 2 --energyplus-shading >"$WORK/sun-asked.stdout" 2>&1 ||
  fail "series --energyplus-shading" "exit $?"
[[ $(head -c 13 "$WORK/sun-asked/energyplus-shading.csv" 2>/dev/null) == "Surface Name," ]] &&
  grep -q "^    energyplus-shading.csv$" "$WORK/sun-asked.stdout" &&
  pass "--energyplus-shading writes it" || fail "--energyplus-shading" "$(ls "$WORK/sun-asked")"
python3 - "$sun" "$WORK/sun-key.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["energyplus_shading"] = True
json.dump(scene, open(sys.argv[2], "w"))
PY
"$SHADOW" series "$WORK/sun-key.json" -o "$WORK/sun-key" --every 0 -t 2 -q || fail "series with the scene key" "exit $?"
[[ -f "$WORK/sun-key/energyplus-shading.csv" ]] && pass "\"energyplus_shading\": true writes it" ||
  fail "scene key energyplus_shading" "$(ls "$WORK/sun-key")"
[[ $("$SHADOW" series --help) == *"--energyplus-shading"* ]] && pass "series --help lists --energyplus-shading" ||
  fail "series --help" "no --energyplus-shading"

# ---- the urban researcher: CityJSON recognised by parsing, not by a prefix ------------------------
# street.city.json as street.json with "type" last, after 64 KiB of attributes (as cjio may write
# a real city: Delft's "type" comes after 1.4 MB).
python3 - "$EXAMPLES/cityjson" "$WORK" <<'PY'
import json, sys
src, work = sys.argv[1], sys.argv[2]
city = json.load(open(src + "/street.city.json"))
del city["type"]
first = next(iter(city["CityObjects"]))
city["CityObjects"][first].setdefault("attributes", {})["padding"] = "x" * 70000
text = json.dumps(city)[:-1] + ', "type": "CityJSON"}'
assert text.find('"type": "CityJSON"') > 65536
open(work + "/street.json", "w").write(text)
scene = json.load(open(src + "/scene.json"))
scene["meshes"][0]["file"] = "street.json"
json.dump(scene, open(work + "/city-scene.json", "w"))
scene["meshes"][0]["file"] = src + "/street.city.json"
json.dump(scene, open(work + "/named-scene.json", "w"))
scene["sun"] = {"latitude": 52.0, "longitude": 4.36, "time_zone": "UTC+01:00", "start": "2026-06-21",
                "end": "2026-06-21", "step_minutes": 60}
del scene["lights"]
scene["meshes"][0]["file"] = "street.json"
json.dump(scene, open(work + "/city-sun.json", "w"))
PY
"$SHADOW" compute "$WORK/city-scene.json" -o "$WORK/city" -q --areas-only -t 2 2>"$WORK/city.stderr" ||
  fail "CityJSON as a mesh file" "exit $?: $(cat "$WORK/city.stderr")"
"$SHADOW" compute "$WORK/named-scene.json" -o "$WORK/named" -q --areas-only -t 2 || fail "street.city.json" "exit $?"
if python3 - "$WORK/city/report.json" "$WORK/named/report.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert len(a["faces"]) > 1 and len(a["faces"]) == len(b["faces"]), (len(a["faces"]), len(b["faces"]))
areas = [[l["lit_area"] for l in f["lights"]] for f in a["faces"]]
assert areas == [[l["lit_area"] for l in f["lights"]] for f in b["faces"]]
assert any(x > 0 for face in areas for x in face) and any(x == 0 for face in areas for x in face)
PY
then pass "CityJSON with \"type\" after 64 KiB as a mesh file: the same faces and areas"; else fail "late type mesh" "reports differ"; fi
# As SCENE: read as a model (which brings no lights), not as a scene with `unknown key "CityObjects"`.
expect_error city_as_scene "the scene has no lights (a model file carries none" compute "$WORK/street.json" -o "$WORK/out-city_as_scene"
# A CityJSON run writes no energyplus-shading.csv.
"$SHADOW" series "$WORK/city-sun.json" -o "$WORK/city-series" --every 0 -t 2 -q 2>"$WORK/city-series.stderr" ||
  fail "series on a city" "exit $?: $(cat "$WORK/city-series.stderr")"
[[ -f "$WORK/city-series/sunlit.csv" && ! -e "$WORK/city-series/energyplus-shading.csv" ]] &&
  pass "a CityJSON series writes no energyplus-shading.csv" || fail "city series files" "$(ls "$WORK/city-series")"
# JSON that is no model, and an OBJ without faces, are errors, not empty results.
echo '{"points": [[0, 0, 0]]}' >"$WORK/points.json"
printf 'v 0 0 0\nv 1 0 0\n' >"$WORK/empty.obj"
for mesh in points.json empty.obj; do
  python3 - "$EXAMPLES/cityjson/scene.json" "$WORK/with-$mesh.json" "$mesh" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["meshes"][0]["file"] = sys.argv[3]
json.dump(scene, open(sys.argv[2], "w"))
PY
done
expect_error json_mesh "meshes[0].file: \"$WORK/points.json\" is JSON but neither CityJSON" \
  compute "$WORK/with-points.json.json" -o "$WORK/out-json_mesh"
expect_error empty_obj "meshes[0].file: \"$WORK/empty.obj\" has no faces" compute "$WORK/with-empty.obj.json" -o "$WORK/out-empty_obj"

# ---- progress in a log ----------------------------------------------------------------------------
LIBSHADOW_PROGRESS_INTERVAL=0 "$SHADOW" series "$sun" -o "$WORK/progress" --every 0 -t 1 >/dev/null 2>"$WORK/progress.log" ||
  fail "series with progress" "exit $?"
lines=$(grep -c '^shadow: instants [0-9]*/[0-9]* ([0-9]*%)' "$WORK/progress.log")
if [[ $lines -ge 2 ]] && grep -q '^shadow: instants [0-9]*/[0-9]* ([0-9]*%), .*, about [0-9].* left$' "$WORK/progress.log" &&
   [[ $(tail -n 1 "$WORK/progress.log") == "shadow: instants "*"(100%)"* ]] && ! grep -q $'[\r\033]' "$WORK/progress.log"; then
  pass "series progress in a log: $lines lines, time left, 100% last"
else
  fail "series progress in a log" "$(cat "$WORK/progress.log")"
fi
"$SHADOW" series "$sun" -o "$WORK/progress-default" --every 0 -t 1 >/dev/null 2>"$WORK/progress-default.log" ||
  fail "series" "exit $?"
[[ ! -s "$WORK/progress-default.log" ]] && pass "a short run writes no progress line at the default interval" ||
  fail "default interval" "$(cat "$WORK/progress-default.log")"
LIBSHADOW_PROGRESS_INTERVAL=0 "$SHADOW" series "$sun" -o "$WORK/progress-quiet" --every 0 -t 1 -q >"$WORK/quiet.out" 2>&1 ||
  fail "series -q" "exit $?"
[[ ! -s "$WORK/quiet.out" ]] && pass "--quiet: no progress" || fail "--quiet" "$(cat "$WORK/quiet.out")"
LIBSHADOW_PROGRESS_INTERVAL=0 "$SHADOW" compute "$EXAMPLES/default/scene.json" -o "$WORK/compute" -t 1 >/dev/null \
  2>"$WORK/compute.log" || fail "compute with progress" "exit $?"
grep -q '^shadow: face-light pairs [0-9]*/[0-9]* (100%)' "$WORK/compute.log" && ! grep -q $'[\r\033]' "$WORK/compute.log" &&
  pass "compute progress in a log" || fail "compute progress in a log" "$(cat "$WORK/compute.log")"

cli_test_end
