#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Install dependencies, build everything optimised (tests included), run every test, then fuzz
# each parser and the engine for a bounded, deterministic time under ASan and UBSan
# (scripts/run-fuzz.sh: about 7 minutes on 2 cores, build included; LIBSHADOW_SKIP_FUZZ=1 skips
# it). docs/testing.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --tests
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
ctest --preset release -j "$(nproc)" "$@"
if [[ "${LIBSHADOW_SKIP_FUZZ:-0}" != 1 ]]; then
  bash scripts/run-fuzz.sh
fi
