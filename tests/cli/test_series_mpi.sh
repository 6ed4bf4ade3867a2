#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `mpirun -np N shadow series` (docs/cluster.md): 2 and 3 ranks on one machine write every file
# byte for byte as one process does (report.json's run.started_utc aside), the exact sun-hours
# map included; a run stopped on 3 ranks resumes on 2; an input error on one rank stops every
# rank with one message, exit 2 and no OUTDIR; ranks that read different scenes are refused; and
# a plain `shadow` (no launcher) never initialises MPI: it runs with an MPI environment that
# would make MPI_Init fail.
#
# Usage: bash test_series_mpi.sh /path/to/shadow /path/to/examples /path/to/mpiexec
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin series-mpi 3 "SHADOW_BINARY EXAMPLES_DIR MPIEXEC" "$@"
SHADOW=$1
SCENE=$2/sun/scene.json
MPIEXEC=$3

# Open MPI refuses root unless told, and more ranks than cores unless told (CI: 2 cores).
MPI_FLAGS=()
if "$MPIEXEC" --version 2>&1 | grep -q "Open MPI\|OpenRTE"; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  MPI_FLAGS+=(--oversubscribe)
  export OMPI_MCA_rmaps_base_oversubscribe=1
fi
mpi() { "$MPIEXEC" "${MPI_FLAGS[@]}" "$@"; }

ARGS=(--from 2026-06-01 --to 2026-06-03 --sun-hours-map tower,ground --every 2 --fragments --energyplus-shading -t 1 -q)

# The reference: one process, no launcher, with an MPI environment under which MPI_Init fails
# (no such point-to-point layer): it must not call it.
status=0
OMPI_MCA_pml=no_such_pml "$SHADOW" series "$SCENE" -o "$WORK/one" "${ARGS[@]}" 2>"$WORK/one.err" || status=$?
[[ $status -eq 0 && -f "$WORK/one/report.json" ]] && pass "plain run does not initialise MPI" ||
  fail "plain run" "exit $status: $(head -3 "$WORK/one.err")"

mpi -np 2 "$SHADOW" series "$SCENE" -o "$WORK/two" "${ARGS[@]}" || fail "2 ranks" "exit $?"
same_outputs "2 ranks equal 1 process" "$WORK/one" "$WORK/two"
[[ -f "$WORK/one/sun_hours.vtp" && -f "$WORK/one/fragments.pvd" ]] && pass "the files compared include the map and fragments" ||
  fail "compared files" "no sun_hours.vtp or fragments.pvd"

# The summary on stdout comes from rank 0 alone and names the ranks.
mpi -np 2 "$SHADOW" series "$SCENE" -o "$WORK/two-talk" "${ARGS[@]:0:${#ARGS[@]}-1}" >"$WORK/two.out" 2>/dev/null
[[ $(grep -c "^shadow .* series:" "$WORK/two.out") -eq 1 ]] && grep -q "on 2 MPI ranks" "$WORK/two.out" &&
  pass "one summary, from rank 0" || fail "summary" "$(cat "$WORK/two.out")"

# 3 ranks (uneven shares of instants and map faces), stopped, then resumed on 2.
status=0
mpi -np 3 "$SHADOW" series "$SCENE" -o "$WORK/three" "${ARGS[@]}" --checkpoint --stop-after 5 2>"$WORK/three.err" || status=$?
[[ $status -eq 5 && $(grep -c "^shadow:" "$WORK/three.err") -eq 1 && ! -f "$WORK/three/report.json" ]] &&
  pass "3 ranks stopped: exit 5, one message" || fail "3 ranks stopped" "exit $status: $(grep "^shadow" "$WORK/three.err")"
mpi -np 2 "$SHADOW" series "$SCENE" -o "$WORK/three" "${ARGS[@]}" --resume || fail "resume on 2 ranks" "exit $?"
same_outputs "stopped on 3 ranks, resumed on 2" "$WORK/one" "$WORK/three"

# An input error on rank 1 only (its scene is missing): every rank stops, rank 0 prints the one
# line, exit 2, no OUTDIR.
status=0
mpi -np 1 "$SHADOW" series "$SCENE" -o "$WORK/err" -q : -np 1 "$SHADOW" series "$WORK/missing.json" -o "$WORK/err" -q \
  2>"$WORK/err.err" || status=$?
if [[ $status -eq 2 && $(grep -c "^shadow" "$WORK/err.err") -eq 1 ]] &&
   grep -q "^shadow: rank 1: error: .*missing.json" "$WORK/err.err" && [[ ! -e "$WORK/err" ]]; then
  pass "an input error on one rank stops all: one line, exit 2, no OUTDIR"
else
  fail "error on one rank" "exit $status: $(grep "^shadow" "$WORK/err.err")"
fi

# Ranks that read different scenes (a node with another copy) are refused.
sed 's/, 30\]/, 31]/g' "$SCENE" >"$WORK/taller.json"
status=0
mpi -np 1 "$SHADOW" series "$SCENE" -o "$WORK/differ" -q : -np 1 "$SHADOW" series "$WORK/taller.json" -o "$WORK/differ" -q \
  2>"$WORK/differ.err" || status=$?
[[ $status -eq 2 && $(grep -c "^shadow" "$WORK/differ.err") -eq 1 ]] && grep -q "rank 1: error: .*another scene" "$WORK/differ.err" &&
  pass "ranks with different scenes refused" || fail "different scenes" "exit $status: $(grep "^shadow" "$WORK/differ.err")"

cli_test_end
