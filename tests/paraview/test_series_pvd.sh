#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ParaView (pvpython, headless) opens the series.pvd that test_series wrote (2028, hourly, every
# 24th instant: 168 time steps). Exit 77 (skipped) on a machine without ParaView Python.
set -uo pipefail
source_dir=$1
pvd=$2
steps=$3
log=$(mktemp)
status=0
"$source_dir/tools/paraview/pvpython.sh" "$source_dir/tests/paraview/check_series_pvd.py" "$pvd" "$steps" >"$log" 2>&1 ||
  status=$?
cat "$log"
if [[ $status -eq 2 ]] && grep -q "^pvpython.sh: no pvpython" "$log"; then
  rm -f "$log"
  exit 77  # ctest SKIP_RETURN_CODE: this machine has no ParaView Python
fi
# pvpython's exit status can be spoiled by GLX teardown: the script's verdict line counts.
grep -q "^check_series_pvd: ok" "$log"
result=$?
rm -f "$log"
exit $result
