#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `shadow render`'s output file (issue 30, items 10 and 11): the staged-write rule of every
# output (a temporary name, a checked close, a rename; one line and exit 3 on failure, nothing
# under the final name), extensions it does not write refused, the output folder checked before
# any work.
#
# A full disk is simulated with a file size limit (`ulimit -f`, SIGXFSZ ignored): a write past
# the limit fails with EFBIG exactly where a full disk fails with ENOSPC, and it needs neither
# root, nor a mount, nor LD_PRELOAD.
#
# Usage: bash test_cli_render_output.sh /path/to/shadow /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-render-output 2 "SHADOW_BINARY EXAMPLES_DIR" "$@"
SHADOW=$1
EXAMPLES=$2
SCENE="$EXAMPLES/default/scene.json"

if ! "$SHADOW" render --help >/dev/null 2>&1; then
  echo "SKIP: this shadow was built without render"
  exit 77
fi

# one_error_line NAME STATUS EXPECTED_STATUS STDERR_FILE PART...: exit status, exactly one
# "shadow: error:" line on stderr containing every PART.
one_error_line() {
  local name=$1 status=$2 expected=$3 file=$4
  shift 4
  local stderr lines
  stderr=$(cat "$file")
  lines=$(wc -l <"$file")
  if [[ $status -ne $expected ]]; then
    fail "$name" "exit status $status, expected $expected: $stderr"
    return 1
  fi
  if [[ $lines -ne 1 || $stderr != "shadow: error: "* ]]; then
    fail "$name" "expected one 'shadow: error:' line, got $lines: $stderr"
    return 1
  fi
  local part
  for part in "$@"; do
    if [[ $stderr != *"$part"* ]]; then
      fail "$name" "stderr lacks '$part': $stderr"
      return 1
    fi
  done
  return 0
}

# ---- item 11: extensions and the output folder ---------------------------------------------------
for out in o.jpg noext o.PNG.bak; do
  status=0
  "$SHADOW" render "$SCENE" -o "$WORK/$out" >"$WORK/ext.stdout" 2>"$WORK/ext.stderr" || status=$?
  if one_error_line "render_refuses_$out" "$status" 2 "$WORK/ext.stderr" "--output" ".png" ".svg" ".pdf"; then
    if [[ -e "$WORK/$out" ]]; then
      fail "render_refuses_$out" "left $WORK/$out"
    else
      pass "render_refuses_$out"
    fi
  fi
done
# Upper case is the same type.
status=0
"$SHADOW" render "$SCENE" -o "$WORK/upper.SVG" --width 64 --height 48 -q 2>"$WORK/upper.stderr" || status=$?
if [[ $status -eq 0 && $(head -c 5 "$WORK/upper.SVG") == "<?xml" ]]; then
  pass "render_takes_upper_case_svg"
else
  fail "render_takes_upper_case_svg" "status $status: $(cat "$WORK/upper.stderr")"
fi

# A missing folder is found first: before the scene is even read (a bad scene would be exit 2).
echo '{"meshes": [' >"$WORK/broken.json"
for out in missing/view.svg missing/view.png missing/view.pdf; do
  status=0
  "$SHADOW" render "$WORK/broken.json" -o "$WORK/$out" >"$WORK/dir.stdout" 2>"$WORK/dir.stderr" || status=$?
  if one_error_line "render_missing_folder_${out##*.}" "$status" 3 "$WORK/dir.stderr" "$WORK/missing" \
      "does not exist"; then
    pass "render_missing_folder_${out##*.}"
  fi
done
touch "$WORK/plainfile"
status=0
"$SHADOW" render "$SCENE" -o "$WORK/plainfile/view.svg" >"$WORK/dir.stdout" 2>"$WORK/dir.stderr" || status=$?
one_error_line render_folder_is_a_file "$status" 3 "$WORK/dir.stderr" "plainfile" "not a directory" &&
  pass render_folder_is_a_file
