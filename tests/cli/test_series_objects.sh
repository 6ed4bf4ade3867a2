#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Sun hours per building (docs/series.md, docs/cityjson.md): `shadow series` writes
# sun_hours_by_object.csv and report.json's series.objects, one row per CityJSON top-level city
# object (a Building's BuildingParts rolled up into it, even when the Building has no geometry of
# its own), per EnergyPlus zone, per other mesh; each the area-weighted mean of its receiving
# faces' sun hours. Checked against report.json's own faces.
#
# Usage: bash test_series_objects.sh /path/to/shadow
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin series-objects 1 "SHADOW_BINARY" "$@"
SHADOW=$1

# A Building without geometry and its two BuildingParts (boxes 6 m and 12 m high), a Building
# with geometry of its own, a TINRelief ground; and a scene file that puts a day of suns on them
# beside a plain mesh (a pole).
python3 - "$WORK" <<'PY'
import json, sys
work = sys.argv[1]
vertices = []
def box(x0, y0, x1, y1, h):
    """Walls and roof (no ground surface), outward, as a MultiSurface in millimetres."""
    corners = {}
    def v(x, y, z):
        key = (x, y, z)
        if key not in corners:
            corners[key] = len(vertices)
            vertices.append([x * 1000, y * 1000, z * 1000])
        return corners[key]
    rings = [[(x0, y0, 0), (x1, y0, 0), (x1, y0, h), (x0, y0, h)],
             [(x1, y0, 0), (x1, y1, 0), (x1, y1, h), (x1, y0, h)],
             [(x1, y1, 0), (x0, y1, 0), (x0, y1, h), (x1, y1, h)],
             [(x0, y1, 0), (x0, y0, 0), (x0, y0, h), (x0, y1, h)],
             [(x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h)]]
    return {"type": "MultiSurface", "lod": "2",
            "boundaries": [[[v(*p) for p in ring]] for ring in rings],
            "semantics": {"surfaces": [{"type": "WallSurface"}, {"type": "RoofSurface"}],
                          "values": [0, 0, 0, 0, 1]}}
objects = {
    "B1": {"type": "Building", "children": ["B1-part-low", "B1-part-high"]},
    "B1-part-low": {"type": "BuildingPart", "parents": ["B1"], "geometry": [box(0, 0, 10, 10, 6)]},
    "B1-part-high": {"type": "BuildingPart", "parents": ["B1"], "geometry": [box(11, 0, 21, 10, 12)]},
    "B2": {"type": "Building", "geometry": [box(0, 20, 8, 28, 9)]},
}
ground = [v for v in [(-20, -20), (40, -20), (40, 40), (-20, 40)]]
first = len(vertices)
vertices += [[x * 1000, y * 1000, 0] for x, y in ground]
objects["T"] = {"type": "TINRelief", "geometry": [{"type": "CompositeSurface", "lod": "1",
                                                   "boundaries": [[[first, first + 1, first + 2, first + 3]]]}]}
city = {"type": "CityJSON", "version": "2.0",
        "transform": {"scale": [0.001, 0.001, 0.001], "translate": [0, 0, 0]},
        "CityObjects": objects, "vertices": vertices}
json.dump(city, open(work + "/city.city.json", "w"))
pole = [[[30, 30, 0], [31, 30, 0], [31, 30, 5], [30, 30, 5]]]
scene = {"meshes": [{"name": "city", "file": "city.city.json"}, {"name": "pole", "polygons": pole}],
         "sun": {"latitude": 52.0, "longitude": 4.4, "time_zone": "UTC+01:00",
                 "start": "2026-03-20", "end": "2026-03-20", "step_minutes": 60}}
json.dump(scene, open(work + "/scene.json", "w"))
PY

