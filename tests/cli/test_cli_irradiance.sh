#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow irradiance` (docs/irradiance.md) on a weather day written here: the files, an open
# horizontal roof's direct irradiation against `shadow sun` at every mid-hour (DNI x sin
# elevation), its isotropic sky diffuse against the day's DHI, the energy check, --hourly, and
# bad input (one line, exit 2, nothing written).
#
# Usage: bash test_cli_irradiance.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-irradiance 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
EXAMPLES=$2

# 21 June at 48 N 2 E, UTC+1, sea level: DNI 600 and DHI 100 Wh/m2 from hour 6 to hour 19,
# global horizontal missing (9999: the library derives it), albedo 0.3.
python3 - "$WORK/day.epw" <<'PY'
import sys
lines = ["LOCATION,Testtown,XX,FRA,test,000001,48.0,2.0,1.0,0.0", "DESIGN CONDITIONS,0",
         "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0", "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
         "COMMENTS 1,written by test_cli_irradiance.sh", "COMMENTS 2,", "DATA PERIODS,1,1,Data,Monday, 6/21,6/21"]
for h in range(1, 25):
    day = 6 <= h <= 19
    dni, dhi = (600, 100) if day else (0, 0)
    lines.append(f"2021,6,21,{h},60,x,15,10,70,100000,0,0,300,9999,{dni},{dhi},0,0,0,0,180,2,5,5,20,77777,9,"
                 f"999999999,10,0.1,0,88,0.3,0,0")
open(sys.argv[1], "w").write("\r\n".join(lines) + "\r\n")
PY
cat >"$WORK/scene.json" <<'JSON'
{"meshes": [
  {"name": "roof", "polygons": [{"name": "open roof", "vertices": [[0, 0, 30], [4, 0, 30], [4, 4, 30], [0, 4, 30]]}]},
  {"name": "tower", "polygons": [
    {"name": "tower top", "vertices": [[10, 0, 20], [14, 0, 20], [14, 4, 20], [10, 4, 20]]},
    {"name": "tower west", "vertices": [[10, 4, 0], [10, 0, 0], [10, 0, 20], [10, 4, 20]]}]},
  {"name": "yard", "polygons": [{"name": "yard", "vertices": [[4, 0, 0], [10, 0, 0], [10, 4, 0], [4, 4, 0]]}]},
  {"name": "panel", "polygons": [{"name": "open tilted", "vertices": [[1000, 0, 27.42884956125384], [1004, 0, 27.42884956125384],
    [1004, 3.064177772475912, 30], [1000, 3.064177772475912, 30]]}]}
]}
JSON

for sky in perez isotropic; do
  if "$SHADOW" irradiance "$WORK/scene.json" --weather "$WORK/day.epw" -o "$WORK/out-$sky" --sky "$sky" -t 2 \
       --hourly >"$WORK/$sky.stdout" 2>"$WORK/$sky.stderr" &&
     [[ -f $WORK/out-$sky/report.json && -f $WORK/out-$sky/irradiation.csv && -f $WORK/out-$sky/faces.vtp &&
        -f $WORK/out-$sky/irradiance_hourly.csv && ! -f $WORK/out-$sky/energyplus-diffuse-shading.csv ]]; then
    pass "runs_$sky"
  else
    fail "runs_$sky" "$(cat "$WORK/$sky.stderr")"
  fi
done

# The open roof (30 m up, above everything else) gets: its direct part: sum over the hours of DNI x sin(elevation at mid-hour), the sun
# from `shadow sun` (the same SPA, standard pressure at sea level, 12 C).
expected_direct=0
for h in $(seq 6 19); do
  t=$(printf '2021-06-21T%02d:30:00+01:00' $((h - 1)))
  e=$("$SHADOW" sun --latitude 48 --longitude 2 --elevation 0 --time "$t" |
      python3 -c 'import json,sys; print(json.load(sys.stdin)["elevation"])')
  expected_direct=$(python3 -c "import math; e=$e; print($expected_direct + (600*math.sin(math.radians(e)) if e > 0 else 0))")
