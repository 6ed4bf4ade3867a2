#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The `shadow` command line on bad and good input: exit status, one clear error line on stderr
# naming the file and the place, and no output files after a failure.
#
# Usage: bash test_cli.sh /path/to/shadow /path/to/tests/data /path/to/examples
set -u

source "$(dirname "${BASH_SOURCE[0]}")/harness.sh"
cli_test_begin cli-test 3 "SHADOW_BINARY TEST_DATA_DIR EXAMPLES_DIR" "$@"
SHADOW=$1
DATA=$2
EXAMPLES=$3

# expect_input_error NAME SCENE PART...: `shadow compute SCENE` must exit with status 2 (bad
# input), print exactly one line on stderr that contains every PART, and leave no output files.
expect_input_error() {
  local name=$1 scene=$2
  shift 2
  local out="$WORK/out-$name"
  local status=0
  "$SHADOW" compute "$scene" -o "$out" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  local stderr
  stderr=$(cat "$WORK/$name.stderr")
  local lines
  lines=$(wc -l <"$WORK/$name.stderr")
  if [[ $status -ne 2 ]]; then
    fail "$name" "exit status $status, expected 2 (stderr: $stderr)"
    return
  fi
  if [[ $lines -ne 1 ]]; then
    fail "$name" "expected exactly one line on stderr, got $lines: $stderr"
    return
  fi
  if [[ $stderr != "shadow: error: "* ]]; then
    fail "$name" "stderr does not start with 'shadow: error: ': $stderr"
    return
  fi
  local part
  for part in "$@"; do
    if [[ $stderr != *"$part"* ]]; then
      fail "$name" "stderr lacks '$part': $stderr"
      return
    fi
  done
  local file
  for file in report.json fragments.vtp plane_shadows.vtp scene.vtm; do
    if [[ -e "$out/$file" ]]; then
      fail "$name" "a failed run left $out/$file"
      return
    fi
  done
  pass "$name"
}

S="$DATA/scenes"

# ---- bad input ---------------------------------------------------------------------------------
expect_input_error nonexistent_scene "$S/no_such_scene.json" \
  "no_such_scene.json" "cannot open" "No such file"
expect_input_error malformed_json "$S/malformed.json" \
  "malformed.json" "line 5, column 5" "malformed JSON"
expect_input_error missing_mesh_file "$S/missing_mesh_file.json" \
  "missing_mesh_file.json" "meshes[1].file" "no_such_statue.obj" "cannot open"
expect_input_error huge_coordinate "$S/huge_coordinate.json" \
  "huge_coordinate.json" "meshes[0].polygons[0][1][2]" "not finite"
expect_input_error nan_in_obj "$S/nan_vertex.json" \
  "nan_vertex.obj" "line 4" "not finite"
expect_input_error obj_index_out_of_range "$S/index_out_of_range.json" \
  "index_out_of_range.obj" "line 8" "vertex index 12 is out of range"
expect_input_error face_with_two_vertices "$S/two_vertex_face.json" \
  "two_vertex_face.obj" "line 6" "face has 2 vertices"
expect_input_error zero_to_light "$S/zero_to_light.json" \
  "zero_to_light.json" "lights[1].to_light" "zero length"
expect_input_error unknown_light_type "$S/unknown_light_type.json" \
  "unknown_light_type.json" "lights[0].type" "unknown light type \"spot\"" "directional"
expect_input_error unknown_key "$S/unknown_key.json" \
  "unknown_key.json" "lights[1]" "unknown key \"postion\""
expect_input_error nonplanar_face "$S/nonplanar.json" \
  "nonplanar.obj" "line 7" "face is not planar"
expect_input_error self_intersecting_face "$S/bowtie.json" \
  "bowtie.obj" "line 7" "face boundary intersects itself"

# A scene file that is a directory, and an empty scene file.
mkdir -p "$WORK/a_directory.json"
expect_input_error scene_is_a_directory "$WORK/a_directory.json" "a_directory.json" "cannot open"
: >"$WORK/empty.json"
expect_input_error empty_scene_file "$WORK/empty.json" "empty.json" "line 1, column 1" "malformed JSON"

# ---- usage and help ----------------------------------------------------------------------------
check_help() {
  local name=$1
  shift
  local status=0 output
  output=$("$@" 2>&1) || status=$?
  if [[ $status -ne 0 ]]; then
    fail "$name" "exit status $status"
    return
  fi
  echo "$output" >"$WORK/$name.txt"
  HELP_OUTPUT=$output
  pass "$name"
}
HELP_OUTPUT=""
check_help help "$SHADOW" --help
top_help=$HELP_OUTPUT
check_help compute_help "$SHADOW" compute --help
compute_help=$HELP_OUTPUT

# shadow series: its help, and a scene without a `sun` block is one clear line, exit 2, no OUTDIR.
check_help series_help "$SHADOW" series --help
for option in --threads --fast --quiet --every --fragments --output --tile-casters --fast-tile-casters; do
  [[ $HELP_OUTPUT == *"$option"* ]] || fail series_help_lists_options "series --help does not mention $option"
