#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the fuzz targets (CMake preset `fuzz`: clang, libFuzzer, ASan, UBSan) and runs each one
# deterministically (-seed=1, a fixed number of runs) from its seed corpus in tests/fuzz/corpus/.
# Exits non-zero when a target crashes, leaks, hits undefined behaviour, breaks an invariant or
# lets an exception other than shadow::InputError escape, and prints the reproducer's path.
# Needs clang-14 and libclang-rt-14-dev (scripts/install-deps.sh --tests). docs/testing.md.
#
#   bash scripts/run-fuzz.sh                      # the CI run (bounded, deterministic)
#   LIBSHADOW_FUZZ_RUNS=200000 bash scripts/run-fuzz.sh   # longer (runs per target)
#   LIBSHADOW_FUZZ_BUILD=0 bash scripts/run-fuzz.sh       # reuse build/fuzz as it is
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ "${LIBSHADOW_FUZZ_BUILD:-1}" == 1 ]]; then
  cmake --preset fuzz >/dev/null
  cmake --build --preset fuzz -j "$(nproc)"
fi

# Runs per target: sized so that all of them together take a few minutes on 2 cores (the engine
# runs the exact engine four times per accepted input). LIBSHADOW_FUZZ_RUNS overrides them all.
declare -A runs=([fuzz_scene]=100000 [fuzz_obj]=300000 [fuzz_engine]=12000 [fuzz_energyplus]=100000)
declare -A max_len=([fuzz_scene]=4096 [fuzz_obj]=4096 [fuzz_engine]=256 [fuzz_energyplus]=4096)
# The engine's inputs are short: let them reach 5 faces of 8 vertices at once (libFuzzer otherwise
# grows the length slowly and stays near 2 small faces for the whole bounded run).
declare -A extra=([fuzz_scene]="" [fuzz_obj]="" [fuzz_engine]="-len_control=0" [fuzz_energyplus]="")
# A cap on each target's time, so that a slow machine still ends (the run is then shorter, not
# different: libFuzzer with -seed=1 explores in the same order).
max_time="${LIBSHADOW_FUZZ_MAX_TIME:-150}"

export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"

work=build/fuzz/fuzz-run
rm -rf "$work"
status=0
for target in fuzz_scene fuzz_obj fuzz_engine fuzz_energyplus; do
  dir="$work/$target"
  mkdir -p "$dir/corpus" "$dir/artifacts"
  n="${LIBSHADOW_FUZZ_RUNS:-${runs[$target]}}"
  echo "run-fuzz: $target: $n runs from tests/fuzz/corpus/$target (log: $dir.log)"
  start=$SECONDS
  # New inputs go to the first folder (scratch), never into the source tree's corpus.
  if "build/fuzz/bin/$target" -seed=1 -runs="$n" -max_total_time="$max_time" -max_len="${max_len[$target]}" \
       -timeout=60 -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$dir/artifacts/" ${extra[$target]} \
       "$dir/corpus" "tests/fuzz/corpus/$target" >"$dir.log" 2>&1; then
    echo "run-fuzz: $target: ok in $((SECONDS - start)) s ($(grep -o 'stat::number_of_executed_units: [0-9]*' "$dir.log" | grep -o '[0-9]*$') inputs, $(find "$dir/corpus" -type f | wc -l) new in the corpus)"
  else
    status=1
    echo "run-fuzz: $target: FAILED after $((SECONDS - start)) s; the end of its log:"
    tail -n 60 "$dir.log"
    for reproducer in "$dir"/artifacts/*; do
      [[ -e "$reproducer" ]] || continue
      echo "run-fuzz: reproducer: $reproducer"
      echo "run-fuzz:   rerun it: build/fuzz/bin/$target $reproducer"
    done
  fi
done
exit "$status"