# Two zones of an IDF, one with a window in its south wall (the wall comes in pieces).
cat >"$WORK/model.idf" <<'IDF'
Version, 9.6;
Building, Two zones, 0;
Site:Location, Chicago, 41.98, -87.92, -6, 190;
RunPeriod, Year, 1, 1, , 12, 31, , Sunday;
Timestep, 1;
GlobalGeometryRules, UpperLeftCorner, Counterclockwise, Relative;
Zone, West;
Zone, East;
BuildingSurface:Detailed, W:South, Wall, C, West, , Outdoors, , SunExposed, WindExposed, , 4,
  0,0,3, 0,0,0, 10,0,0, 10,0,3;
BuildingSurface:Detailed, W:West, Wall, C, West, , Outdoors, , SunExposed, WindExposed, , 4,
  0,8,3, 0,8,0, 0,0,0, 0,0,3;
BuildingSurface:Detailed, W:Roof, Roof, C, West, , Outdoors, , SunExposed, WindExposed, , 4,
  0,8,3, 0,0,3, 10,0,3, 10,8,3;
FenestrationSurface:Detailed, W:South:Win, Window, G, W:South, , , , 1, 4,
  2,0,2.5, 2,0,1, 8,0,1, 8,0,2.5;
BuildingSurface:Detailed, E:South, Wall, C, East, , Outdoors, , SunExposed, WindExposed, , 4,
  10,0,6, 10,0,0, 20,0,0, 20,0,6;
BuildingSurface:Detailed, E:East, Wall, C, East, , Outdoors, , SunExposed, WindExposed, , 4,
  20,0,6, 20,0,0, 20,8,0, 20,8,6;
BuildingSurface:Detailed, E:Roof, Roof, C, East, , Outdoors, , SunExposed, WindExposed, , 4,
  10,8,6, 10,0,6, 20,0,6, 20,8,6;
IDF

# check.py DIR KIND: the CSV and report.json's series.objects against report.json's faces.
cat >"$WORK/check.py" <<'PY'
import csv, json, math, sys
out, kind = sys.argv[1], sys.argv[2]
report = json.load(open(out + "/report.json"))
with open(out + "/sun_hours_by_object.csv", newline="") as f:
    raw = f.read()
assert raw.endswith("\r\n"), "CRLF line ends"
rows = list(csv.reader(raw.splitlines()))
assert rows[0] == ["object", "type", "faces", "area", "sun_hours", "sunlit_area_hours"], rows[0]
table = {r[0]: r[1:] for r in rows[1:]}
objects = {o["id"]: o for o in report["series"]["objects"]}
if kind == "city":
    expected = {"city/B1": "Building", "city/B2": "Building", "city/T": "TINRelief", "pole": "mesh"}
    parts = {"city/B1": {"city/B1-part-low", "city/B1-part-high"}, "city/B2": {"city/B2"},
             "city/T": {"city/T"}, "pole": {"pole"}}
else:
    expected = {"West": "zone", "East": "zone"}
    parts = {"West": {"West"}, "East": {"East"}}
assert [r[0] for r in rows[1:]] == list(expected), [r[0] for r in rows[1:]]
assert list(objects) == list(expected), list(objects)
faces = report["faces"]
for name, type_ in expected.items():
    mine = [f for f in faces if f["mesh"] in parts[name]]
    assert all(f["object"] == name for f in mine), name
    area = sum(f["area"] for f in mine)
    mean = sum(f["area"] * f["sun_hours"] for f in mine) / area
    t, n, a, h, ah = table[name]
    o = objects[name]
    assert t == type_ and o["type"] == type_, (name, t, o["type"])
    assert int(n) == len(mine) == o["face_count"], (name, n, len(mine))
    assert set(o["meshes"]) == parts[name], o["meshes"]
    # The CSV holds report.json's doubles, shortest round trip.
    assert float(a) == o["area"] and float(h) == o["sun_hours"] and float(ah) == o["sunlit_area_hours"], name
    assert math.isclose(float(a), area, rel_tol=1e-13), (name, a, area)
    assert math.isclose(float(h), mean, rel_tol=1e-12), (name, h, mean)
    assert math.isclose(float(ah), float(h) * float(a), rel_tol=1e-12), (name, ah)
    assert 0 < float(h) <= report["series"]["above_horizon"] * report["series"]["hours_per_instant"], (name, h)