done
status=0
"$SHADOW" series "$EXAMPLES/default/scene.json" -o "$WORK/out-series-no-sun" 2>"$WORK/series-no-sun.stderr" >/dev/null || status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/series-no-sun.stderr") -eq 1 && ! -e "$WORK/out-series-no-sun" ]] &&
   grep -q "scene.json: sun: the scene has no \`sun\` block" "$WORK/series-no-sun.stderr"; then
  pass series_without_sun_block
else
  fail series_without_sun_block "status $status: $(cat "$WORK/series-no-sun.stderr")"
fi

# shadow series on an EnergyPlus model read whole: energyplus-shading.csv's header is exactly the
# model's exterior surfaces, named as EnergyPlus holds them (upper case) (the zone's walls, their window and door, the roof: no floor, no
# shading), and --from/--to/--step run its site over another period (one June day, hourly).
idf="$EXAMPLES/energyplus/box-office.idf"
out="$WORK/out-series-idf"
status=0
"$SHADOW" series "$idf" -o "$out" --from 2023-06-21 --to 2023-06-21 --step 60 --every 0 --quiet \
  2>"$WORK/series-idf.stderr" || status=$?
expected_header="Surface Name,WALL-SOUTH,WINDOW-SOUTH,DOOR-SOUTH,WALL-EAST,WINDOW-EAST,WALL-NORTH,WALL-WEST,ROOF"
if [[ $status -eq 0 && -f "$out/report.json" ]] &&
   [[ $(head -n 1 "$out/energyplus-shading.csv" | tr -d '\r') == "$expected_header" ]] &&
   [[ $(wc -l <"$out/energyplus-shading.csv") -eq 8761 ]]; then
  pass series_energyplus_model_header
else
  fail series_energyplus_model_header "status $status: $(head -c 300 "$out/energyplus-shading.csv" 2>/dev/null) $(cat "$WORK/series-idf.stderr")"
fi
# Chicago on 21 June: about 15 hours of sun, one sunlit.csv row each (and the header), at
# mid-hour: where EnergyPlus takes the sun of an hourly time step (UTC-6: 10:30 local is 16:30Z).
rows=$(($(wc -l <"$out/sunlit.csv" 2>/dev/null || echo 0) - 1))
if [[ $rows -ge 14 && $rows -le 16 ]] && grep -q '^2023-06-21T16:30:00Z,' "$out/sunlit.csv" &&
   ! grep -q '^2023-06-21T..:00:00Z,' "$out/sunlit.csv"; then
  pass series_from_to_step
else
  fail series_from_to_step "$rows rows in sunlit.csv"
fi
status=0
"$SHADOW" series "$idf" -o "$WORK/out-series-bad-date" --from 2023-02-30 2>"$WORK/series-bad-date.stderr" >/dev/null ||
  status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/series-bad-date.stderr") -eq 1 && ! -e "$WORK/out-series-bad-date/report.json" ]] &&
   grep -q -- "--from: expected a date" "$WORK/series-bad-date.stderr"; then
  pass series_from_bad_date
else
  fail series_from_bad_date "status $status: $(cat "$WORK/series-bad-date.stderr")"
fi
# --from alone after the model's RunPeriod ends: the message names --from, the option given.
status=0
"$SHADOW" series "$idf" -o "$WORK/out-series-from-late" --from 2024-01-01 2>"$WORK/series-from-late.stderr" >/dev/null ||
  status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/series-from-late.stderr") -eq 1 ]] &&
   grep -q -- "--from: --from 2024-01-01 is after the period's end .*: give --to too" "$WORK/series-from-late.stderr"; then
  pass series_from_alone_after_the_end
else
  fail series_from_alone_after_the_end "status $status: $(cat "$WORK/series-from-late.stderr")"
fi
if [[ $top_help == *compute* ]]; then pass "help_lists_compute"; else fail "help_lists_compute" "$top_help"; fi
for word in compute -o --threads --quiet; do
  if [[ $compute_help == *"$word"* ]]; then
    pass "compute_help_mentions_$word"
  else
    fail "compute_help_mentions_$word" "missing from: $compute_help"
  fi
done

status=0
"$SHADOW" >/dev/null 2>&1 || status=$?
if [[ $status -ne 0 ]]; then pass "no_subcommand_is_a_usage_error"; else fail "no_subcommand_is_a_usage_error" "exit 0"; fi
status=0
"$SHADOW" compute "$S/three_meshes.json" >/dev/null 2>&1 || status=$?
if [[ $status -ne 0 ]]; then pass "missing_output_option_is_a_usage_error"; else fail "missing_output_option_is_a_usage_error" "exit 0"; fi

