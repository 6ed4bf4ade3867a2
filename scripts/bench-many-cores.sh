#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Issue 35, goal 5: the many-core measurements of docs/benchmarks.md ("Sixteen cores again"), in
# one run that fits a short lease of a many-core machine. Two uses:
#
#   scripts/bench-many-cores.sh pack BUNDLE.tar.xz
#       here, after a release build: shadow, shadow-bench, /usr/bin/time and every library they
#       load but glibc's, in bin/ and lib/, for a machine that has none of them (about 26 MB)
#   scripts/bench-many-cores.sh BIN_DIR OUT_DIR [SECONDS]
#       there, with LD_LIBRARY_PATH naming the bundle's lib/: the measurements
#
# OUT_DIR receives one log per step and summary.txt. Steps, most wanted first: the 10,000-box
# city's tiles at 1-16 threads, the million faces' whole `shadow compute` (fast and exact, 16 and
# 2 threads), the engine alone on the million faces, the 1,000-box city's year of suns (fast and
# exact, 16 threads) and the 10,000-box city's fast year. A step that could not finish in the
# SECONDS left (default 480) is skipped and says so. Scenes are generated under $TMPDIR.
set -uo pipefail
if [[ ${1:-} == pack ]]; then
  set -e
  bundle=$(realpath -m "$2")
  root=$(cd "$(dirname "$0")/.." && pwd)
  stage=$(mktemp -d)
  trap 'rm -rf "$stage"' EXIT
  mkdir -p "$stage/bin" "$stage/lib"
  programs=("$root/build/release/bin/shadow" "$root/build/release/bin/shadow-bench")
  cp "${programs[@]}" /usr/bin/time "$stage/bin/"
  # glibc's own libraries stay behind: they must match the other machine's loader.
  ldd "${programs[@]}" | awk '/=> \//{print $3}' | sort -u |
    grep -v -E '/(libc|libm|libpthread|libdl|librt|ld-linux-x86-64)\.so' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
  strip --strip-unneeded "$stage/bin/shadow" "$stage/bin/shadow-bench" "$stage"/lib/libshadow*.so*
  tar -C "$stage" -cJf "$bundle" bin lib
  echo "$bundle: $(du -h "$bundle" | cut -f1)"
  exit 0
fi
bin=$(cd "$1" && pwd)
out=$2
budget=${3:-480}
mkdir -p "$out"
work=${TMPDIR:-/tmp}/libshadow-many-cores
rm -rf "$work" && mkdir -p "$work"
start=$SECONDS
summary=$out/summary.txt

say() { echo "== +$((SECONDS - start)) s: $*" | tee -a "$summary"; }
# step NAME NEEDED_SECONDS COMMAND...: runs COMMAND (its output to OUT/NAME.txt) when at least
# NEEDED_SECONDS of the budget are left.
step() {
  local name=$1 needed=$2
  shift 2
  if ((budget - (SECONDS - start) < needed)); then
    say "$name skipped: under $needed s left"
    return
  fi
  say "$name: $*"
  "$@" >"$out/$name.txt" 2>&1
  say "$name done (rc $?)"
}
# timed COMMAND...: wall, user and system seconds and peak resident memory, then the output.
timed() {
  if [[ -x $bin/time ]]; then
    "$bin/time" -f 'time: %e s wall, %U s user, %S s system, %M KB peak' "$@"
  else
    local t0=$SECONDS
    "$@"
    echo "time: about $((SECONDS - t0)) s wall"
  fi
}
# A year of hourly suns on a written city: its scene without lights, with the year's sun.
year_scene() {
  local dir=$1
  [[ -f $dir/scene.json ]] || return 0  # its write-city step was skipped
  python3 - "$dir/scene.json" <<'EOF'
import json, sys
path = sys.argv[1]
scene = json.load(open(path))
scene.pop("lights", None)
scene["sun"] = {"latitude": 48, "longitude": 2.35, "time_zone": "UTC+01:00",
                "start": "2026-01-01", "end": "2026-12-31", "step_minutes": 60}
json.dump(scene, open(path, "w"), indent=1)
EOF
}

{
  echo "nproc: $(nproc)"
  grep -m1 'model name' /proc/cpuinfo
  free -g | head -2
  uname -r
} >"$out/machine.txt" 2>&1
cat "$out/machine.txt" >>"$summary"

step tiles 120 "$bin/shadow-bench" tiles --sizes 10000 --elevations 40,5 --threads 1,2,4,8,16 --no-untiled
step write-million 60 "$bin/shadow-bench" write-city --boxes 166667 --elevation 40 --output "$work/m40"
for arithmetic in fast exact; do
  flag=$([[ $arithmetic == fast ]] && echo --fast)
  for threads in 16 2; do
    step "million-$arithmetic-$threads" 40 timed "$bin/shadow" compute "$work/m40/scene.json" -o "$work/m40-out" \
      --areas-only --threads "$threads" $flag
  done
done
rm -rf "$work/m40" "$work/m40-out"
step low-sun-million 120 "$bin/shadow-bench" low-sun --sizes 166667 --elevations 40,5 --threads 16
step write-year 20 "$bin/shadow-bench" write-city --boxes 1000 --elevation 40 --output "$work/year"
year_scene "$work/year"
step year-fast-16 40 timed "$bin/shadow" series "$work/year/scene.json" -o "$work/year-out" --fast --threads 16 --quiet
step year-exact-16 90 timed "$bin/shadow" series "$work/year/scene.json" -o "$work/year-out" --threads 16 --quiet
step write-year-10k 20 "$bin/shadow-bench" write-city --boxes 10000 --elevation 40 --output "$work/year10k"
year_scene "$work/year10k"
step year10k-fast-16 120 timed "$bin/shadow" series "$work/year10k/scene.json" -o "$work/year10k-out" --fast --threads 16 --quiet
say "finished"