done
if python3 - "$WORK" "$expected_direct" <<'PY'
import csv, json, math, sys
work, expected_direct = sys.argv[1], float(sys.argv[2]) / 1000
for sky in ("perez", "isotropic"):
    r = json.load(open(f"{work}/out-{sky}/report.json"))
    assert r["kind"] == "irradiance" and r["run"]["sky"] == sky, r["run"]
    assert abs(r["run"]["ground_reflectance"] - 0.3) < 1e-12, r["run"]  # the file's mean albedo
    assert r["energy_check"]["ok"], r["energy_check"]
    faces = {f["label"]: f for f in r["faces"]}
    roof = faces["open roof"]
    a = roof["annual_irradiation_kwh_m2"]
    assert roof["sky_view_factor"] == 1.0, roof
    assert abs(a["direct"] - expected_direct) < 1e-9, (a, expected_direct)
    assert a["ground_reflected"] == 0.0, a
    assert abs(a["total"] - a["direct"] - a["sky_diffuse"] - a["ground_reflected"]) < 1e-12, a
    if sky == "isotropic":
        assert abs(a["sky_diffuse"] - 14 * 100 / 1000) < 1e-12, a  # the day's DHI, all of the sky seen
    # The tower's west wall looks over the yard and the roof: half the sky at most, and the
    # yard beside the tower sees less sky than the open roof.
    assert faces["tower west"]["sky_view_factor"] <= 0.5 + 1e-12, faces["tower west"]
    assert faces["yard"]["sky_view_factor"] < 1.0, faces["yard"]
    assert abs(sum(roof["monthly_irradiation_kwh_m2"]["total"]) - a["total"]) < 1e-12
    assert [s["name"] for s in r["surfaces"]] == ["open roof", "tower top", "tower west", "yard", "open tilted"], r["surfaces"]
    rows = list(csv.DictReader(open(f"{work}/out-{sky}/irradiation.csv", newline="")))
    assert [row["surface"] for row in rows] == ["open roof", "tower top", "tower west", "yard", "open tilted"], rows
    assert abs(float(rows[0]["total_kwh_m2"]) - a["total"]) < 1e-12 and abs(float(rows[0]["jun_kwh_m2"]) - a["total"]) < 1e-12
    hourly = list(csv.DictReader(open(f"{work}/out-{sky}/irradiance_hourly.csv", newline="")))
    assert len(hourly) == 24 * 5, len(hourly)
    roof_hours = [row for row in hourly if row["surface"] == "open roof"]
    assert roof_hours[0]["hour_start_utc"] == "2021-06-20T23:00:00Z", roof_hours[0]
    assert abs(sum(float(row["total_w_m2"]) for row in roof_hours) / 1000 - a["total"]) < 1e-9
PY
then pass "roof_against_shadow_sun"; else fail "roof_against_shadow_sun" "see above"; fi

# --map: the yard and the tower cut along the beam's shadows, every cell's direct part adding up
# to its face's (area-weighted) in report.json.
# The cells are read with VTK's Python module (python3-vtk9): the first python3 that has it.
vtk_python=""
for candidate in python3 /usr/bin/python3; do
  if "$candidate" -c "import vtkmodules.vtkIOXML" 2>/dev/null; then vtk_python=$candidate; break; fi
done
if [[ -z $vtk_python ]]; then
  echo "skip map_adds_up: no python3 with VTK's module"
elif "$SHADOW" irradiance "$WORK/scene.json" --weather "$WORK/day.epw" -o "$WORK/out-map" --map yard,tower -q &&
   "$vtk_python" - "$WORK/out-map" <<'PY'
