#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a ParaView Python script headless: tools/paraview/pvpython.sh SCRIPT.py [ARGS...]
#
# Uses the system's pvpython when python3-paraview is installed; otherwise the copy that
# scripts/setup-pvpython.sh unpacked beside libshadow's build dependencies (Debian 12's
# python3-paraview conflicts with libvtk9-dev). Rendering is offscreen; without a DISPLAY the
# script runs under a private virtual X server (run-headless.sh beside this script, or one level up where installed: Debian's xvfb).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
prefix="${LIBSHADOW_PVPYTHON_PREFIX:-/opt/libshadow/python3-paraview}"

if (($# < 1)); then
  echo "usage: $0 SCRIPT.py [ARGS...]" >&2
  exit 2
fi

command=()
if dpkg-query -W -f='${Status}' python3-paraview 2>/dev/null | grep -q "install ok installed"; then
  command=(pvpython --force-offscreen-rendering "$@")
elif [[ -x "$prefix/usr/bin/pvpython" ]]; then
  export LIBSHADOW_PVPYTHON_SITE="$prefix/usr/lib/python3/dist-packages"
  command=("$prefix/usr/bin/pvpython" --force-offscreen-rendering "$here/pv_bootstrap.py" "$@")
else
  echo "pvpython.sh: no pvpython: install python3-paraview, or run scripts/setup-pvpython.sh" >&2
  exit 2
fi

if [[ -z "${DISPLAY:-}" ]]; then
  # A private Xvfb (run-headless.sh: installed one level up, in share/libshadow; beside it in the source tree).
  headless="$here/../run-headless.sh"
  [[ -x "$headless" ]] || headless="$here/run-headless.sh"
  command=("$headless" "${command[@]}")
fi
exec "${command[@]}"
