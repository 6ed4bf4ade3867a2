#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes the pictures of docs/gallery.md: plain scenes without materials (examples/gallery/,
# examples/sun/) under `shadow render`'s defaults, and the default scene before and after.
# Usage: scripts/make-render-gallery.sh [SHADOW]   (default: build/release/bin/shadow)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
shadow="${1:-$root/build/release/bin/shadow}"
out="$root/docs/img/gallery"
mkdir -p "$out"
size=(--width 640 --height 480)
for scene in boxes far room sun_and_lamp; do
  "$shadow" render "$root/examples/gallery/$scene.json" -o "$out/$scene.png" "${size[@]}" --quiet
done
"$shadow" render "$root/examples/gallery/sun_and_lamp.json" -o "$out/sun_and_lamp-legend.png" "${size[@]}" \
  --legend --compass on --quiet
"$shadow" render "$root/examples/sun/scene.json" -o "$out/sun-day.png" "${size[@]}" --legend --quiet
# The look before issue 17: white material, no exposure, the whole scene framed.
old=(--colours white --exposure 1 --tone clip --frame scene)
"$shadow" render "$root/examples/gallery/sun_and_lamp.json" -o "$out/sun_and_lamp-before.png" "${size[@]}" \
  "${old[@]}" --quiet
"$shadow" render "$root/examples/sun/scene.json" -o "$out/sun-day-before.png" "${size[@]}" "${old[@]}" \
  --compass off --quiet
"$shadow" render "$root/examples/default/scene.json" -o "$out/default.png" "${size[@]}" --quiet
"$shadow" render "$root/examples/default/scene.json" -o "$out/default-before.png" "${size[@]}" \
  --exposure 1 --tone clip --frame scene --quiet
ls -l "$out"