# ---- good input --------------------------------------------------------------------------------
# expect_success NAME SCENE: exit 0 with report.json and fragments.vtp in the output directory.
expect_success() {
  local name=$1 scene=$2
  shift 2
  local out="$WORK/out-$name"
  local status=0
  "$SHADOW" compute "$scene" -o "$out" "$@" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  if [[ $status -ne 0 ]]; then
    fail "$name" "exit status $status: $(cat "$WORK/$name.stderr")"
    return
  fi
  local file
  for file in report.json fragments.vtp; do
    if [[ ! -s "$out/$file" ]]; then
      fail "$name" "no $file in $out"
      return
    fi
  done
  pass "$name"
}

mkdir -p "$WORK/tiny"
cat >"$WORK/tiny/scene.json" <<'EOF'
{
  "meshes": [{"name": "ground", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]]}],
  "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1]}]
}
EOF
expect_success tiny_scene "$WORK/tiny/scene.json"
expect_success tiny_scene_quiet_two_threads "$WORK/tiny/scene.json" --quiet --threads 2
if [[ -s "$WORK/tiny_scene_quiet_two_threads.stdout" || -s "$WORK/tiny_scene_quiet_two_threads.stderr" ]]; then
  fail "quiet_prints_nothing" "$(cat "$WORK/tiny_scene_quiet_two_threads.stdout" "$WORK/tiny_scene_quiet_two_threads.stderr")"
else
  pass "quiet_prints_nothing"
fi

expect_success scene_with_obj_meshes "$S/three_meshes.json"

# A zero-area face is a warning, not an error: the run succeeds and says where the face is.
expect_success zero_area_face_warns "$S/collinear.json"
if grep -q "collinear.obj: line 9: face has zero area" "$WORK/zero_area_face_warns.stderr"; then
  pass "zero_area_face_warning_names_the_face"
else
  fail "zero_area_face_warning_names_the_face" "stderr: $(cat "$WORK/zero_area_face_warns.stderr")"
fi

if [[ -f "$EXAMPLES/default/scene.json" ]]; then
  expect_success example_default_scene "$EXAMPLES/default/scene.json" --quiet
fi

# The scene's camera is read and checked by the library: a malformed one stops `shadow compute` too.
mkdir -p "$WORK/badcam"
cat >"$WORK/badcam/scene.json" <<'EOF'
{
  "meshes": [{"name": "ground", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]]}],
  "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1]}],
  "camera": {"eye": [0.5, 0.5, 2], "fov": 200}
}
EOF
expect_input_error compute_bad_scene_camera "$WORK/badcam/scene.json" \
  "badcam/scene.json: camera.fov: expected a vertical view angle in degrees, in [1, 170]"