mkdir -p "$WORK/adir.svg"
status=0
"$SHADOW" render "$SCENE" -o "$WORK/adir.svg" >"$WORK/dir.stdout" 2>"$WORK/dir.stderr" || status=$?
one_error_line render_output_is_a_folder "$status" 3 "$WORK/dir.stderr" "adir.svg" "is a directory" &&
  pass render_output_is_a_folder

# ---- item 10: a full disk --------------------------------------------------------------------
# full_disk NAME FILE ARGS...: `shadow render ARGS -o FILE` with a 2 KiB file size limit, FILE
# holding "old" before: exit 3, one line naming FILE and the reason, FILE unchanged, no temporary
# left. LAUNCH (an array) runs it: empty, or xvfb-run for a PNG without a display.
LAUNCH=()
full_disk() {
  local name=$1 file=$2
  shift 2
  local dir
  dir=$(dirname "$file")
  mkdir -p "$dir"
  echo old >"$file"
  local status=0
  "${LAUNCH[@]}" bash -c 'trap "" XFSZ; ulimit -f 2; exec "$@"' limited "$SHADOW" render "$SCENE" -o "$file" "$@" \
    >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  one_error_line "$name" "$status" 3 "$WORK/$name.stderr" "$file" "File too large" || return
  if [[ $(cat "$file") != old ]]; then
    fail "$name" "$file was replaced by a cut file"
  elif compgen -G "$dir/.$(basename "$file").tmp-*" >/dev/null; then
    fail "$name" "a temporary was left: $(ls -a "$dir")"
  elif [[ -s "$WORK/$name.stdout" ]]; then
    fail "$name" "printed on stdout: $(cat "$WORK/$name.stdout")"
  else
    pass "$name"
  fi
}
full_disk render_full_disk_svg "$WORK/full/view.svg"
# The PDF only where cairo was built in (without it: exit 3 saying so, checked elsewhere).
status=0
"$SHADOW" render "$SCENE" -o "$WORK/probe.pdf" --width 64 --height 48 -q 2>/dev/null || status=$?
if [[ $status -eq 0 ]]; then
  full_disk render_full_disk_pdf "$WORK/full/view.pdf"
fi
# The PNG needs an X display: under xvfb-run when there is none (the limit applies to shadow
# only, not to the X server). libpng's own messages must not reach stderr.
if [[ -n ${DISPLAY:-} ]]; then
  full_disk render_full_disk_png "$WORK/full/view.png"
elif command -v xvfb-run >/dev/null 2>&1; then
  LAUNCH=(xvfb-run -a -s "-screen 0 2048x2048x24 -noreset")
  full_disk render_full_disk_png "$WORK/full/view.png"
  LAUNCH=()
fi

# ---- the render module: loaded for `shadow render` only -------------------------------------------
# The program itself loads no rendering library (every other subcommand paid ~20 ms for them);
# `shadow render` loads them from its module, and a program without its module says so.
if command -v ldd >/dev/null 2>&1; then
  loaded=$(ldd "$SHADOW" 2>&1)
  if grep -E -q 'libvtkRendering|libcairo|libX11|libGL' <<<"$loaded"; then
    fail "render_libraries_not_loaded_by_shadow" "$(grep -E 'libvtkRendering|libcairo|libX11|libGL' <<<"$loaded" | head -3)"
  else
    pass "render_libraries_not_loaded_by_shadow"
  fi
fi
# A copy of the program in a folder without the module (its libraries found as before, through
# its run path): one line naming the module, exit 4 (an internal error: the install is broken),
# no file.
mkdir -p "$WORK/alone/bin"
cp "$SHADOW" "$WORK/alone/bin/shadow"
status=0
"$WORK/alone/bin/shadow" render "$SCENE" -o "$WORK/alone/view.svg" >"$WORK/alone.stdout" 2>"$WORK/alone.stderr" || status=$?
if [[ $status -ne 4 || $(wc -l <"$WORK/alone.stderr") -ne 1 ]] ||
   ! grep -q "shadow_render_module.so" "$WORK/alone.stderr" || [[ -e "$WORK/alone/view.svg" ]]; then
  fail "render_without_its_module" "exit $status: $(cat "$WORK/alone.stderr")"
else
  pass "render_without_its_module"
fi

cli_test_end
