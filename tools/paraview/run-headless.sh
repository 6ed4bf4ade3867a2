#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a command with a private virtual X server: tools/paraview/run-headless.sh COMMAND [ARGS...]
#
# For VTK and ParaView rendering on a machine without a display (Debian's VTK 9.1 needs X even
# off screen). Unlike `xvfb-run -a`, which picks a display number from lock files and races
# when two start at once, Xvfb chooses a free display itself (-displayfd) and says which when
# it is ready. The server is stopped when the command ends, however it ends. -noreset: by
# default an X server resets when its last client disconnects and refuses connections while it
# does; VTK opens and closes a connection per render window, and on a loaded machine the next
# window then finds no server ("bad X server connection") and VTK aborts.
set -uo pipefail
if (($# < 1)); then
  echo "usage: $0 COMMAND [ARGS...]" >&2
  exit 2
fi
if ! command -v Xvfb >/dev/null; then
  echo "run-headless.sh: no Xvfb (Debian packages xvfb and xauth)" >&2
  exit 2
fi

scratch="$(mktemp -d)"
server=""
cleanup() {
  if [[ -n "$server" ]]; then
    kill "$server" 2>/dev/null
    wait "$server" 2>/dev/null
  fi
  rm -rf "$scratch"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

mkfifo "$scratch/display"
Xvfb -displayfd 3 -screen 0 "${LIBSHADOW_XVFB_SCREEN:-1920x1080x24}" -nolisten tcp -noreset \
  3>"$scratch/display" 2>"$scratch/xvfb.log" &
server=$!
display=""
read -r -t 60 display <"$scratch/display"
if [[ -z "$display" ]]; then
  echo "run-headless.sh: Xvfb did not start: $(tail -n 3 "$scratch/xvfb.log" | tr '\n' ' ')" >&2
  exit 2
fi
DISPLAY=":$display" "$@"