# ---- shadow render (built when VTK's OpenGL rendering is available) ----
if "$SHADOW" render --help >/dev/null 2>&1; then
  # Without DISPLAY the command restarts itself under xvfb-run (when it is installed).
  if command -v xvfb-run >/dev/null 2>&1 || [[ -n ${DISPLAY:-} ]]; then
    status=0
    env -u DISPLAY "$SHADOW" render "$WORK/tiny/scene.json" -o "$WORK/tiny.png" --width 64 --height 48 \
      --quiet >"$WORK/render.stdout" 2>"$WORK/render.stderr" || status=$?
    if [[ $status -eq 0 && $(head -c 4 "$WORK/tiny.png" | od -An -c | tr -d ' ') == "211PNG" ]]; then
      pass "render_writes_a_png_without_a_display"
    else
      fail "render_writes_a_png_without_a_display" "status $status, stderr: $(cat "$WORK/render.stderr")"
    fi
  fi
  # An extended light lights the picture and the vector view from its centre, a point light
  # (docs/render.md, docs/vector-views.md): the same files as a lamp at the area light's centroid.
  mkdir -p "$WORK/centre"
  cat >"$WORK/centre/area.json" <<'EOF2'
{
  "meshes": [
    {"name": "ground", "polygons": [[[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]]},
    {"name": "square", "polygons": [[[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]]}
  ],
  "lights": [{"name": "lamp", "type": "area",
              "polygon": [[0.25, 0.25, 4], [0.25, 0.75, 4], [0.75, 0.75, 4], [0.75, 0.25, 4]]}],
  "camera": {"eye": [6, -7, 9], "target": [0, 0, 0]}
}
EOF2
  sed 's/"type": "area",/"type": "point", "position": [0.5, 0.5, 4]}],/; /"polygon"/d' "$WORK/centre/area.json" \
    >"$WORK/centre/point.json"
  status=0
  for n in area point; do
    "$SHADOW" render "$WORK/centre/$n.json" -o "$WORK/centre/$n.svg" --quiet 2>>"$WORK/centre/stderr" || status=$?
  done
  if [[ $status -eq 0 ]] && diff <(grep -v '<title>' "$WORK/centre/area.svg") \
      <(grep -v '<title>' "$WORK/centre/point.svg") >/dev/null && grep -q 'fill' "$WORK/centre/area.svg"; then
    pass "render_svg_of_an_area_light_is_its_centres"
  else
    fail "render_svg_of_an_area_light_is_its_centres" "status $status: $(cat "$WORK/centre/stderr")"
  fi
  if command -v xvfb-run >/dev/null 2>&1 || [[ -n ${DISPLAY:-} ]]; then
    status=0
    for n in area point; do
      env -u DISPLAY "$SHADOW" render "$WORK/centre/$n.json" -o "$WORK/centre/$n.png" --width 160 --height 120 \
        --quiet 2>>"$WORK/centre/stderr" || status=$?
    done
    if [[ $status -eq 0 ]] && cmp -s "$WORK/centre/area.png" "$WORK/centre/point.png"; then
      pass "render_png_of_an_area_light_is_its_centres"
    else
      fail "render_png_of_an_area_light_is_its_centres" "status $status: $(cat "$WORK/centre/stderr")"
    fi
  fi
  # No display and no xvfb-run: one line that says what to install, status 3, no image.
  status=0
  env -u DISPLAY PATH=/nonexistent "$SHADOW" render "$WORK/tiny/scene.json" -o "$WORK/no-x.png" \
    >"$WORK/no-x.stdout" 2>"$WORK/no-x.stderr" || status=$?
  if [[ $status -eq 3 && $(grep -c . "$WORK/no-x.stderr") -eq 1 && $(cat "$WORK/no-x.stderr") == *xvfb* &&
        ! -e "$WORK/no-x.png" ]]; then
    pass "render_without_display_or_xvfb_says_what_to_do"
  else
    fail "render_without_display_or_xvfb_says_what_to_do" "status $status: $(cat "$WORK/no-x.stderr")"
  fi
  # Bad options and bad scenes: non-zero status, one line on stderr.
  expect_render_error() {
    local name=$1 expected_status=$2 part=$3
    shift 3
    local status=0
    "$SHADOW" render "$@" -o "$WORK/$name.png" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
    local lines
    lines=$(wc -l <"$WORK/$name.stderr")  # usage errors too: exactly one line
    if [[ $status -ne $expected_status ]]; then
      fail "$name" "exit status $status, expected $expected_status: $(cat "$WORK/$name.stderr")"
    elif [[ $lines -ne 1 || $(cat "$WORK/$name.stderr") != *"$part"* ]]; then
      fail "$name" "expected one line with '$part': $(cat "$WORK/$name.stderr")"
    elif [[ -e "$WORK/$name.png" ]]; then
      fail "$name" "a failed run left $WORK/$name.png"
    else
      pass "$name"
    fi
  }
  expect_render_error render_unknown_model 2 "--model" "$WORK/tiny/scene.json" --model toon
  expect_render_error render_missing_scene 2 "does-not-exist.json" "$S/does-not-exist.json"
  mkdir -p "$WORK/cam"
  cat >"$WORK/cam/scene.json" <<'EOF'
{
  "meshes": [{"name": "ground", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]]}],
  "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1]}],
  "camera": {"eye": [0.5, 0.5], "fov": 40}
}
EOF
  expect_render_error render_bad_scene_camera 2 "camera.eye: expected 3 numbers" "$WORK/cam/scene.json"
  expect_render_error render_nan_fov 2 "--fov" "$WORK/tiny/scene.json" --fov nan
  expect_render_error render_huge_threads 2 "--threads" "$WORK/tiny/scene.json" --threads 99999999
  expect_render_error render_bad_width 2 "--width" "$WORK/tiny/scene.json" --width abc
  expect_render_error render_up_along_view 2 "--up" "$WORK/tiny/scene.json" --eye 0,0,5 --target 0,0,0 --up 0,0,1
  expect_render_error render_nan_eye 2 "finite coordinate" "$WORK/tiny/scene.json" --eye nan,0,1
  expect_render_error render_huge_target 2 "finite coordinate" "$WORK/tiny/scene.json" --target 1e200,0,0
  # The look options (docs/render.md): one line naming the option.
  expect_render_error render_bad_exposure 2 "--exposure" "$WORK/tiny/scene.json" --exposure bright
  expect_render_error render_zero_exposure 2 "--exposure" "$WORK/tiny/scene.json" --exposure 0
  expect_render_error render_bad_colours 2 "--colours" "$WORK/tiny/scene.json" --colours pink
  expect_render_error render_bad_tone 2 "--tone" "$WORK/tiny/scene.json" --tone reinhard
  expect_render_error render_bad_frame 2 "--frame" "$WORK/tiny/scene.json" --frame all
  expect_render_error render_bad_compass 2 "--compass" "$WORK/tiny/scene.json" --compass maybe
  mkdir -p "$WORK/cam2"
  cat >"$WORK/cam2/scene.json" <<'EOF'
{
  "meshes": [{"name": "ground", "polygons": [[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]]}],
  "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, 0.2, 1]}],
  "camera": {"eye": [0.5, 0.5, 2], "target": [0.5, 0.5, 2]}
}
EOF
  expect_render_error render_scene_camera_eye_is_target 2 "cam2/scene.json: camera: the camera's eye and target" \
    "$WORK/cam2/scene.json"
