#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Install dependencies, build everything optimised (tests included), run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --tests
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)"
ctest --preset release -j "$(nproc)" "$@"