import json, sys
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy
r = json.load(open(sys.argv[1] + "/report.json"))
reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1] + "/irradiation_map.vtp")
reader.Update()
cd = reader.GetOutput().GetCellData()
direct = vtk_to_numpy(cd.GetArray("irradiation_direct_kwh_m2"))
area = vtk_to_numpy(cd.GetArray("area"))
face = vtk_to_numpy(cd.GetArray("face_id"))
assert cd.GetArray("irradiation_total_kwh_m2") is not None
faces = {f["face"]: f for f in r["faces"]}
assert sorted(set(face.tolist())) == [1, 2, 3], sorted(set(face.tolist()))
for f in set(face.tolist()):
    mean = (direct[face == f] * area[face == f]).sum() / area[face == f].sum()
    assert abs(mean - faces[f]["annual_irradiation_kwh_m2"]["direct"]) < 1e-9, (f, mean, faces[f])
PY
then pass "map_adds_up"; else fail "map_adds_up" "see above"; fi

# The open panel (tilt 40 degrees, facing south, far from the rest), hour by hour against Perez
# et al. 1990 written again here in Python from the paper (all-sites coefficients, Kasten-Young
# air mass, Spencer's extraterrestrial irradiance), with the sun of `shadow sun` at mid-hour.
suns=""
for h in $(seq 1 24); do
  t=$(printf '2021-06-21T%02d:30:00+01:00' $((h - 1)))
  suns+=$("$SHADOW" sun --latitude 48 --longitude 2 --elevation 0 --time "$t")$'\n'
done
if python3 - "$WORK" "$suns" <<'PY'
import csv, json, math, sys
work, suns = sys.argv[1], [json.loads(line) for line in sys.argv[2].splitlines() if line]
F = [(-0.008, 0.588, -0.062, -0.060, 0.072, -0.022), (0.130, 0.683, -0.151, -0.019, 0.066, -0.029),
     (0.330, 0.487, -0.221, 0.055, -0.064, -0.026), (0.568, 0.187, -0.295, 0.109, -0.152, -0.014),
     (0.873, -0.392, -0.362, 0.226, -0.462, 0.001), (1.132, -1.237, -0.412, 0.288, -0.823, 0.056),
     (1.060, -1.600, -0.359, 0.264, -1.127, 0.131), (0.678, -0.327, -0.250, 0.156, -1.377, 0.251)]
EDGES = [1.065, 1.23, 1.5, 1.95, 2.8, 4.5, 6.2]
rad = math.radians
tilt, surface_azimuth = 40.0, 180.0
b = 2 * math.pi * (172 - 1) / 365  # 21 June 2021: day 172
i0 = 1366.1 * (1.00011 + 0.034221 * math.cos(b) + 0.00128 * math.sin(b) + 0.000719 * math.cos(2 * b) + 0.000077 * math.sin(2 * b))
rows = [row for row in csv.DictReader(open(f"{work}/out-perez/irradiance_hourly.csv", newline="")) if row["surface"] == "open tilted"]
assert len(rows) == 24
for h, (row, sun) in enumerate(zip(rows, suns), start=1):
    dni, dhi = (600.0, 100.0) if 6 <= h <= 19 else (0.0, 0.0)
    zen, az = sun["zenith"], sun["azimuth"]
    if sun["elevation"] <= 0:
        dni = 0.0
    cos_aoi = math.cos(rad(zen)) * math.cos(rad(tilt)) + math.sin(rad(zen)) * math.sin(rad(tilt)) * math.cos(rad(az - surface_azimuth))
    direct = dni * max(0.0, cos_aoi)
    if dhi > 0 and zen < 90:
        z = rad(zen)
        am = 1 / (math.cos(z) + 0.50572 * (96.07995 - zen) ** -1.6364)
        eps = ((dhi + dni) / dhi + 1.041 * z ** 3) / (1 + 1.041 * z ** 3)
        f = F[sum(eps >= e for e in EDGES)]
        delta = dhi * am / i0
        f1 = max(0.0, f[0] + f[1] * delta + f[2] * z)
        f2 = f[3] + f[4] * delta + f[5] * z
        sky = max(0.0, dhi * ((1 - f1) * (1 + math.cos(rad(tilt))) / 2 + f1 * max(0.0, cos_aoi) / max(math.cos(rad(85)), math.cos(z))
                              + f2 * math.sin(rad(tilt))))
    else:
        sky = dhi * (1 + math.cos(rad(tilt))) / 2
    ghi = dni * max(0.0, math.cos(rad(zen))) + dhi
    ground = 0.3 * ghi * (1 - math.cos(rad(tilt))) / 2
    for name, mine in (("direct_w_m2", direct), ("sky_diffuse_w_m2", sky), ("ground_reflected_w_m2", ground)):
        assert abs(float(row[name]) - mine) < 1e-9, (h, name, row[name], mine)
