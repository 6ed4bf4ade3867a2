#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow sun` and scenes with a `sun` block (docs/sun.md): the JSON line, usage errors (one
# line, exit 2), the SPA paper's example, a second method (the Astronomical Almanac's
# low-precision sun, written here in Python) agreeing within its own 0.01-degree accuracy, and
# `shadow compute` on examples/sun with report.json's sun object.
#
# Usage: bash test_cli_sun.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-sun 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
EXAMPLES=$2

# expect_usage_error NAME PART ARGS...: exit 2, exactly one line on stderr containing PART.
expect_usage_error() {
  local name=$1 part=$2
  shift 2
  local status=0
  "$SHADOW" "$@" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  local lines
  lines=$(wc -l <"$WORK/$name.stderr")
  if [[ $status -eq 2 && $lines -eq 1 && $(cat "$WORK/$name.stderr") == "shadow: error: "*"$part"* &&
        ! -s "$WORK/$name.stdout" ]]; then
    pass "$name"
  else
    fail "$name" "status $status, $lines lines: $(cat "$WORK/$name.stderr")"
  fi
}

# The SPA paper's example (Reda & Andreas 2004): zenith 50.11162, azimuth 194.34024.
line=$("$SHADOW" sun --latitude 39.742476 --longitude -105.1786 --elevation 1830.14 --pressure 820 \
         --temperature 11 --delta-t 67 --time 2003-10-17T12:30:30-07:00)
if python3 - "$line" <<'PY'
import json, sys
j = json.loads(sys.argv[1])
assert set(j) == {"time", "elevation", "azimuth", "zenith", "to_light"}, j
assert j["time"] == "2003-10-17T19:30:30Z", j
assert abs(j["zenith"] - 50.11162) < 1e-4 and abs(j["azimuth"] - 194.34024) < 1e-4, j
assert abs(j["elevation"] + j["zenith"] - 90) < 1e-12, j
assert abs(sum(c * c for c in j["to_light"]) - 1) < 1e-15, j
PY
then pass "sun_paper_example"; else fail "sun_paper_example" "$line"; fi

# --pressure 0 (NREL's SPA takes 0 to 5000 mbar): the airless, geometric position. Refraction
# (820 mbar) lifts the sun; a vanishing pressure lifts it by almost nothing, and 0 by nothing.
spa_args=(--latitude 39.742476 --longitude -105.1786 --elevation 1830.14 --temperature 11 --delta-t 67
          --time 2003-10-17T12:30:30-07:00)
airless=$("$SHADOW" sun "${spa_args[@]}" --pressure 0 2>&1)
thin=$("$SHADOW" sun "${spa_args[@]}" --pressure 1e-9 2>&1)
if python3 - "$airless" "$thin" "$line" <<'PY'
import json, sys
airless, thin, air = (json.loads(x) for x in sys.argv[1:4])
assert airless["elevation"] + airless["zenith"] == 90 or abs(airless["elevation"] + airless["zenith"] - 90) < 1e-12
assert air["elevation"] - airless["elevation"] > 0.01, (air, airless)  # about 0.0163 degrees at 820 mbar
assert 0 <= thin["elevation"] - airless["elevation"] < 1e-9, (thin, airless)
assert airless["azimuth"] == air["azimuth"], (air, airless)  # refraction moves the elevation only
PY
then pass "sun_pressure_zero_is_geometric"; else fail "sun_pressure_zero_is_geometric" "$airless / $thin"; fi

# --north-axis 90: the model's +y is east, so to_light is the true one turned 90 degrees
# counter-clockwise: (x, y) -> (-y, x).
a=$("$SHADOW" sun --latitude 48.85 --longitude 2.35 --time 2026-06-21T08:00:00Z)
b=$("$SHADOW" sun --latitude 48.85 --longitude 2.35 --time 2026-06-21T08:00:00Z --north-axis 90)
if python3 - "$a" "$b" <<'PY'
import json, sys
a, b = (json.loads(x) for x in sys.argv[1:3])
assert a["azimuth"] == b["azimuth"] and a["elevation"] == b["elevation"]
ax, ay, az = a["to_light"]; bx, by, bz = b["to_light"]
assert abs(bx + ay) < 1e-12 and abs(by - ax) < 1e-12 and abs(bz - az) < 1e-15, (a, b)
PY
then pass "sun_north_axis"; else fail "sun_north_axis" "$a / $b"; fi

