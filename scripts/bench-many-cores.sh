#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Issue 35, goal 5: the many-core measurements of docs/benchmarks.md ("Sixteen cores again"),
# sized for a short lease of a many-core machine that has none of the project's libraries. Uses:
#
#   scripts/bench-many-cores.sh pack BUNDLE.tar.xz
#       here, after a release build: shadow, shadow-bench, /usr/bin/time and every library they
#       load but glibc's, in bin/ and lib/ (about 25 MB); fails if a library is not found
#   scripts/bench-many-cores.sh BUNDLE_DIR OUT_DIR [SECONDS]
#       there, on the unpacked bundle (its programs get LD_LIBRARY_PATH=BUNDLE_DIR/lib, nothing
#       else does; python3 is needed for the year scenes): the measurements
#
# OUT_DIR receives one log per step and summary.txt. Steps, most wanted first: the 10,000-box
# city's tiles at 1-16 threads, the million faces' whole `shadow compute` (fast and exact, 16 and
# 2 threads), the engine alone on the million faces, the year's samples at 1-16 threads, the
# 1,000-box city's year of suns (fast and exact, 16 threads) and the 10,000-box city's fast year.
# A step is skipped when fewer seconds are left than it is expected to need (its estimate, for a
# 16-core machine) or when its scene was not written, and stopped when the SECONDS (default 480)
# run out. Scenes are generated under $TMPDIR.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage() {
  echo "usage: $0 pack BUNDLE.tar.xz | $0 BUNDLE_DIR OUT_DIR [SECONDS]" >&2
  exit 2
}

if [[ ${1:-} == pack ]]; then
  [[ $# -eq 2 ]] || usage
  set -e
  bundle=$(realpath -m "$2")
  stage=$(mktemp -d)
  trap 'rm -rf "$stage"' EXIT
  mkdir -p "$stage/bin" "$stage/lib"
  programs=("$root/build/release/bin/shadow" "$root/build/release/bin/shadow-bench")
  cp "${programs[@]}" /usr/bin/time "$stage/bin/"
  libraries=$(ldd "${programs[@]}")
  if grep 'not found' <<<"$libraries"; then
    echo "pack: a library above is not found: build and install first" >&2
    exit 1
  fi
  # glibc's own libraries stay behind: they must match the other machine's loader.
  awk '/=> \//{print $3}' <<<"$libraries" | sort -u |
    grep -v -E '/(libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libanl|libthread_db|libnss_[a-z]+|ld-linux-x86-64)\.so' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
  strip --strip-unneeded "$stage/bin/shadow" "$stage/bin/shadow-bench"
  find "$stage/lib" -name 'libshadow*.so*' -exec strip --strip-unneeded {} +
  tar -C "$stage" -cJf "$bundle" bin lib
  echo "$bundle: $(du -h "$bundle" | cut -f1)"
  exit 0
fi

[[ $# -ge 2 && $# -le 3 ]] || usage
bundle=$(cd "$1" && pwd) || usage
bin=$bundle/bin
[[ -x $bin/shadow && -x $bin/shadow-bench ]] || { echo "$0: no shadow and shadow-bench in $bin" >&2; exit 2; }
out=$2
budget=${3:-480}
mkdir -p "$out"
work=${TMPDIR:-/tmp}/libshadow-many-cores
rm -rf "$work" && mkdir -p "$work"
start=$SECONDS
summary=$out/summary.txt
: >"$summary"
# The bundle's programs find its libraries; the shell's tools (python3, tee) keep the system's.
shadow=(env "LD_LIBRARY_PATH=$bundle/lib" "$bin/shadow")
bench=(env "LD_LIBRARY_PATH=$bundle/lib" "$bin/shadow-bench")

say() { echo "== +$((SECONDS - start)) s: $*" | tee -a "$summary"; }
# step NAME NEEDED_SECONDS [--needs FILE] COMMAND...: runs COMMAND, its output to OUT/NAME.txt,
# when at least NEEDED_SECONDS of the budget are left (and FILE exists), stopped at the budget.
step() {
  local name=$1 needed=$2
  shift 2
  if [[ $1 == --needs ]]; then
    if [[ ! -e $2 ]]; then
      say "$name skipped: no $2"
      return
    fi
    shift 2
  fi
  local left=$((budget - (SECONDS - start)))
  if ((left < needed)); then
    say "$name skipped: under $needed s left"
    return
  fi
  say "$name: $*"
  timeout "$left" "$@" >"$out/$name.txt" 2>&1
  local rc=$?
  say "$name done (rc $rc$( ((rc == 124)) && echo ': stopped at the budget'))"
}
# A prefix that prints the command's wall, user and system seconds and peak resident memory (KiB)
# after its output (GNU time: the bundle's, else the system's; without one the summary's clock).
time_format='time: %e s wall, %U s user, %S s system, %M KiB peak'
if [[ -x $bin/time ]]; then
  timed=("$bin/time" -f "$time_format")
elif [[ -x /usr/bin/time ]]; then
  timed=(/usr/bin/time -f "$time_format")
else
  timed=()
  say "no GNU time: the steps' times are the summary's"
fi
{
  echo "nproc: $(nproc)"
  grep -m1 'model name' /proc/cpuinfo
  free -g | head -2
  uname -r
} >"$out/machine.txt" 2>&1
cat "$out/machine.txt" >>"$summary"

step tiles 120 "${bench[@]}" tiles --sizes 10000 --elevations 40,5 --threads 1,2,4,8,16 --no-untiled
step write-million 60 "${bench[@]}" write-city --boxes 166667 --elevation 40 --output "$work/m40"
for arithmetic in fast exact; do
  flag=()
  [[ $arithmetic == fast ]] && flag=(--fast)
  for threads in 16 2; do
    step "million-$arithmetic-$threads" 40 --needs "$work/m40/scene.json" "${timed[@]}" "${shadow[@]}" compute \
      "$work/m40/scene.json" -o "$work/m40-out" --areas-only --threads "$threads" "${flag[@]}"
  done
done
rm -rf "$work/m40" "$work/m40-out"
step low-sun-million 120 "${bench[@]}" low-sun --sizes 166667 --elevations 40,5 --threads 16
for threads in 1 2 4 8 16; do
  step "year-sample-$threads" 30 "${bench[@]}" series --sample 400 --runs 4 --arithmetic fast --threads "$threads"
  step "year-sample-exact-$threads" 30 "${bench[@]}" series --sample 64 --runs 2 --arithmetic exact --threads "$threads"
done
# The year scenes: the same city as write-city's, with a year of hourly suns at 48° N, 2.35° E.
city_scene=(python3 "$root/tools/bench/city_scene.py" --longitude 2.35)
step write-year 20 "${city_scene[@]}" --boxes 1000 -o "$work/year.json"
step year-fast-16 40 --needs "$work/year.json" "${timed[@]}" "${shadow[@]}" series "$work/year.json" \
  -o "$work/year-out" --fast --threads 16 --quiet
step year-exact-16 90 --needs "$work/year.json" "${timed[@]}" "${shadow[@]}" series "$work/year.json" \
  -o "$work/year-out" --threads 16 --quiet
step write-year-10k 30 "${city_scene[@]}" --boxes 10000 -o "$work/year10k.json"
step year10k-fast-16 160 --needs "$work/year10k.json" "${timed[@]}" "${shadow[@]}" series "$work/year10k.json" \
  -o "$work/year10k-out" --fast --threads 16 --quiet
say "finished"