PY
then pass "open_panel_against_perez"; else fail "open_panel_against_perez" "see above"; fi

# --reflections: the scene's own reflections over the period; everything else as without them,
# the total their sum, the surfaces' values area-weighted, the open roof nothing more.
if "$SHADOW" irradiance "$WORK/scene.json" --weather "$WORK/day.epw" -o "$WORK/out-refl" --reflections -q &&
   python3 - "$WORK/out-perez" "$WORK/out-refl" <<'PY'
import json, sys
plain = json.load(open(sys.argv[1] + "/report.json"))
refl = json.load(open(sys.argv[2] + "/report.json"))
assert refl["reflections"]["shots"] > 0 and refl["reflections"]["unshot_fraction"] <= 1e-3, refl["reflections"]
some = 0
for a, b in zip(plain["faces"], refl["faces"]):
    pa, pb = a["annual_irradiation_kwh_m2"], b["annual_irradiation_kwh_m2"]
    assert "scene_reflected" not in pa
    for k in ("direct", "sky_diffuse", "ground_reflected"):
        assert pa[k] == pb[k], (b["label"], k)
    assert pb["scene_reflected"] >= 0.0
    assert abs(pb["total"] - (pa["total"] + pb["scene_reflected"])) <= 1e-9 * pb["total"], b["label"]
    some += pb["scene_reflected"] > 0.01
assert some > 0, "no face receives reflected light"
for s in refl["surfaces"]:
    assert "scene_reflected" in s["annual_irradiation_kwh_m2"], s["name"]
PY
then pass "reflections"; else fail "reflections" "see above"; fi

# An EnergyPlus model: energyplus-diffuse-shading.csv, one ratio in [0, 1] per surface, names as
# EnergyPlus holds them (upper case); the overhang-shaded south wall below 1.
if "$SHADOW" irradiance "$EXAMPLES/energyplus/box-office.idf" --weather "$WORK/day.epw" -o "$WORK/out-idf" -q &&
   python3 - "$WORK/out-idf" <<'PY'
import csv, json, sys
rows = list(csv.reader(open(sys.argv[1] + "/energyplus-diffuse-shading.csv", newline="")))
assert rows[0] == ["Surface Name", "Diffuse Shading Ratio"], rows[0]
ratios = {name: float(value) for name, value in rows[1:]}
assert all(0.0 <= r <= 1.0 for r in ratios.values()), ratios
assert all(name == name.upper() for name in ratios), ratios
assert ratios["WALL-SOUTH"] < 1.0, ratios
report = json.load(open(sys.argv[1] + "/report.json"))
assert len(ratios) == len(report["surfaces"]), (len(ratios), len(report["surfaces"]))
PY
then pass "energyplus_diffuse_shading"; else fail "energyplus_diffuse_shading" "see above"; fi

