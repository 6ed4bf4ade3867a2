#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow series --tile-casters N --fast-tile-casters N` (docs/tiles.md): exact tiles change no
# bit, so a series without tiles (0 0) and with thresholds small enough to split the ground, the
# walls and the roofs of a small city (1 and 3) write the same sunlit.csv, energyplus-shading.csv,
# faces.vtp and per-instant datasets byte for byte, and report.json differs only in run.options
# (the thresholds, named when not the defaults) and in the stats' candidate counts. Fast tiles
# stay within the fast path's bounds of the exact sun hours. Bad values are one usage error line
# (exit 2), as for `shadow compute`; a checkpoint of other thresholds is refused on --resume.
#
# Usage: bash test_series_tiles.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin series-tiles 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
SCENE=$2/sun/scene.json

# Two June days in Berlin, hourly (34 instants above the horizon), every third instant's dataset.
ARGS=(--from 2026-06-20 --to 2026-06-21 --every 3 -t 2 -q --energyplus-shading)
run() {  # run NAME ARGS...: one series into $WORK/NAME
  local name=$1
  shift
  "$SHADOW" series "$SCENE" -o "$WORK/$name" "${ARGS[@]}" "$@" 2>"$WORK/$name.err" || fail "$name" "exit $?: $(cat "$WORK/$name.err")"
}
run default
run whole --tile-casters 0 --fast-tile-casters 0
run tiled1 --tile-casters 1 --fast-tile-casters 1
run tiled3 --tile-casters 3 --fast-tile-casters 3

# The area files, byte for byte.
for tiled in tiled1 tiled3 default; do
  files=$(cd "$WORK/whole" && find . -type f ! -name report.json | sort)
  theirs=$(cd "$WORK/$tiled" && find . -type f ! -name report.json | sort)
  if [[ "$files" != "$theirs" ]]; then
    fail "$tiled: same files" "$(diff <(echo "$files") <(echo "$theirs") | tr '\n' ' ')"
    continue
  fi
  differing=""
  while read -r f; do same_file "$WORK/whole" "$WORK/$tiled" "$f" || differing+=" $f"; done <<<"$files"
  [[ -z "$differing" ]] && pass "$tiled: $(echo "$files" | wc -l) files byte-identical to the untiled series" ||
    fail "$tiled: byte-identical" "differ:$differing"
done

# report.json: the same faces, surfaces and series; the thresholds in run.options only when not
# the defaults; the tiled runs did split receivers (more candidate pairs: a caster is counted
# once per tile that it reaches; stats.tiled_receivers and stats.tiles count the splits).
if python3 - "$WORK" <<'PY'
import json, sys
work = sys.argv[1]
r = {n: json.load(open(f"{work}/{n}/report.json")) for n in ("default", "whole", "tiled1", "tiled3")}
for n in ("default", "tiled1", "tiled3"):
    for key in r["whole"]:
        if key not in ("run", "stats"):
            assert r[n][key] == r["whole"][key], (n, key)
    for key in ("receivers", "back_facing", "unshadowed"):
        assert r[n]["stats"][key] == r["whole"]["stats"][key], (n, key)
options = {n: r[n]["run"]["options"] for n in r}
assert "tile_casters" not in options["default"] and "fast_tile_casters" not in options["default"], options
assert options["whole"]["tile_casters"] == 0 and options["whole"]["fast_tile_casters"] == 0, options
assert options["tiled1"]["tile_casters"] == 1 and options["tiled3"]["fast_tile_casters"] == 3, options
assert r["tiled1"]["stats"]["candidate_pairs"] > r["whole"]["stats"]["candidate_pairs"]
assert r["default"]["stats"] == r["whole"]["stats"]  # the defaults split nothing here
# The splits are counted (summed over the instants), and only where there were any.
for n in ("tiled1", "tiled3"):
    st = r[n]["stats"]
    assert 0 < st["tiled_receivers"] <= st["receivers"] and st["tiles"] >= 2 * st["tiled_receivers"], (n, st)