# A second method: the Astronomical Almanac's low-precision sun (about 0.01 degrees from 1950
# to 2050), geocentric and without refraction (pressure ~0 here), at seeded random places and
# times. Agreement within 0.02 degrees in elevation and in the angle between the two directions
# (azimuth differences alone grow as 1/cos(elevation) near the zenith).
python3 - "$SHADOW" <<'PY' >"$WORK/almanac.out" 2>&1
import json, math, random, subprocess, sys, datetime
shadow = sys.argv[1]
rng = random.Random(20261122)
worst_e = worst_a = 0.0
def direction(el, az):
    e, a = math.radians(el), math.radians(az)
    return (math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e))
for _ in range(40):
    lat = rng.uniform(-70, 70); lon = rng.uniform(-180, 180)
    t = datetime.datetime(1990, 1, 1, tzinfo=datetime.timezone.utc) + datetime.timedelta(
        seconds=rng.randrange(0, 50 * 365 * 86400))
    iso = t.strftime("%Y-%m-%dT%H:%M:%SZ")
    out = subprocess.run([shadow, "sun", "--latitude", repr(lat), "--longitude", repr(lon), "--time", iso,
                          "--pressure", "1e-9"], capture_output=True, text=True, check=True).stdout
    j = json.loads(out)
    n = t.timestamp() / 86400.0 + 2440587.5 - 2451545.0
    rad = math.radians
    L = (280.460 + 0.9856474 * n) % 360
    g = rad((357.528 + 0.9856003 * n) % 360)
    lam = rad(L + 1.915 * math.sin(g) + 0.020 * math.sin(2 * g))
    eps = rad(23.439 - 0.0000004 * n)
    ra = math.atan2(math.cos(eps) * math.sin(lam), math.cos(lam))
    dec = math.asin(math.sin(eps) * math.sin(lam))
    gmst = rad((280.46061837 + 360.98564736629 * n) % 360)
    h = gmst + rad(lon) - ra
    phi = rad(lat)
    el = math.degrees(math.asin(math.sin(phi) * math.sin(dec) + math.cos(phi) * math.cos(dec) * math.cos(h)))
    az = math.degrees(math.atan2(-math.sin(h), math.tan(dec) * math.cos(phi) - math.sin(phi) * math.cos(h))) % 360
    # SPA is topocentric: take the sun's parallax (8.794" cos el) out before comparing.
    geocentric = j["elevation"] + 8.794 / 3600 * math.cos(rad(el))
    worst_e = max(worst_e, abs(geocentric - el))
    u, v = direction(geocentric, j["azimuth"]), direction(el, az)
    cross = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    angle = math.degrees(math.atan2(math.sqrt(sum(c * c for c in cross)), sum(a * b for a, b in zip(u, v))))
    worst_a = max(worst_a, angle)
print("worst elevation %.5f direction %.5f degrees" % (worst_e, worst_a))
assert worst_e < 0.02 and worst_a < 0.02, (worst_e, worst_a)
PY
if [[ $? -eq 0 ]]; then pass "sun_agrees_with_almanac ($(cat "$WORK/almanac.out"))"
else fail "sun_agrees_with_almanac" "$(cat "$WORK/almanac.out")"; fi