# shadow render --irradiation (docs/render.md): a PNG of the scene coloured by each face's total;
# the picture's colours against the values are tested in tests/render/test_value_picture.cpp.
# Refused: the vector view, a report of another scene, a file that is not an irradiance report.
if "$SHADOW" render --help >/dev/null 2>&1 && { [[ -n ${DISPLAY:-} ]] || command -v xvfb-run >/dev/null; }; then
  if "$SHADOW" render "$WORK/scene.json" --irradiation "$WORK/out-perez" -o "$WORK/irradiation.png" --width 320 \
       --height 240 >"$WORK/render.stdout" 2>"$WORK/render.stderr" &&
     [[ $(head -c 8 "$WORK/irradiation.png" | od -An -c | tr -d ' ') == '211PNG\r\n032\n' ]] &&
     grep -q "coloured by total irradiation" "$WORK/render.stdout"; then
    pass "render_irradiation_png"
  else
    fail "render_irradiation_png" "$(cat "$WORK/render.stderr")"
  fi
  echo '{"meshes": [{"name": "other", "polygons": [{"name": "lone", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0]]}]}]}' \
    >"$WORK/other.json"
  render_refused() {
    local name=$1 part=$2 image=$3
    shift 3
    local status=0
    "$SHADOW" render "$@" -o "$WORK/$image" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
    if [[ $status -eq 2 && $(wc -l <"$WORK/$name.stderr") -eq 1 && $(cat "$WORK/$name.stderr") == *"$part"* &&
          ! -e $WORK/$image ]]; then
      pass "$name"
    else
      fail "$name" "status $status: $(cat "$WORK/$name.stderr")"
    fi
  }
  render_refused render_irradiation_vector "--irradiation: draws a PNG picture" view.svg \
    "$WORK/scene.json" --irradiation "$WORK/out-perez"
  render_refused render_irradiation_other_scene "faces[0].label: \"open roof\" is face 0 of the result" other.png \
    "$WORK/other.json" --irradiation "$WORK/out-perez/report.json"
  render_refused render_irradiation_not_a_report "day.epw: not JSON" notjson.png \
    "$WORK/scene.json" --irradiation "$WORK/day.epw"
else
  echo "skip render_irradiation: no shadow render or no display"
fi

# examples/irradiance (the scene of docs/irradiance.md's picture; no weather ships with it) runs
# under the day written here, and its roofs receive more than its north walls.
if "$SHADOW" irradiance "$EXAMPLES/irradiance/scene.json" --weather "$WORK/day.epw" -o "$WORK/out-example" -q -t 2 &&
   python3 - "$WORK/out-example/report.json" <<'PY'
import json, sys
s = {g["name"]: g["annual_irradiation_kwh_m2"]["total"] for g in json.load(open(sys.argv[1]))["surfaces"]}
assert s["tower roof"] > s["tower north"] and s["low roof"] > s["low north"], s
PY
then pass "example_scene_runs"; else fail "example_scene_runs" "see above"; fi

# OUTDIR is held for the whole run (as for shadow series): a second run into it while the lock is
# taken (here by flock(1) on the same lock file, as a running shadow takes it) is refused at once
# with one line and exit 3 (an output could not be written), the earlier result untouched; the
# lock file is gone after a run.
if command -v flock >/dev/null 2>&1; then
  out="$WORK/out-perez"
  before=$(md5sum <"$out/report.json")
  status=0
  flock "$out/.shadow.lock" "$SHADOW" irradiance "$WORK/scene.json" --weather "$WORK/day.epw" -o "$out" \
    >"$WORK/locked.stdout" 2>"$WORK/locked.stderr" || status=$?
  if [[ $status -eq 3 && $(wc -l <"$WORK/locked.stderr") -eq 1 ]] && grep -q "another shadow process" "$WORK/locked.stderr" &&
     [[ $(md5sum <"$out/report.json") == "$before" && ! -s $WORK/locked.stdout ]]; then
    pass "locked_outdir_is_refused"
  else
    fail "locked_outdir_is_refused" "status $status: $(cat "$WORK/locked.stderr")"
  fi
  if [[ ! -e $WORK/out-isotropic/.shadow.lock && ! -e $WORK/out-map/.shadow.lock ]]; then
    pass "lock_file_removed_after_a_run"
  else
    fail "lock_file_removed_after_a_run" "a .shadow.lock was left behind"
  fi
else
  echo "skip locked_outdir_is_refused: no flock(1)"
fi

