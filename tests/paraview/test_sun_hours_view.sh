#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The sun-hours view of tools/paraview/open_result.py, headless: a small city's exact sun-hours
# map (shadow-bench sun-hours --write) opened alone (one view) and beside a full result (three
# views); each screenshot must have the requested size and show the map's colour bands: at
# least four distinct hour colours of the Inferno map over a good part of the picture.
# Usage: test_sun_hours_view.sh SOURCE_DIR SHADOW_BENCH WORK_DIR
set -euo pipefail
source_dir="$1" bench="$2" work="$3"
rm -rf "$work"
mkdir -p "$work/map-only"
"$bench" sun-hours --boxes 6 --instants 12 --threads 2 --write "$work/full" >/dev/null
cp "$work/full/sun_hours.vtp" "$work/full/faces.vtp" "$work/map-only/"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
for case in map-only full; do
  status=0
  "$source_dir/tools/paraview/pvpython.sh" "$source_dir/tools/paraview/open_result.py" "$work/$case" \
    --screenshot "$work/$case.png" --size 900 600 --describe "$work/$case.json" >"$log" 2>&1 || status=$?
  if [[ $status -eq 2 ]] && grep -q "^pvpython.sh: no pvpython" "$log"; then
    cat "$log"
    exit 77  # ctest SKIP_RETURN_CODE: this machine has no ParaView Python
  fi
  cat "$log"
  grep -q "^open_result: ok, wrote " "$log" || { echo "FAIL: open_result.py gave no verdict ($case)"; exit 1; }
  /usr/bin/python3 - "$work/$case.png" <<'PY'
import sys

import vtk

reader = vtk.vtkPNGReader()
reader.SetFileName(sys.argv[1])
reader.Update()
image = reader.GetOutput()
dims = image.GetDimensions()
scalars = image.GetPointData().GetScalars()
# Inferno's bands run from near-black purple through red and orange to pale yellow: saturated
# pixels whose red exceeds blue. Count the distinct ones (coarsely) and their share.
bands = set()
warm = 0
for i in range(scalars.GetNumberOfTuples()):
    r, g, b = (int(scalars.GetComponent(i, c)) for c in range(3))
    if max(r, g, b) - min(r, g, b) > 60 and r > b:
        warm += 1
        bands.add((r >> 5, g >> 5, b >> 5))
share = warm / scalars.GetNumberOfTuples()
print(f"sun-hours view: {dims[0]}x{dims[1]}, map colours cover {100 * share:.1f}%, {len(bands)} colour groups")
if (dims[0], dims[1]) != (900, 600) or share < 0.05 or len(bands) < 4:
    print("FAIL: the sun-hours map is not visible as expected")
    sys.exit(1)
PY
  # The map framed and clear of its bar, which reads hours in fixed point.
  /usr/bin/python3 "$source_dir/tests/paraview/check_layout.py" "$work/$case.json" 0.3
done
echo "test_sun_hours_view: ok"
