#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Out of memory (README's exit status 6): `shadow compute` on a generated scene under a series of
# `ulimit -v` limits, from the smallest at which the program starts at all to one at which the
# run completes. Every run must end one of two ways: complete (status 0, report.json), or one
# line `shadow: error: out of memory while STAGE (...)`, status 6, no report.json, no complete
# output left. Before, GMP's "Cannot allocate memory" and SIGABRT, or "internal error:
# std::bad_alloc" with status 4. The limits are relative to what this binary needs to start
# (jemalloc's and the threads' reservations count), so the check does not depend on the
# machine.
#
# Usage: bash test_cli_out_of_memory.sh /path/to/shadow
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-out-of-memory 1 "SHADOW_BINARY" "$@"
SHADOW=$1

# A city of boxes on a ground under a sun and a lamp, with polygons: enough exact numbers that
# the computation needs a few hundred MB more than starting does.
python3 - "$WORK/scene.json" <<'PY'
import json, sys
meshes = [{"name": "ground", "polygons": [[[-5, -5, 0], [125, -5, 0], [125, 125, 0], [-5, 125, 0]]]}]
boxes = []
for i in range(24):
    for j in range(24):
        x, y, h = 5 * i + 0.5, 5 * j + 0.25, 2 + (i * 7 + j * 3) % 9
        a, b = (x, y), (x + 2.5 + 0.125 * (j % 3), y + 3)
        def q(*p): return [list(v) for v in p]
        boxes += [q((a[0], a[1], h), (b[0], a[1], h), (b[0], b[1], h), (a[0], b[1], h)),
                  q((a[0], a[1], 0), (b[0], a[1], 0), (b[0], a[1], h), (a[0], a[1], h)),
                  q((b[0], a[1], 0), (b[0], b[1], 0), (b[0], b[1], h), (b[0], a[1], h)),
                  q((b[0], b[1], 0), (a[0], b[1], 0), (a[0], b[1], h), (b[0], b[1], h)),
                  q((a[0], b[1], 0), (a[0], a[1], 0), (a[0], a[1], h), (a[0], b[1], h))]
meshes.append({"name": "boxes", "polygons": boxes})
scene = {"meshes": meshes,
         "lights": [{"name": "sun", "type": "directional", "to_light": [0.31, 0.17, 0.4]},
                    {"name": "lamp", "type": "point", "position": [61.3, 58.7, 14.5]}]}
json.dump(scene, open(sys.argv[1], "w"))
PY

# run_limited KB OUT ARGS...: `shadow` under `ulimit -v KB`; stdout and stderr in OUT.{stdout,stderr}.
run_limited() {
  local kb=$1 out=$2
  shift 2
  (ulimit -v "$kb" && exec "$SHADOW" "$@") >"$out.stdout" 2>"$out.stderr"
}

# The smallest limit (to 8 MiB) at which `shadow --version` runs: what starting costs.
low=16384 high=$((64 * 1024 * 1024))
if ! run_limited "$high" "$WORK/version" --version; then
  fail "start" "shadow --version fails even under a 64 GiB limit: $(cat "$WORK/version.stderr")"
  cli_test_end
  exit
fi
while ((high - low > 8192)); do
  mid=$(((low + high) / 2))
  # (A subshell of its own: the dynamic loader or the allocator may die of a tiny limit.)
  if (run_limited "$mid" "$WORK/version" --version) 2>/dev/null; then high=$mid; else low=$mid; fi
done
start_kb=$high

# A complete run first (the reference: what a run needs to succeed at all).
status=0
"$SHADOW" compute "$WORK/scene.json" -o "$WORK/free" --threads 2 --quiet 2>"$WORK/free.stderr" || status=$?
if [[ $status -eq 0 && -s "$WORK/free/report.json" ]]; then
  pass "complete run without a limit"
else
  fail "complete run without a limit" "status $status: $(cat "$WORK/free.stderr")"
fi

# From the start-up cost upwards, in steps of 8 MiB, then larger steps until a run completes.
declare -A stages=()
oom=0 completed=0 bad=0
limit=$((start_kb + 4096))
step=$((8 * 1024))
for attempt in $(seq 1 40); do
  out="$WORK/run$attempt"
  status=0
  (run_limited "$limit" "$out" compute "$WORK/scene.json" -o "$out.dir" --threads 2 --quiet) 2>/dev/null || status=$?
  lines=$(wc -l <"$out.stderr")
  if [[ $status -eq 0 && -s "$out.dir/report.json" ]]; then
    completed=$((completed + 1))
    break
  elif [[ $status -eq 6 && $lines -eq 1 && ! -e "$out.dir/report.json" ]] &&
       grep -Eq '^shadow: error: out of memory while (starting|loading the scene|preparing the faces|computing the shadows|writing the outputs) \(.*\); no report\.json was written$' "$out.stderr"; then
    oom=$((oom + 1))
    stage=$(sed -E 's/^shadow: error: out of memory while ([a-z ]+) \(.*/\1/' "$out.stderr")
    stages[$stage]=1
  else
    bad=$((bad + 1))
    fail "limit $limit KiB" "status $status, $lines lines: $(head -c 300 "$out.stderr")"
  fi
  # Nothing that looks complete in OUTDIR after a failed run.
  if [[ $status -ne 0 && -d "$out.dir" ]] && find "$out.dir" -name report.json | grep -q .; then
    fail "limit $limit KiB" "a report.json was left"
  fi
  rm -rf "$out.dir"
  limit=$((limit + step))
  if ((attempt >= 16)); then step=$((step * 2)); fi
done

if ((bad == 0)); then pass "every limited run either completed or reported out of memory (status 6, one line)"; fi
if ((oom >= 2 && ${#stages[@]} >= 2)); then
  pass "$oom runs out of memory, in ${#stages[@]} stages: ${!stages[*]}"
else
  fail "out of memory" "$oom runs ran out of memory, in ${#stages[@]} stages (start-up needs $start_kb KiB)"
fi
if [[ -n ${stages["computing the shadows"]+x} ]]; then
  pass "ran out while computing the shadows"
else
  fail "computing stage" "no run ran out while computing (stages: ${!stages[*]})"
fi
if ((completed == 1)); then pass "a large enough limit completes"; else fail "completion" "no limit completed"; fi

if "$SHADOW" --help | grep -q "6 out of memory" && "$SHADOW" compute --help | grep -q "6 out of memory"; then
  pass "help lists exit status 6"
else
  fail "help" "shadow --help or shadow compute --help lacks exit status 6"
fi

cli_test_end