# expect_error NAME PART ARGS...: exit 2, one line on stderr containing PART, no report.json.
expect_error() {
  local name=$1 part=$2
  shift 2
  local status=0
  "$SHADOW" irradiance "$@" -o "$WORK/out-$name" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  if [[ $status -eq 2 && $(wc -l <"$WORK/$name.stderr") -eq 1 && $(cat "$WORK/$name.stderr") == *"$part"* &&
        ! -e $WORK/out-$name/report.json ]]; then
    pass "$name"
  else
    fail "$name" "status $status: $(cat "$WORK/$name.stderr")"
  fi
}
sed 's/^2021,6,21,12,60,x,15,10,70,100000,0,0,300,9999,600,/2021,6,21,12,60,x,15,10,70,100000,0,0,300,9999,6O0,/' \
  "$WORK/day.epw" >"$WORK/bad.epw"
expect_error bad_epw "bad.epw: line 20, field 15 (direct normal radiation): '6O0' is not a number" \
  "$WORK/scene.json" --weather "$WORK/bad.epw"
expect_error no_epw "missing.epw: cannot open the weather file" "$WORK/scene.json" --weather "$WORK/missing.epw"
expect_error bad_patches "--sky-patches" "$WORK/scene.json" --weather "$WORK/day.epw" --sky-patches 100
expect_error bad_reflectance "--ground-reflectance" "$WORK/scene.json" --weather "$WORK/day.epw" --ground-reflectance 2
expect_error bad_period "before it starts" "$WORK/scene.json" --weather "$WORK/day.epw" --from 07-01 --to 06-01
expect_error empty_period "no record of the weather file" "$WORK/scene.json" --weather "$WORK/day.epw" --from 07-01
expect_error period_past_the_file "ends after the file's last record" "$WORK/scene.json" --weather "$WORK/day.epw" \
  --from 06-21 --to 06-22

# --from/--to on a file whose records run across 31 December (31 December 2020, 1 January 2021):
# the dates are placed on the file's timeline. Read as month-days, --from 01-01 took 31 December
# too, and --from 12-31 --to 01-01 was "before it starts".
python3 - "$WORK/day.epw" "$WORK/new-year.epw" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
header, records = lines[:8], [l for l in lines[8:] if l]
header[7] = "DATA PERIODS,1,1,Data,Thursday, 12/31,1/ 1"
out = header + [r.replace("2021,6,21,", "2020,12,31,", 1) for r in records] + [r.replace("2021,6,21,", "2021,1,1,", 1) for r in records]
open(sys.argv[2], "w").write("\n".join(out) + "\n")
PY
period_hours() {
  local name=$1
  shift
  if "$SHADOW" irradiance "$WORK/scene.json" --weather "$WORK/new-year.epw" -o "$WORK/out-$name" "$@" >"$WORK/$name.stdout" 2>&1; then
    sed -n 's/.* \([0-9]*\) hours of .*/\1/p' "$WORK/$name.stdout" | head -1
  else
    echo "exit $?: $(cat "$WORK/$name.stdout")"
  fi
}
hours_jan=$(period_hours period_jan --from 01-01)
hours_both=$(period_hours period_both --from 12-31 --to 01-01)
hours_dec=$(period_hours period_dec --to 12-31)
if [[ $hours_jan == 24 && $hours_both == 48 && $hours_dec == 24 ]]; then
  pass period_across_new_year
else
  fail period_across_new_year "hours: --from 01-01 '$hours_jan' (24), --from 12-31 --to 01-01 '$hours_both' (48), --to 12-31 '$hours_dec' (24)"
fi

# A date with its year on a file of two years (2020 and 2021, DNI 600 in 2020 and 300 in 2021):
# that day where the file holds it (before, the year was dropped and 06-21 of 2020 taken); a day
# the file does not hold is an error; on the two-day file above a year it does not hold leaves
# the month and day (a typical year stamped with other years).
python3 - "$WORK/day.epw" "$WORK/two-years.epw" <<'PY'
import datetime, sys
lines = open(sys.argv[1]).read().splitlines()
header, records = lines[:8], [l for l in lines[8:] if l]
header[7] = "DATA PERIODS,1,1,Data,Wednesday, 1/ 1/2020,12/31/2021"
out = list(header)
day = datetime.date(2020, 1, 1)
while day.year < 2022:
    for r in records:
        fields = r.split(",")
        fields[0:3] = [str(day.year), str(day.month), str(day.day)]
        if fields[14] != "0":
            fields[14] = "600" if day.year == 2020 else "300"
        out.append(",".join(fields))
    day += datetime.timedelta(days=1)