if kind == "city":
    # The high part's roof is never shaded: its hours are every instant above the horizon.
    roof = [f for f in faces if f["mesh"] == "city/B1-part-high" and f["kind"] == "RoofSurface"]
    assert len(roof) == 1 and roof[0]["sun_hours"] == report["series"]["above_horizon"], roof
    # The low part's east wall is in the high part's shadow all morning: the building's mean is
    # below the mean of its parts taken alone would be for an open box.
    assert int(table["city/B1"][1]) == 10
else:
    west = [f for f in faces if f["mesh"] == "West"]
    assert len(west) > 3, "the south wall comes in pieces around its window"
print("ok")
PY

"$SHADOW" series "$WORK/scene.json" -o "$WORK/city" --every 0 >"$WORK/city.out" 2>"$WORK/city.err" ||
  fail "city series" "exit $?: $(cat "$WORK/city.err")"
if msg=$(python3 "$WORK/check.py" "$WORK/city" city 2>&1); then pass "CityJSON: per building, parts rolled up"; else
  fail "CityJSON: per building" "$msg"; fi
if grep -q 'sun_hours_by_object.csv' "$WORK/city.out"; then pass "the summary names the CSV"; else
  fail "the summary names the CSV" "$(cat "$WORK/city.out")"; fi

"$SHADOW" series "$WORK/model.idf" -o "$WORK/idf" --from 2023-06-21 --to 2023-06-21 --step 60 --every 0 \
  >"$WORK/idf.out" 2>"$WORK/idf.err" || fail "IDF series" "exit $?: $(cat "$WORK/idf.err")"
if msg=$(python3 "$WORK/check.py" "$WORK/idf" zones 2>&1); then pass "EnergyPlus: per zone"; else
  fail "EnergyPlus: per zone" "$msg"; fi

# A part whose parent is not in the file is its own object, with one warning; `parents` that is
# not an array of ids is an error naming it (exit 2, no report.json).
python3 - "$WORK" <<'PY'
import json, sys
work = sys.argv[1]
city = json.load(open(work + "/city.city.json"))
city["CityObjects"]["B2"]["parents"] = ["gone"]
json.dump(city, open(work + "/lost.city.json", "w"))
city["CityObjects"]["B2"]["parents"] = "B1"
json.dump(city, open(work + "/bad.city.json", "w"))
for name in ("lost", "bad"):
    scene = json.load(open(work + "/scene.json"))
    scene["meshes"][0]["file"] = name + ".city.json"
    json.dump(scene, open(work + "/" + name + ".json", "w"))
PY
"$SHADOW" series "$WORK/lost.json" -o "$WORK/lost" --every 0 >"$WORK/lost.out" 2>"$WORK/lost.err" ||
  fail "lost parent" "exit $?: $(cat "$WORK/lost.err")"
if grep -q 'CityObjects\["B2"\].parents: 1 city object names a parent that is not in CityObjects' "$WORK/lost.err" &&
  grep -q '^city/B2,Building,5,' "$WORK/lost/sun_hours_by_object.csv"; then pass "a lost parent: a warning, its own object"; else
  fail "a lost parent" "$(cat "$WORK/lost.err") $(cat "$WORK/lost/sun_hours_by_object.csv" 2>&1)"; fi
"$SHADOW" series "$WORK/bad.json" -o "$WORK/bad" --every 0 >"$WORK/bad.out" 2>"$WORK/bad.err"
code=$?
if [[ $code -eq 2 && $(wc -l <"$WORK/bad.err") -eq 1 ]] &&
  grep -q '^shadow: error: .*bad.city.json: CityObjects\["B2"\].parents: expected an array of city object ids' "$WORK/bad.err" &&
  [[ ! -e "$WORK/bad/report.json" ]]; then pass "malformed parents: one error line, exit 2"; else
  fail "malformed parents" "exit $code: $(cat "$WORK/bad.err")"; fi

cli_test_end