# --rise-set: Berlin on the 2026 June solstice, almanac times 04:43 and 21:33 CEST (02:43 and
# 19:33 UTC, to the minute); Sydney the same day 07:00 and 16:53 AEST; Longyearbyen (78.2 N) has
# midnight sun in June and polar night in December: null.
check_rise_set() {
  local name=$1 lat=$2 lon=$3 time=$4 rise=$5 set=$6
  local line
  line=$("$SHADOW" sun --latitude "$lat" --longitude "$lon" --time "$time" --rise-set)
  if python3 - "$line" "$rise" "$set" <<'PY'
import datetime, json, sys
j = json.loads(sys.argv[1])
def close(got, want):
    if want == "null":
        return got is None
    if want == "-":  # not checked against a published value, but it must be there
        return got is not None
    parse = lambda s: datetime.datetime.strptime(s, "%Y-%m-%dT%H:%M:%SZ" if s.count(":") == 2 else "%Y-%m-%dT%H:%MZ")
    return got is not None and abs((parse(got) - parse(want)).total_seconds()) <= 60
assert close(j["sunrise"], sys.argv[2]) and close(j["sunset"], sys.argv[3]), j
PY
  then pass "$name"; else fail "$name" "$line"; fi
}
check_rise_set rise_set_berlin 52.52 13.405 2026-06-21T12:00:00Z 2026-06-21T02:43Z 2026-06-21T19:33Z
check_rise_set rise_set_sydney -33.87 151.21 2026-06-21T02:00:00Z 2026-06-20T21:00Z 2026-06-21T06:53Z
check_rise_set rise_set_polar_day 78.22 15.65 2026-06-21T12:00:00Z null null
check_rise_set rise_set_polar_night 78.22 15.65 2026-12-21T12:00:00Z null null
# NREL's spa_tester prints sunrise 06:12:43 local time (UTC-7) for the paper's example.
check_rise_set rise_set_spa_example 39.742476 -105.1786 2003-10-17T19:30:30Z 2003-10-17T13:12:43Z -

expect_usage_error sun_bad_time "--time" sun --latitude 40 --longitude 0 --time 2026-02-30T12:00:00Z
expect_usage_error sun_no_zone "--time" sun --latitude 40 --longitude 0 --time 2026-06-21T12:00:00
expect_usage_error sun_hour_24 "--time" sun --latitude 40 --longitude 0 --time 2026-06-21T24:01:00Z
expect_usage_error sun_latitude "--latitude" sun --latitude 91 --longitude 0 --time 2026-06-21T12:00:00Z
expect_usage_error sun_latitude_nan "--latitude" sun --latitude nan --longitude 0 --time 2026-06-21T12:00:00Z
expect_usage_error sun_longitude "--longitude" sun --latitude 0 --longitude 180.5 --time 2026-06-21T12:00:00Z
expect_usage_error sun_missing_time "--time" sun --latitude 0 --longitude 0
expect_usage_error sun_pressure "--pressure" sun --latitude 0 --longitude 0 --time 2026-06-21T12:00:00Z --pressure -3
expect_usage_error sun_pressure_high "--pressure" sun --latitude 0 --longitude 0 --time 2026-06-21T12:00:00Z --pressure 5001

if "$SHADOW" --help | grep -q "sun" && "$SHADOW" sun --help | grep -q -- "--north-axis"; then
  pass "sun_in_help"
else
  fail "sun_in_help" "shadow --help or shadow sun --help lacks the sun subcommand"
fi

# The example scene: one June day in Berlin, hourly; report.json's sun object and sun lights.
out="$WORK/out-sun"
if "$SHADOW" compute "$EXAMPLES/sun/scene.json" -o "$out" -q && python3 - "$out/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r["sun"]
assert s["instants"] == 24 and s["above_horizon"] + s["below_horizon"] == 24, s
assert s["above_horizon"] == len(r["lights"]) == 17, s  # Berlin, June 21: 02:43 to 19:33 UTC
assert s["period"] == {"start": "2026-06-21", "end": "2026-06-21", "step_minutes": 60}, s
assert s["utc_offset"] == 1.0 and s["site"]["latitude"] == 52.52, s
for light in r["lights"]:
    assert light["name"] == "sun " + light["time"] and light["elevation"] > 0, light
    assert 0 <= light["azimuth"] < 360 and light["type"] == "directional", light
assert r["lights"][0]["time"] == "2026-06-21T03:00:00Z", r["lights"][0]
PY
then pass "compute_sun_example"; else fail "compute_sun_example" "see above"; fi

# A bad sun block: one line naming the file and the place.
mkdir -p "$WORK/bad"
printf '{"meshes": [{"name": "m", "polygons": [[[0,0,0],[1,0,0],[1,1,0]]]}], "sun": {"latitude": 40, "longitude": 0, "start": "2026-06-21", "end": "2026-06-21", "step_minutes": 7}}\n' >"$WORK/bad/scene.json"
expect_usage_error compute_bad_step "scene.json: sun.step_minutes: step_minutes must divide a day" \
  compute "$WORK/bad/scene.json" -o "$WORK/out-bad"
if [[ -e "$WORK/out-bad/report.json" ]]; then fail "compute_bad_step_no_output" "report.json written"; fi

cli_test_end
