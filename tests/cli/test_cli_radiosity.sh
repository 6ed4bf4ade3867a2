#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow radiosity` (docs/radiosity.md): the furnace (a closed room whose faces all emit E and
# reflect rho has radiosity E / (1 - rho) everywhere) through the CLI, radiosity.vtp's arrays,
# report.json's balance, and bad input (one line naming file and place, exit 2, no report).
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

cli_test_end