assert "tiled_receivers" not in r["whole"]["stats"] and "tiles" not in r["whole"]["stats"]
PY
then
  pass "report.json: same areas, thresholds in run.options, more candidate pairs when tiled"
else
  fail "report.json" "see the Python assertion above"
fi

# The fast path: tiled and untiled sun hours both within their bounds of the exact ones.
run fast_whole --fast --fast-tile-casters 0
run fast_tiled --fast --fast-tile-casters 1
if python3 - "$WORK" <<'PY'
import json, sys
work = sys.argv[1]
exact = {f["id"]: f["sun_hours"] for f in json.load(open(f"{work}/whole/report.json"))["faces"]}
for n in ("fast_whole", "fast_tiled"):
    report = json.load(open(f"{work}/{n}/report.json"))
    for f in report["faces"]:
        assert abs(f["sun_hours"] - exact[f["id"]]) <= f["sun_hours_error_bound"] + 1e-12, (n, f["id"])
assert json.load(open(f"{work}/fast_tiled/report.json"))["run"]["options"]["fast_tile_casters"] == 1
PY
then
  pass "fast: tiled and untiled sun hours within their bounds"
else
  fail "fast" "see the Python assertion above"
fi

# Bad values: one line, exit 2, nothing written (the checks of `shadow compute`'s options).
expect_usage_error() {  # NAME PART ARGS...
  local name=$1 part=$2
  shift 2
  local status=0
  "$SHADOW" series "$SCENE" -o "$WORK/bad-$name" "$@" >/dev/null 2>"$WORK/$name.err" || status=$?
  if [[ $status -eq 2 && $(wc -l <"$WORK/$name.err") -eq 1 ]] && grep -q "^shadow: error: .*$part" "$WORK/$name.err" &&
     [[ ! -e "$WORK/bad-$name" ]]; then
    pass "bad value refused ($name)"
  else
    fail "bad value ($name)" "exit $status: $(cat "$WORK/$name.err")"
  fi
}
expect_usage_error negative '--tile-casters: expected a whole number from 0 to 1000000000, got "-1"' --tile-casters -1
expect_usage_error fraction '--fast-tile-casters: expected a whole number from 0 to 1000000000, got "1.5"' \
  --fast-tile-casters 1.5
expect_usage_error word '--tile-casters: expected a whole number' --tile-casters many
expect_usage_error missing "--fast-tile-casters" --fast-tile-casters

# --resume: a checkpoint of other tile thresholds (of the run's arithmetic) is refused; the
# same thresholds resume to the uninterrupted run's files.
status=0
"$SHADOW" series "$SCENE" -o "$WORK/stopped" "${ARGS[@]}" --tile-casters 1 --checkpoint --stop-after 8 2>/dev/null ||
  status=$?
[[ $status -eq 5 ]] && pass "stopped with a checkpoint" || fail "stopped" "exit $status"
cp -r "$WORK/stopped" "$WORK/stopped-other"
status=0
"$SHADOW" series "$SCENE" -o "$WORK/stopped-other" "${ARGS[@]}" --tile-casters 3 --resume 2>"$WORK/other.err" || status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/other.err") -eq 1 ]] &&
   grep -q "series.checkpoint: .*another scene or other options" "$WORK/other.err"; then
  pass "resume refused for other tile thresholds"
else
  fail "resume with other thresholds" "exit $status: $(cat "$WORK/other.err")"
fi
"$SHADOW" series "$SCENE" -o "$WORK/stopped" "${ARGS[@]}" --tile-casters 1 --fast-tile-casters 1 --resume 2>/dev/null ||
  fail "resume" "exit $?"
differing=""
for f in sunlit.csv energyplus-shading.csv faces.vtp; do cmp -s "$WORK/tiled1/$f" "$WORK/stopped/$f" || differing+=" $f"; done
cmp -s <(grep -v '"started_utc"' "$WORK/tiled1/report.json") <(grep -v '"started_utc"' "$WORK/stopped/report.json") ||
  differing+=" report.json"
[[ -z "$differing" ]] && pass "resumed with the same thresholds: the uninterrupted run's files" ||
  fail "resumed" "differ:$differing"

cli_test_end
