#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# An extended light in ParaView: `shadow compute` on the sun-disk example, then open_result.py
# headless; the left view must colour the light's fragments by `visibility` with a 0-1 legend
# titled "visible part" (docs/area-light-visibility.md), and the fragments file must carry the
# array. Usage: test_visibility_view.sh SOURCE_DIR SHADOW_BINARY WORK_DIR
set -euo pipefail
source_dir="$1" shadow="$2" work="$3"
rm -rf "$work"
mkdir -p "$work"
"$shadow" compute "$source_dir/examples/area-light/sun-disk.json" -o "$work/result" >/dev/null
log="$work/log.txt"
status=0
"$source_dir/tools/paraview/pvpython.sh" "$source_dir/tools/paraview/open_result.py" "$work/result" \
  --light 0 --screenshot "$work/view.png" --size 1200 500 --describe "$work/view.json" >"$log" 2>&1 || status=$?
if [[ $status -eq 2 ]] && grep -q "^pvpython.sh: no pvpython" "$log"; then
  cat "$log"
  exit 77  # no ParaView Python on this machine
fi
cat "$log"
grep -q "^open_result: ok, wrote " "$log" || { echo "FAIL: open_result.py gave no verdict"; exit 1; }
/usr/bin/python3 - "$work/view.json" <<'PY'
import json, sys
views = json.load(open(sys.argv[1]))["views"]
bars = views[0]["bars"]
assert len(bars) == 1, bars
bar = bars[0]
assert bar["title"] == "visible part", bar["title"]
assert bar["range"] == [0.0, 1.0], bar["range"]
assert bar["custom_labels"] == [0.0, 0.25, 0.5, 0.75, 1.0], bar["custom_labels"]
assert not bar["categorical"]
PY
grep -q 'Name="visibility"' "$work/result/fragments.vtp" || { echo "FAIL: no visibility array"; exit 1; }
echo "test_visibility_view: ok"
