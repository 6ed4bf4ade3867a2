#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The energy modeller's journey (docs/energyplus.md): an IDF whose windows are set back from their
# wall (EnergyPlus's reveals) runs through `shadow series`; the run writes energyplus-objects.idf
# (ShadowCalculation Imported, Schedule:File:Shading naming the CSV) and prints it;
# --write-idf writes the model with those objects in place, which reads again to the same
# results. A period over 7 days writes at most 48 per-instant files unless --every asks for
# more; a short one writes every instant, as before. `shadow render` takes series' load options.
#
# Usage: bash test_series_energyplus.sh /path/to/shadow
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin series-energyplus 1 "SHADOW_BINARY" "$@"
SHADOW=$1

# A 10 x 8 x 3 m room in Chicago, two windows 0.152 m behind its south wall (as EnergyPlus's
# SolarShadingTest.idf sets them), and a ShadowCalculation of its own that --write-idf replaces.
cat >"$WORK/model.idf" <<'IDF'
Version, 9.6;
Building, Box, 0;
Site:Location, Chicago, 41.98, -87.92, -6, 190;
RunPeriod, Year, 1, 1, , 12, 31, , Sunday;
Timestep, 4;
GlobalGeometryRules, UpperLeftCorner, Counterclockwise, Relative;
Zone, Room;
BuildingSurface:Detailed, Zn001:Wall001, Wall, C, Room, , Outdoors, , SunExposed, WindExposed, , 4,
  0,0,3, 0,0,0, 10,0,0, 10,0,3;
BuildingSurface:Detailed, Zn001:Wall002, Wall, C, Room, , Outdoors, , SunExposed, WindExposed, , 4,
  10,0,3, 10,0,0, 10,8,0, 10,8,3;
BuildingSurface:Detailed, Zn001:Wall003, Wall, C, Room, , Outdoors, , SunExposed, WindExposed, , 4,
  10,8,3, 10,8,0, 0,8,0, 0,8,3;
BuildingSurface:Detailed, Zn001:Wall004, Wall, C, Room, , Outdoors, , SunExposed, WindExposed, , 4,
  0,8,3, 0,8,0, 0,0,0, 0,0,3;
BuildingSurface:Detailed, Zn001:Roof001, Roof, C, Room, , Outdoors, , SunExposed, WindExposed, , 4,
  0,8,3, 0,0,3, 10,0,3, 10,8,3;
BuildingSurface:Detailed, Zn001:Flr001, Floor, C, Room, , Ground, , NoSun, NoWind, , 4,
  0,0,0, 0,8,0, 10,8,0, 10,0,0;
FenestrationSurface:Detailed, Zn001:Wall001:Win001, Window, G, Zn001:Wall001, , , , 1, 4,
  1,0.152,2.5, 1,0.152,1, 4,0.152,1, 4,0.152,2.5;
FenestrationSurface:Detailed, Zn001:Wall001:Win002, Window, G, Zn001:Wall001, , , , 1, 4,
  6,0.152,2.5, 6,0.152,1, 9,0.152,1, 9,0.152,2.5;
ShadowCalculation, PolygonClipping, Periodic, 20;
IDF

count() { find "$1" -name 'sun_*.vtp' 2>/dev/null | wc -l; }
instants() { echo $(($(wc -l <"$1/sunlit.csv") - 1)); }  # rows of sunlit.csv: instants above the horizon

# Two days: every instant has its file, as before; the windows in reveals are read.
short=$WORK/short
"$SHADOW" series "$WORK/model.idf" -o "$short" --from 2023-06-20 --to 2023-06-21 --step 60 \
  >"$WORK/short.out" 2>"$WORK/short.err" || fail "short series" "exit $?: $(cat "$WORK/short.err")"
n=$(instants "$short")
if [[ $n -gt 20 && $(count "$short/series") -eq $n ]]; then pass "2 days: all $n instants written"; else
  fail "2 days: all instants" "$(count "$short/series") files for $n instants"; fi