open(sys.argv[2], "w").write("\n".join(out) + "\n")
PY
roof_direct() {
  local name=$1 file=$2
  shift 2
  if "$SHADOW" irradiance "$WORK/scene.json" --weather "$file" -o "$WORK/out-$name" -q "$@" >"$WORK/$name.stdout" 2>&1; then
    python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); print(r["run"]["period"]["hours"], round(r["faces"][0]["annual_irradiation_kwh_m2"]["direct"], 3))' \
      "$WORK/out-$name/report.json"
  else
    echo "exit $?: $(cat "$WORK/$name.stdout")"
  fi
}
y2020=$(roof_direct year_2020 "$WORK/two-years.epw" --from 2020-06-21 --to 2020-06-21)
y2021=$(roof_direct year_2021 "$WORK/two-years.epw" --from 2021-06-21 --to 2021-06-21)
md=$(roof_direct year_month_day "$WORK/two-years.epw" --from 06-21 --to 06-21)
typical=$(roof_direct year_typical "$WORK/new-year.epw" --from 2030-01-01)
if [[ ${y2020%% *} == 24 && ${y2021%% *} == 24 && $md == "$y2020" && ${typical%% *} == 24 ]] &&
   python3 -c "import sys; a, b = float('${y2020#* }'), float('${y2021#* }'); sys.exit(0 if abs(b - a / 2) < 1e-3 * a else 1)"; then
  pass period_with_its_year
else
  fail period_with_its_year "2020-06-21 '$y2020', 2021-06-21 '$y2021' (half the direct), 06-21 '$md' (2020's), typical 2030-01-01 '$typical' (24 hours)"
fi
expect_error period_year_not_in_file "--from 2019-06-21 is not a day of the weather file" "$WORK/scene.json" \
  --weather "$WORK/two-years.epw" --from 2019-06-21
expect_error period_leap_day "--from 02-29: the weather file has no 29 February" "$WORK/scene.json" \
  --weather "$WORK/day.epw" --from 02-29
expect_error period_year_reversed "before it starts" "$WORK/scene.json" --weather "$WORK/two-years.epw" \
  --from 2021-06-21 --to 2020-06-22

expect_error bad_map "--map" "$WORK/scene.json" --weather "$WORK/day.epw" --map nothing
expect_error bad_ground "--ground" "$WORK/scene.json" --weather "$WORK/day.epw" --ground nothing

# The same day as a TMY3 CSV file (site line, column names, hour-ending records; the missing
# global horizontal as -9900): the same irradiation on every face as from the EPW file.
python3 - "$WORK/day.epw" "$WORK/day.csv" <<'PY'
import sys
rows = [l.split(",") for l in open(sys.argv[1]).read().splitlines()[8:]]
out = ['1,"Testtown, test",XX,1.0,48.0,2.0,0.0',
       "Date (MM/DD/YYYY),Time (HH:MM),ETR (W/m^2),ETRN (W/m^2),GHI (W/m^2),GHI source,GHI uncert (%),"
       "DNI (W/m^2),DNI source,DNI uncert (%),DHI (W/m^2),DHI source,DHI uncert (%),Dry-bulb (C),Alb (unitless)"]
for r in rows:
    ghi = "-9900" if r[13] == "9999" else r[13]
    out.append(f"{int(r[1]):02d}/{int(r[2]):02d}/{r[0]},{int(r[3]):02d}:00,0,0,{ghi},1,8,{r[14]},1,8,{r[15]},1,8,{r[6]},{r[32]}")
open(sys.argv[2], "w").write("\n".join(out) + "\n")
PY
if "$SHADOW" irradiance "$WORK/scene.json" --weather "$WORK/day.csv" -o "$WORK/out-tmy3" -q -t 2 &&
   python3 - "$WORK/out-tmy3/report.json" "$WORK/out-perez/report.json" <<'PY'
