#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Newcomer's first command: install dependencies, build (release), and compute the shadows of
# the bundled default scene into out/default.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target shadow -j "$(nproc)"
./build/release/bin/shadow compute examples/default/scene.json -o out/default "$@"