if grep -q 'set back from the plane of their base surface by 0.152 m' "$WORK/short.err"; then pass "reveals: one warning"; else
  fail "reveals: one warning" "$(cat "$WORK/short.err")"; fi
if head -n 1 "$short/sunlit.csv" | grep -q 'Zn001:Wall001:Win002' && ! head -n 1 "$short/sunlit.csv" | grep -q Reveal; then
  pass "windows are columns, reveals are not"; else fail "windows are columns" "$(head -n 1 "$short/sunlit.csv")"; fi

# The objects that make EnergyPlus read the CSV: beside it, and printed.
objects=$short/energyplus-objects.idf
csv=$(cd "$short" && pwd)/energyplus-shading.csv
if [[ -f "$objects" ]] && grep -q '^  Imported, *!- Shading Calculation Method' "$objects" &&
   grep -qF "  $csv; " "$objects" && grep -q '^    Schedule:File:Shading,' "$WORK/short.out" &&
   grep -qF -- "--write-idf FILE" "$WORK/short.out"; then
  pass "energyplus-objects.idf names the CSV, and the summary prints it"
else
  fail "energyplus-objects.idf" "$(cat "$objects" "$WORK/short.out" 2>&1 | head -40)"
fi

# --write-idf: the model with its ShadowCalculation replaced; it reads again to the same fractions.
"$SHADOW" series "$WORK/model.idf" -o "$WORK/written" --from 2023-06-20 --to 2023-06-21 --step 60 -q \
  --write-idf "$WORK/imported.idf" 2>/dev/null || fail "--write-idf" "exit $?"
# Two days of a year: the summary says the rest of the CSV is 0 (fully shaded) before anyone runs
# EnergyPlus on the copy; and a leap year's rows against the model's 365-day RunPeriod.
"$SHADOW" series "$WORK/model.idf" -o "$WORK/written-note" --from 2023-06-20 --to 2023-06-21 --step 60 \
  --write-idf "$WORK/imported-note.idf" >"$WORK/note.out" 2>/dev/null || fail "--write-idf note" "exit $?"
"$SHADOW" series "$WORK/model.idf" -o "$WORK/written-leap" --from 2028-06-20 --to 2028-06-20 --step 60 \
  --write-idf "$WORK/imported-leap.idf" >"$WORK/leap.out" 2>/dev/null || fail "--write-idf leap" "exit $?"
if grep -q "note: energyplus-shading.csv: the period covers 48 of the year's 8760 time steps; the others are 0, fully shaded" "$WORK/note.out" &&
   ! grep -q "RunPeriod" "$WORK/note.out" &&
   grep -q "the CSV's 8784 time steps are 2028's (366 days): EnergyPlus will not match them" "$WORK/leap.out"; then
  pass "--write-idf: the summary notes a part of the year and a year of another length"
else
  fail "--write-idf notes" "$(grep note "$WORK/note.out" "$WORK/leap.out")"
fi
if [[ $(grep -c '^ShadowCalculation,' "$WORK/imported.idf") -eq 1 ]] && ! grep -q PolygonClipping "$WORK/imported.idf" &&
   grep -qF "$(cd "$WORK/written" && pwd)/energyplus-shading.csv;" "$WORK/imported.idf"; then
  pass "--write-idf: one ShadowCalculation, Imported, naming the CSV"
else
  fail "--write-idf" "$(grep -n -A3 'ShadowCalculation\|Schedule:File' "$WORK/imported.idf" 2>&1 | head -20)"
fi
"$SHADOW" series "$WORK/imported.idf" -o "$WORK/reread" --from 2023-06-20 --to 2023-06-21 --step 60 -q 2>/dev/null ||
  fail "the written model reads" "exit $?"