fi

# The fast path: --fast (or --arithmetic fast) says so in report.json and carries error bounds.
if [[ -f "$EXAMPLES/default/scene.json" ]]; then
  expect_success fast_path "$EXAMPLES/default/scene.json" --quiet --fast
  report="$WORK/out-fast_path/report.json"
  if grep -q '"arithmetic": "fast"' "$report" && grep -q '"lit_area_error_bound"' "$report" &&
     grep -q '"fast_exact_fallbacks"' "$report"; then
    pass "fast_path_report_states_arithmetic_and_bounds"
  else
    fail "fast_path_report_states_arithmetic_and_bounds" "report.json lacks them"
  fi
  expect_success exact_arithmetic "$EXAMPLES/default/scene.json" --quiet --arithmetic exact
  if grep -q '"arithmetic": "exact"' "$WORK/out-exact_arithmetic/report.json" &&
     ! grep -q '"lit_area_error_bound"' "$WORK/out-exact_arithmetic/report.json"; then
    pass "exact_report_states_arithmetic"
  else
    fail "exact_report_states_arithmetic" "report.json should say exact, without bounds"
  fi
  # Tiles: --tile-casters 1 splits receivers with a caster (named in stats and options);
  # 0 never splits, and the defaults write neither key.
  expect_success tiles_on "$EXAMPLES/default/scene.json" --quiet --tile-casters 1
  expect_success tiles_off "$EXAMPLES/default/scene.json" --quiet --tile-casters 0 --fast-tile-casters 0
  if grep -q '"tiled_receivers"' "$WORK/out-tiles_on/report.json" &&
     grep -q '"tile_casters": 1' "$WORK/out-tiles_on/report.json" &&
     ! grep -q '"tiled_receivers"' "$WORK/out-tiles_off/report.json" &&
     ! grep -q '"tiled_receivers"\|"tile_casters"' "$WORK/out-exact_arithmetic/report.json"; then
    pass "tile_options_reach_report"
  else
    fail "tile_options_reach_report" "report.json: tiled_receivers or tile_casters missing or unexpected"
  fi
fi
status=0
"$SHADOW" compute "$S/three_meshes.json" -o "$WORK/out-bad-arith" --arithmetic sloppy >/dev/null 2>&1 || status=$?
if [[ $status -eq 2 ]]; then
  pass "unknown_arithmetic_is_a_usage_error"
else
  fail "unknown_arithmetic_is_a_usage_error" "exit status $status"
fi

