#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Opens a `shadow compute` result in ParaView headless (pvpython, offscreen, under Xvfb when
# there is no display) with the shipped script, saves a screenshot, and checks the picture;
# then opens scene.vtm as a ParaView user would and checks its blocks.
# Usage: test_open_result.sh SOURCE_DIR RESULT_DIR SCREENSHOT.png
set -euo pipefail
source_dir="$1" result="$2" screenshot="$3"

rm -f "$screenshot"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
status=0
"$source_dir/tools/paraview/pvpython.sh" "$source_dir/tools/paraview/open_result.py" "$result" \
  --light 0 --screenshot "$screenshot" --size 1200 500 --describe "${screenshot%.png}.json" >"$log" 2>&1 || status=$?
if [[ $status -eq 2 ]] && grep -q "^pvpython.sh: no pvpython" "$log"; then
  cat "$log"
  exit 77  # ctest SKIP_RETURN_CODE: this machine has no ParaView Python
fi
cat "$log"
# pvpython's own exit status can be spoiled by GLX teardown; the script's verdict line is what counts.
grep -q "^open_result: ok, wrote " "$log" || { echo "FAIL: open_result.py gave no verdict"; exit 1; }
/usr/bin/python3 "$source_dir/tests/paraview/check_screenshot.py" "$screenshot" 1200 500
# The model framed and clear of the colour bars, fixed-point labels, the light glyphs at the model.
/usr/bin/python3 "$source_dir/tests/paraview/check_layout.py" "${screenshot%.png}.json"

# The one-step way: File > Open scene.vtm.
"$source_dir/tools/paraview/pvpython.sh" "$source_dir/tests/paraview/open_vtm.py" "$result" >"$log" 2>&1 || true
cat "$log"
grep -q "^open_vtm: ok" "$log" || { echo "FAIL: ParaView did not open scene.vtm as expected"; exit 1; }
echo "test_open_result: ok"
