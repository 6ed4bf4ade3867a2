#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The "Plane shadows" table of docs/benchmarks.md: plane shadows of the 10,000-box city at 40 and
# 5 degrees, 1 and 2 threads, wall and CPU time. With a library built from an older commit
# (BEFORE_LIB=DIR holding its libshadow.so.0), each row is run with it and then with this build,
# interleaved, so that both see the same load: the same shadow-bench binary, the old library
# through LD_LIBRARY_PATH (the public API it calls has not changed). About 3 minutes on 2 cores.
# REPEAT=N: each row the fastest of N runs (its CPU time with it).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release >/dev/null
cmake --build --preset release --target shadow-bench
bench=./build/release/bin/shadow-bench
sizes=${SIZES:-10000}
echo "| build | boxes | sun | threads | wall (s) | CPU (s) | peak (MiB) | polygons | regions | area (m^2) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for e in 40 5; do
  for t in 1 2; do
    if [ -n "${BEFORE_LIB:-}" ]; then
      LD_LIBRARY_PATH="$BEFORE_LIB" "$bench" planes --sizes "$sizes" --elevations "$e" --threads "$t" --repeat "${REPEAT:-1}" --label before | tail -1
    fi
    "$bench" planes --sizes "$sizes" --elevations "$e" --threads "$t" --repeat "${REPEAT:-1}" --label after | tail -1
  done
done