if cmp -s "$short/sunlit.csv" "$WORK/reread/sunlit.csv"; then pass "the written model gives the same sunlit.csv"; else
  fail "the written model gives the same sunlit.csv" "they differ"; fi
status=0
"$SHADOW" series "$WORK/model.idf" -o "$WORK/bad" --from 2023-06-20 --to 2023-06-20 --write-idf "$WORK/model.idf" \
  2>"$WORK/bad.err" >/dev/null || status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/bad.err") -eq 1 ]] && grep -q -- '--write-idf.*is the model itself' "$WORK/bad.err" &&
   [[ ! -e "$WORK/bad/report.json" ]]; then pass "--write-idf onto the model itself: one error line"; else
  fail "--write-idf onto the model itself" "status $status: $(cat "$WORK/bad.err")"; fi
# --energyplus-shading asked for by name on a step EnergyPlus cannot take: one error before any
# computing, not a run without the file.
status=0
"$SHADOW" series "$WORK/model.idf" -o "$WORK/bad-step" --from 2023-06-20 --to 2023-06-20 --step 90 \
  --energyplus-shading 2>"$WORK/bad-step.err" >/dev/null || status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/bad-step.err") -eq 1 ]] &&
   grep -q -- '--energyplus-shading: energyplus-shading.csv cannot be written for this run: step_minutes 90 does not divide an hour' \
     "$WORK/bad-step.err" && [[ ! -e "$WORK/bad-step/report.json" ]]; then
  pass "--energyplus-shading on a 90-minute step: one error line, nothing written"
else
  fail "--energyplus-shading on a 90-minute step" "status $status: $(cat "$WORK/bad-step.err")"
fi
# Without the flag the model's run goes on and says why there is no CSV.
"$SHADOW" series "$WORK/model.idf" -o "$WORK/step90" --from 2023-06-20 --to 2023-06-20 --step 90 \
  >"$WORK/step90.out" 2>/dev/null || fail "a model at 90 minutes" "exit $?"
if [[ ! -e "$WORK/step90/energyplus-shading.csv" ]] && grep -q "no energyplus-shading.csv: step_minutes 90" "$WORK/step90.out"; then
  pass "a model at 90 minutes without the flag: no CSV, and the summary says why"
else
  fail "a model at 90 minutes" "$(grep -i energyplus "$WORK/step90.out")"
fi

# A month: at most 48 per-instant files by default, spread over it, and the summary says so;
# --every 1 asks for them all.
"$SHADOW" series "$WORK/model.idf" -o "$WORK/month" --from 2023-06-01 --to 2023-06-30 --step 60 \
  >"$WORK/month.out" 2>/dev/null || fail "month" "exit $?"
n=$(instants "$WORK/month")
files=$(count "$WORK/month/series")
if [[ $n -gt 300 && $files -gt 0 && $files -le 48 ]] && grep -q "series.pvd shows $files of the $n instants" "$WORK/month.out"; then
  pass "a month: $files of $n instants written, and said"
else
  fail "a month: bounded" "$files files for $n instants: $(grep series "$WORK/month.out")"
fi
"$SHADOW" series "$WORK/model.idf" -o "$WORK/month" --from 2023-06-01 --to 2023-06-30 --step 60 --every 1 -q ||
  fail "month --every 1" "exit $?"
if [[ $(count "$WORK/month/series") -eq $n ]]; then pass "a month with --every 1: all $n"; else
  fail "a month with --every 1" "$(count "$WORK/month/series") files for $n instants"; fi
if "$SHADOW" series --help | grep -q "at most 48 instants"; then pass "--help says the default"; else
  fail "--help says the default" "not in --help"; fi

# shadow render loads what series loads.
if "$SHADOW" render --help 2>/dev/null | grep -q -- "--planarity-tolerance" || ! "$SHADOW" render --help >/dev/null 2>&1; then
  pass "render has --planarity-tolerance (or no render)"; else fail "render --planarity-tolerance" "not in --help"; fi

cli_test_end
