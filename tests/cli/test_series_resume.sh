#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow series --checkpoint / --resume` (docs/cluster.md): a run stopped part-way (the
# --stop-after test hook, exit 5) leaves no file that looks complete, only its checkpoint; the
# resumed run computes the rest and writes every file byte for byte as an uninterrupted run
# does (report.json's run.started_utc aside, which no two runs share). A checkpoint whose last
# record was cut short (a kill mid-write) is resumed from its last whole record; a checkpoint of
# another scene or arithmetic is refused with one line and exit 2.
#
# Usage: bash test_series_resume.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin series-resume 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
SCENE=$2/sun/scene.json

# Three June days in Berlin, hourly at mid-hour (--energyplus-shading places the suns where EnergyPlus takes them): 48 instants above the horizon, with the exact sun-hours map
# of two meshes, every second instant's dataset and its fragments.
ARGS=(--from 2026-06-01 --to 2026-06-03 --sun-hours-map tower,ground --every 2 --fragments --energyplus-shading -t 1 -q)
TALK=("${ARGS[@]:0:${#ARGS[@]}-1}")  # without -q: the resume note is printed

"$SHADOW" series "$SCENE" -o "$WORK/whole" "${ARGS[@]}" || fail reference "exit $?"
[[ -f "$WORK/whole/report.json" && -f "$WORK/whole/sun_hours.vtp" ]] && pass "reference run" || fail "reference run" "no report.json or sun_hours.vtp"

# Stopped after the first rounds: exit 5, one line naming the checkpoint, nothing that looks done.
status=0
"$SHADOW" series "$SCENE" -o "$WORK/stopped" "${ARGS[@]}" --checkpoint --stop-after 10 2>"$WORK/stop.err" || status=$?
if [[ $status -eq 5 && $(wc -l <"$WORK/stop.err") -eq 1 ]] && grep -q "series.checkpoint" "$WORK/stop.err" &&
   grep -q -- "--resume" "$WORK/stop.err"; then
  pass "stopped: exit 5, one line naming the checkpoint"
else
  fail "stopped" "exit $status, stderr: $(cat "$WORK/stop.err")"
fi
left=$(cd "$WORK/stopped" && find . -type f ! -name series.checkpoint | sort | tr '\n' ' ')
[[ -z "$left" && -f "$WORK/stopped/series.checkpoint" ]] && pass "stopped: only the checkpoint in OUTDIR" ||
  fail "stopped: only the checkpoint" "found: $left"
cp -r "$WORK/stopped" "$WORK/torn"
cp -r "$WORK/stopped" "$WORK/other"

# Another scene (the tower one metre taller) and the other arithmetic are refused.
sed 's/, 30\]/, 31]/g' "$SCENE" >"$WORK/taller.json"
for variant in "taller:$WORK/taller.json:" "fast:$SCENE:--fast"; do
  IFS=: read -r name scene extra <<<"$variant"
  status=0
  # shellcheck disable=SC2086
  "$SHADOW" series "$scene" -o "$WORK/other" "${ARGS[@]}" --resume $extra 2>"$WORK/$name.err" || status=$?
  if [[ $status -eq 2 && $(wc -l <"$WORK/$name.err") -eq 1 ]] && grep -q "series.checkpoint: .*another scene or other options" "$WORK/$name.err" &&
     [[ -f "$WORK/other/series.checkpoint" && ! -f "$WORK/other/report.json" ]]; then
    pass "resume refused for a changed input ($name)"
  else
    fail "resume refused ($name)" "exit $status, stderr: $(cat "$WORK/$name.err")"
  fi
done

# Resumed: the rest computed, the files the uninterrupted run's, the checkpoint gone.
"$SHADOW" series "$SCENE" -o "$WORK/stopped" "${TALK[@]}" --resume 2>"$WORK/resume.err" >/dev/null || fail resume "exit $?"
grep -q "resuming from .*: 16 of 48 instants done" "$WORK/resume.err" && pass "resume reads 16 of 48 instants (two rounds of 8)" ||
  fail "resume count" "$(cat "$WORK/resume.err")"