# ---- usage errors (issue 11, item 10): one line on stderr, exit 2 ------------------------------
# expect_usage_error NAME PART ARGS...: `shadow ARGS` exits 2 with one "shadow: error:" line
# containing PART.
expect_usage_error() {
  local name=$1 part=$2
  shift 2
  local status=0
  "$SHADOW" "$@" >"$WORK/$name.stdout" 2>"$WORK/$name.stderr" || status=$?
  local stderr lines
  stderr=$(cat "$WORK/$name.stderr")
  lines=$(wc -l <"$WORK/$name.stderr")
  if [[ $status -ne 2 ]]; then
    fail "$name" "exit status $status, expected 2 (stderr: $stderr)"
  elif [[ $lines -ne 1 || $stderr != "shadow: error: "* || $stderr != *"$part"* ]]; then
    fail "$name" "expected one 'shadow: error:' line with '$part', got $lines: $stderr"
  elif [[ ${#stderr} -gt 300 ]]; then
    fail "$name" "error line is ${#stderr} characters long: $stderr"
  else
    pass "$name"
  fi
}
T="$S/three_meshes.json"
expect_usage_error usage_threads_not_a_number '--threads: expected a whole number from 0 to 1024, got "abc"' \
  compute "$T" -o "$WORK/u" --threads abc
expect_usage_error usage_threads_too_many "from 0 to 1024" compute "$T" -o "$WORK/u" --threads 99999999
expect_usage_error usage_unknown_subcommand 'unknown subcommand "frobnicate"' frobnicate "$T"
expect_usage_error usage_no_subcommand "subcommand" 
expect_usage_error usage_plane_window_nan "--plane-window" compute "$T" -o "$WORK/u" --plane-window nan
expect_usage_error usage_plane_window_inf "--plane-window" compute "$T" -o "$WORK/u" --plane-window inf
expect_usage_error usage_planarity_nan "--planarity-tolerance" compute "$T" -o "$WORK/u" --planarity-tolerance nan
expect_usage_error usage_unknown_option "--bogus" compute "$T" -o "$WORK/u" --bogus
expect_usage_error usage_missing_output "--output" compute "$T"
expect_usage_error usage_tile_casters_negative '--tile-casters: expected a whole number from 0 to 1000000000, got "-1"' \
  compute "$T" -o "$WORK/u" --tile-casters -1
expect_usage_error usage_fast_tile_casters_fraction '--fast-tile-casters: expected a whole number' \
  compute "$T" -o "$WORK/u" --fast-tile-casters 2.5
[[ ! -e "$WORK/u" ]] && pass "usage_errors_write_nothing" || fail "usage_errors_write_nothing" "$WORK/u exists"
if "$SHADOW" --help | grep -q "Exit status: 0 success; 2 bad input or a usage error" &&
   "$SHADOW" compute --help | grep -q "3 an output could not be written"; then
  pass "help_lists_exit_codes"
else
  fail "help_lists_exit_codes" "shadow --help or shadow compute --help lacks the exit codes"
fi

# ---- hostile input files (items 4, 7, 9) -------------------------------------------------------
mkdir -p "$WORK/hostile"
light='"lights": [{"name": "sun", "type": "directional", "to_light": [0, 0, 1]}]'
mkfifo "$WORK/hostile/fifo.obj"
ln -s /dev/zero "$WORK/hostile/zero.obj"
for kind in fifo zero; do
  echo "{\"meshes\": [{\"name\": \"m\", \"file\": \"$kind.obj\"}], $light}" >"$WORK/hostile/$kind.json"
done
# (timeout: before the fix a FIFO blocked forever.)
status=0
timeout 20 "$SHADOW" compute "$WORK/hostile/fifo.json" -o "$WORK/out-fifo" 2>"$WORK/fifo.stderr" || status=$?
if [[ $status -eq 2 && $(wc -l <"$WORK/fifo.stderr") -eq 1 ]] &&
   grep -q 'meshes\[0\].file: cannot open "[^"]*fifo.obj": not a regular file' "$WORK/fifo.stderr"; then
  pass "fifo_mesh_file_is_refused"
else
  fail "fifo_mesh_file_is_refused" "status $status: $(cat "$WORK/fifo.stderr")"
fi
expect_input_error dev_zero_mesh_file "$WORK/hostile/zero.json" 'zero.obj": not a regular file'
expect_input_error dev_urandom_scene /dev/urandom "/dev/urandom: cannot open: not a regular file"
printf 'v 0 0 0\nv 1 0 0\nv 1 1\000junk 0\nf 1 2 3\n' >"$WORK/hostile/nul.obj"
echo "{\"meshes\": [{\"name\": \"m\", \"file\": \"nul.obj\"}], $light}" >"$WORK/hostile/nul.json"
expect_input_error nul_byte_in_obj_is_escaped "$WORK/hostile/nul.json" 'nul.obj: line 3: y coordinate "1\x00junk" is not a number'
echo "{\"meshes\": [{\"name\": \"m\", \"polygons\": [[[0, 0, 0], [1e308, 0, 0], [0, 1e308, 0]]]}], $light}" \
  >"$WORK/hostile/huge.json"
expect_input_error coordinate_beyond_range "$WORK/hostile/huge.json" "meshes[0].polygons[0]" "vertex 1" "2^500"
echo "{\"meshes\": [{\"name\": \"m\", \"polygons\": [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]}],
  \"lights\": [{\"name\": \"lamp\", \"type\": \"point\", \"position\": [0, 0, -1e300]}]}" >"$WORK/hostile/far_light.json"
expect_input_error light_beyond_range "$WORK/hostile/far_light.json" "lights[0].position" "2^500"
echo "{\"meshes\": [{\"name\": \"m\", \"polygons\": [[[0, 0, 0], [1, 0, 0], [0, 1, 0]]]}], $light,
  \"planes\": [{\"name\": \"g\", \"point\": [0, 0, -1e200], \"normal\": [0, 0, 1]}]}" >"$WORK/hostile/far_plane.json"
expect_input_error plane_beyond_range "$WORK/hostile/far_plane.json" "planes[0].point" "2^500"

# ---- inward-facing closed meshes warn (item 3) -------------------------------------------------
# A unit cube wound inward, the same cube wound outward, and an open box (no lid) wound inward.
cube() {  # cube X WINDING(out|in) [open]
  local x=$1 w=$2 open=${3:-}
  local -a f=("[[$x,0,0],[$x,1,0],[$((x+1)),1,0],[$((x+1)),0,0]]" "[[$x,0,1],[$((x+1)),0,1],[$((x+1)),1,1],[$x,1,1]]"
              "[[$x,0,0],[$((x+1)),0,0],[$((x+1)),0,1],[$x,0,1]]" "[[$((x+1)),0,0],[$((x+1)),1,0],[$((x+1)),1,1],[$((x+1)),0,1]]"
              "[[$((x+1)),1,0],[$x,1,0],[$x,1,1],[$((x+1)),1,1]]" "[[$x,1,0],[$x,0,0],[$x,0,1],[$x,1,1]]")
  [[ -n $open ]] && unset 'f[1]'
  local out="" p
  for p in "${f[@]}"; do
    [[ $w == in ]] && p=$(echo "$p" | sed 's/^\[\(\[[^]]*\]\),\(\[[^]]*\]\),\(\[[^]]*\]\),\(\[[^]]*\]\)\]$/[\4,\3,\2,\1]/')
    out+="${out:+,}$p"
  done
  echo "[$out]"
}
mkdir -p "$WORK/orient"
echo "{\"meshes\": [{\"name\": \"inward\", \"polygons\": $(cube 0 in)}, {\"name\": \"outward\", \"polygons\": $(cube 2 out)},
  {\"name\": \"open_box\", \"polygons\": $(cube 4 in open)}], $light}" >"$WORK/orient/scene.json"
expect_success inward_cube_runs "$WORK/orient/scene.json"
if grep -q 'meshes\[0\]: mesh "inward" is closed, and its faces point inward' "$WORK/inward_cube_runs.stderr" &&
   [[ $(grep -c "warning" "$WORK/inward_cube_runs.stderr") -eq 1 ]] &&
   grep -q 'point inward' "$WORK/out-inward_cube_runs/report.json"; then
  pass "inward_closed_mesh_warns_once_and_in_the_report"
else
  fail "inward_closed_mesh_warns_once_and_in_the_report" "stderr: $(cat "$WORK/inward_cube_runs.stderr")"
fi

# --orient-outward turns the inward cube outward and says so, instead of warning about it.
expect_success inward_cube_oriented "$WORK/orient/scene.json" --orient-outward
if grep -q 'mesh "inward" (closed, faces 0, 1, 2, 3, 4 and 1 more.*pointed inward (negative signed volume): its 6 faces were reversed' \
     "$WORK/inward_cube_oriented.stderr" && ! grep -q 'point inward' "$WORK/inward_cube_oriented.stderr"; then
  pass "orient_outward_reverses_the_inward_cube"
else
  fail "orient_outward_reverses_the_inward_cube" "stderr: $(cat "$WORK/inward_cube_oriented.stderr")"
fi

# The bundled CityJSON example: three houses with windows cut out, named per surface.
expect_success example_cityjson_street "$EXAMPLES/cityjson/scene.json"
if grep -q '^  mesh street/house-3 lit sun ' "$WORK/example_cityjson_street.stdout" &&
   grep -q '"kind": "Window"' "$WORK/out-example_cityjson_street/report.json" &&
   grep -q '"name": "house-1/1"' "$WORK/out-example_cityjson_street/report.json"; then
  pass "example_cityjson_street_is_named"
else
  fail "example_cityjson_street_is_named" "stdout: $(cat "$WORK/example_cityjson_street.stdout")"
fi

# A CityJSON model: as the scene it brings no lights (exit 2, one line); as a mesh file of a scene
# with a sun it runs, and the summary gives lit fractions per city object.
mkdir -p "$WORK/city"
cat >"$WORK/city/b.city.json" <<'EOF'
{"type": "CityJSON", "version": "2.0",
 "transform": {"scale": [0.001, 0.001, 0.001], "translate": [85000, 446000, 0]},
 "CityObjects": {"b1": {"type": "Building", "geometry": [{"type": "Solid", "lod": "1",
   "boundaries": [[[[0,3,2,1]], [[4,5,6,7]], [[0,1,5,4]], [[1,2,6,5]], [[2,3,7,6]], [[3,0,4,7]]]]}]}},
 "vertices": [[0,0,0],[8000,0,0],[8000,6000,0],[0,6000,0],[0,0,5000],[8000,0,5000],[8000,6000,5000],[0,6000,5000]]}
EOF
echo '{"meshes": [{"name": "city", "file": "b.city.json"}], "lights": [{"name": "sun", "type": "directional", "to_light": [0.3, -0.4, 0.8]}]}' \
  >"$WORK/city/scene.json"
expect_input_error cityjson_without_lights "$WORK/city/b.city.json" "b.city.json" "the scene has no lights"
expect_success cityjson_as_mesh_file "$WORK/city/scene.json"
if grep -q '^  mesh city/b1 lit sun ' "$WORK/cityjson_as_mesh_file.stdout" &&
   grep -q '"name": "b1/1"' "$WORK/out-cityjson_as_mesh_file/report.json" &&
   grep -q '"origin": \[' "$WORK/out-cityjson_as_mesh_file/report.json"; then
  pass "cityjson_faces_are_named_and_summarised_per_mesh"
else
  fail "cityjson_faces_are_named_and_summarised_per_mesh" "stdout: $(cat "$WORK/cityjson_as_mesh_file.stdout")"
fi

# ---- the output directory (item 12) ------------------------------------------------------------
# A run identifies itself in report.json.
if grep -q '"run": {' "$WORK/out-tiny_scene/report.json" && grep -q '"started_utc": "20[0-9-]*T[0-9:]*Z"' "$WORK/out-tiny_scene/report.json" &&
   grep -q '"options": {' "$WORK/out-tiny_scene/report.json"; then
  pass "report_names_its_run"
else
  fail "report_names_its_run" "no run object in report.json"
fi
# A second writer while OUTDIR is locked: one line, exit 3, the first result untouched.
if command -v flock >/dev/null 2>&1; then
  out="$WORK/out-tiny_scene"
  status=0
  flock "$out/.shadow.lock" "$SHADOW" compute "$WORK/tiny/scene.json" -o "$out" >/dev/null 2>"$WORK/locked.stderr" ||
    status=$?
  if [[ $status -eq 3 && $(wc -l <"$WORK/locked.stderr") -eq 1 ]] && grep -q "another shadow process" "$WORK/locked.stderr" &&
     [[ -s "$out/report.json" ]]; then
    pass "locked_output_directory_is_refused"
  else
    fail "locked_output_directory_is_refused" "status $status: $(cat "$WORK/locked.stderr")"
  fi
fi
# kill -9 during a long run: report.json of the earlier run is gone from the start (so nothing
# looks complete), and the next run removes the temporaries of dead processes.
mkdir -p "$WORK/slow"
awk 'BEGIN { printf "{\"meshes\": [{\"name\": \"q\", \"polygons\": ["; n = 0;
  for (i = 0; i < 60; i++) for (j = 0; j < 60; j++) { x = i * 1.1 + (j % 3) * 0.2; y = j * 1.1; z = (i * 7 + j * 13) % 5;
    if (n++) printf ","; printf "[[%g,%g,%g],[%g,%g,%g],[%g,%g,%g],[%g,%g,%g]]", x, y, z, x+2, y, z+0.5, x+2, y+2, z+0.5, x, y+2, z }
  printf "]}], \"lights\": [{\"name\": \"lamp\", \"type\": \"point\", \"position\": [30, 30, 20]}]}\n" }' >"$WORK/slow/scene.json"
out="$WORK/out-killed"
"$SHADOW" compute "$WORK/tiny/scene.json" -o "$out" -q
: >"$out/.fragments.vtp.tmp-2147483646"   # a dead process's temporary (no such PID)
: >"$out/.faces.vtp.tmp-$$"               # a live process's: left alone
"$SHADOW" compute "$WORK/slow/scene.json" -o "$out" -q --threads 1 &
pid=$!
for _ in $(seq 100); do [[ -e "$out/report.json" ]] || break; sleep 0.1; done
report_gone_early=no
[[ -e "$out/report.json" ]] || report_gone_early=yes
kill -9 "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
if [[ $report_gone_early == yes && ! -e "$out/report.json" && ! -e "$out/.fragments.vtp.tmp-2147483646" &&
      -e "$out/.faces.vtp.tmp-$$" ]]; then
  pass "killed_run_leaves_no_current_looking_report"
else
  fail "killed_run_leaves_no_current_looking_report" "report gone early: $report_gone_early; $(ls -A "$out")"
fi
: >"$out/.report.json.tmp-2147483646"
status=0
"$SHADOW" compute "$WORK/tiny/scene.json" -o "$out" -q || status=$?
if [[ $status -eq 0 && -s "$out/report.json" && ! -e "$out/.report.json.tmp-2147483646" && ! -e "$out/.shadow.lock" ]]; then
  pass "run_after_a_killed_run_succeeds_and_cleans_up"
else
  fail "run_after_a_killed_run_succeeds_and_cleans_up" "status $status; $(ls -A "$out")"
fi
rm -f "$out/.faces.vtp.tmp-$$"

# Extended lights (docs/area-lights.md): the example room's luminaire and the sun disk over a wall
# run, report the three regions per face, and put a `region` cell array in fragments.vtp; a
# scene without an extended light has neither (its files stay as they were).
for example in scene sun-disk; do
  expect_success "area_light_$example" "$EXAMPLES/area-light/$example.json" --quiet
  report="$WORK/out-area_light_$example/report.json"
  if grep -q '"fully_lit_area"' "$report" && grep -q '"penumbra_area"' "$report" &&
     grep -q '"umbra_area"' "$report" && grep -aq 'Name="region"' "$WORK/out-area_light_$example/fragments.vtp"; then
    pass "area_light_${example}_reports_regions"
  else
    fail "area_light_${example}_reports_regions" "no region keys in $report or no region array"
  fi
done
if grep -q '"fully_lit_area"' "$WORK/out-tiny_scene/report.json" ||
   grep -aq 'Name="region"' "$WORK/out-tiny_scene/fragments.vtp"; then
  fail "point_lights_have_no_region_outputs" "region keys or array in the tiny scene's result"
else
  pass "point_lights_have_no_region_outputs"
fi
mkdir -p "$WORK/badarea"
printf '%s\n' '{"meshes": [{"name": "g", "polygons": [[[0,0,0],[1,0,0],[1,1,0],[0,1,0]]]}],' \
  ' "lights": [{"name": "lum", "type": "area", "polygon": [[0,0,2],[2,2,2],[2,0,2],[0,1,2]]}]}' >"$WORK/badarea/scene.json"
expect_input_error area_light_not_simple "$WORK/badarea/scene.json" "scene.json" "lights[0].polygon" "not simple"

cli_test_end
