#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The lighting gallery of docs/lighting.md: the default scene under every lighting model and
# shading method, 480x360 PNGs in docs/img/lighting/.
#
# Usage: bash scripts/make-gallery.sh [SHADOW_BINARY]   (default: build/release/bin/shadow)
# Without a display `shadow render` starts itself under xvfb-run.
set -euo pipefail
cd "$(dirname "$0")/.."
SHADOW=${1:-build/release/bin/shadow}
OUT=docs/img/lighting
mkdir -p "$OUT"
for model in ambient lambert half-lambert modified-half-lambert phong blinn-phong; do
  for shading in flat gouraud phong; do
    "$SHADOW" render examples/default/scene.json -o "$OUT/$model-$shading.png" \
      --width 480 --height 360 --model "$model" --shading "$shading" --quiet
    echo "$OUT/$model-$shading.png"
  done
done