import json, sys
t, e = (json.load(open(p)) for p in sys.argv[1:3])
assert t["run"]["ground_reflectance"] == e["run"]["ground_reflectance"], t["run"]
assert t["run"]["period"]["hours"] == 24 and t["run"]["location"]["city"] == "Testtown, test", t["run"]
for a, b in zip(t["faces"], e["faces"]):
    assert a["face"] == b["face"]
    for k, v in a["annual_irradiation_kwh_m2"].items():
        assert abs(v - b["annual_irradiation_kwh_m2"][k]) <= 1e-12 * (1 + abs(v)), (a["label"], k, v, b)
PY
then pass "tmy3_same_as_epw"; else fail "tmy3_same_as_epw" "see above"; fi
sed 's#^06/21/2021,13:00,0,0,-9900,1,8,600,#06/21/2021,13:00,0,0,-9900,1,8,6O0,#' "$WORK/day.csv" >"$WORK/bad.csv"
expect_error bad_tmy3 "bad.csv: line 15, field 8 (DNI (W/m^2)): '6O0' is not a number" \
  "$WORK/scene.json" --weather "$WORK/bad.csv"

# The ground's view: the tower's west wall looks down onto the yard (a scene face, 6 m wide), which
# hides part of the ground; with --ground yard the yard is the ground and the wall sees half the
# world below it as ground, exactly as an open wall; the roof sees none. faces.vtp carries it.
if "$SHADOW" irradiance "$WORK/scene.json" --weather "$WORK/day.epw" -o "$WORK/out-ground" -q -t 2 --ground yard &&
   python3 - "$WORK/out-ground/report.json" "$WORK/out-perez/report.json" <<'PY'
import json, sys
g, d = (json.load(open(p)) for p in sys.argv[1:3])
fg = {f["label"]: f for f in g["faces"]}
fd = {f["label"]: f for f in d["faces"]}
assert g["run"]["ground_meshes"] == ["yard"] and d["run"]["ground_meshes"] == [], (g["run"], d["run"])
assert abs(fg["tower west"]["ground_view_factor"] - 0.5) < 1e-12, fg["tower west"]
assert 0.0 < fd["tower west"]["ground_view_factor"] < 0.45, fd["tower west"]
assert fg["yard"]["ground"] and not fd["yard"]["ground"]
for f in (fg, fd):
    assert f["open roof"]["ground_view_factor"] == 0.0 and f["open roof"]["annual_irradiation_kwh_m2"]["ground_reflected"] == 0.0
    assert abs(f["open roof"]["sky_view_factor"] + f["open roof"]["ground_view_factor"] - 1.0) < 1e-12
    t = f["open tilted"]
    assert abs(t["sky_view_factor"] + t["ground_view_factor"] - 1.0) < 1e-12, t
west = {s["name"]: s for s in g["surfaces"]}["tower west"]
assert abs(west["ground_view_factor"] - 0.5) < 1e-12, west
ratio = fd["tower west"]["annual_irradiation_kwh_m2"]["ground_reflected"] / fg["tower west"]["annual_irradiation_kwh_m2"]["ground_reflected"]
assert abs(ratio - fd["tower west"]["ground_view_factor"] / 0.5) < 1e-12, ratio
PY
then pass "ground_view"; else fail "ground_view" "see above"; fi
if [[ -n $vtk_python ]]; then
  if "$vtk_python" - "$WORK/out-ground" <<'PY'
import json, sys
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy
r = json.load(open(sys.argv[1] + "/report.json"))
reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1] + "/faces.vtp")
reader.Update()
g = vtk_to_numpy(reader.GetOutput().GetCellData().GetArray("ground_view_factor"))
for f in r["faces"]:
    assert abs(g[f["face"]] - f["ground_view_factor"]) < 1e-12, (f, g)
PY
  then pass "faces_vtp_ground_view"; else fail "faces_vtp_ground_view" "see above"; fi
fi
cli_test_end