same_outputs "resumed run equals the uninterrupted one" "$WORK/whole" "$WORK/stopped"
[[ ! -e "$WORK/stopped/series.checkpoint" ]] && pass "checkpoint removed when complete" || fail "checkpoint removed" "still there"

# A kill in the middle of appending a record: the torn record (the file's last 100 bytes cut
# off) is dropped and its instants computed again.
size=$(stat -c %s "$WORK/torn/series.checkpoint")
truncate -s $((size - 100)) "$WORK/torn/series.checkpoint"
"$SHADOW" series "$SCENE" -o "$WORK/torn" "${TALK[@]}" --resume 2>"$WORK/torn.err" >/dev/null || fail "torn resume" "exit $?"
grep -q "8 of 48 instants done (an unfinished last record was dropped)" "$WORK/torn.err" &&
  pass "torn last record dropped" || fail "torn record" "$(cat "$WORK/torn.err")"
same_outputs "resumed from a torn checkpoint" "$WORK/whole" "$WORK/torn"

# --resume without a checkpoint starts afresh (a job script may always pass it); --checkpoint
# alone gives the same files too.
"$SHADOW" series "$SCENE" -o "$WORK/fresh" "${ARGS[@]}" --resume 2>/dev/null || fail "fresh resume" "exit $?"
same_outputs "--resume without a checkpoint" "$WORK/whole" "$WORK/fresh"
"$SHADOW" series "$SCENE" -o "$WORK/checkpointed" "${ARGS[@]}" --checkpoint || fail "checkpointed" "exit $?"
same_outputs "--checkpoint, uninterrupted" "$WORK/whole" "$WORK/checkpointed"

# Not a checkpoint at all: refused with one line.
mkdir -p "$WORK/junk" && echo "not a checkpoint" >"$WORK/junk/series.checkpoint"
status=0
"$SHADOW" series "$SCENE" -o "$WORK/junk" "${ARGS[@]}" --resume 2>"$WORK/junk.err" || status=$?
[[ $status -eq 2 && $(wc -l <"$WORK/junk.err") -eq 1 ]] && grep -q "not a shadow series checkpoint" "$WORK/junk.err" &&
  pass "junk checkpoint refused" || fail "junk checkpoint" "exit $status: $(cat "$WORK/junk.err")"

# A checkpoint that is no regular file gets the rules of scene files: a FIFO would block the read
# forever and a link to /dev/zero would fill the memory; each is one line and exit 2, at once
# (a time limit catches a read that blocks), and OUTDIR keeps no result.
expect_refused_checkpoint() {
  local name=$1 words=$2
  local status=0
  timeout 20 "$SHADOW" series "$SCENE" -o "$WORK/$name" "${ARGS[@]}" --resume 2>"$WORK/$name.err" || status=$?
  if [[ $status -eq 2 && $(wc -l <"$WORK/$name.err") -eq 1 ]] &&
     grep -q "^shadow: error: .*$name/series.checkpoint: .*$words" "$WORK/$name.err" && [[ ! -e "$WORK/$name/report.json" ]]; then
    pass "checkpoint refused: $name"
  else
    fail "checkpoint refused: $name" "exit $status: $(head -c 300 "$WORK/$name.err")"
  fi
}
mkdir -p "$WORK/fifo" && mkfifo "$WORK/fifo/series.checkpoint"
expect_refused_checkpoint fifo "not a regular file"
mkdir -p "$WORK/zero" && ln -s /dev/zero "$WORK/zero/series.checkpoint"
expect_refused_checkpoint zero "not a regular file"
mkdir -p "$WORK/dir/series.checkpoint"
expect_refused_checkpoint dir "Is a directory"
# A regular file longer than any checkpoint of this run can be (the example's whole checkpoint
# holds a few kilobytes) is refused before it is read.
mkdir -p "$WORK/big" && cp "$WORK/junk/series.checkpoint" "$WORK/big/series.checkpoint" &&
  truncate -s 64M "$WORK/big/series.checkpoint"
expect_refused_checkpoint big "larger than the limit of [0-9]* bytes (the most a checkpoint of this run can hold"

cli_test_end
