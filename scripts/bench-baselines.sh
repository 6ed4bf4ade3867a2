#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Regenerates the "Exact against the baselines" part of docs/benchmarks.md: builds shadow-bench,
# runs the exact engine, the fast path, the shadow map and ray sampling on the standard scenes and the hard
# cases (2 threads each), and draws the speed/error plots. About 3 minutes on 2 cores.
# Needs /usr/bin/python3 with matplotlib (LIBSHADOW_WITH_EXTRAS=1 bash scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release >/dev/null
cmake --build --preset release --target shadow-bench
bench=./build/release/bin/shadow-bench
"$bench" compare --threads 2 --max-samples 9e8 --csv docs/bench-compare.csv --json docs/bench-compare.json \
  | tee /tmp/bench-compare.md
"$bench" hard-cases --threads 2 --csv docs/bench-hard-cases.csv | tee /tmp/bench-hard-cases.md
/usr/bin/python3 tools/bench/plot_speed_error.py docs/bench-compare.csv docs/img/bench-speed-error \
  | tee /tmp/bench-scaling.md
echo "bench-baselines: tables in /tmp/bench-compare.md, /tmp/bench-hard-cases.md, /tmp/bench-scaling.md"
