#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs libshadow's build and test dependencies from Debian's packages.
# Idempotent: packages already present are skipped, and apt-get update runs
# only when something is missing. Must run as root (or via sudo).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libglm-dev
  libpolyclipping-dev
  libvtk9-dev
  libgtest-dev libgmock-dev librapidcheck-dev
  libcli11-dev nlohmann-json3-dev
  libjemalloc-dev
  # The zlib streams of every .vtp file, made by libdeflate (libshadow/io, vtk_zlib_blocks).
  libdeflate-dev
  # `mpirun -np N shadow series` and its test (docs/cluster.md); the build works without it.
  libopenmpi-dev openmpi-bin
  # `shadow render` and its tests on a machine without a display: an X server in memory and
  # Mesa's software OpenGL (llvmpipe).
  xvfb xauth libgl1-mesa-dri
  # `shadow render -o view.pdf` (the exact vector view through cairo), and rsvg-convert, with
  # which the tests render the SVG view.
  libcairo2-dev librsvg2-bin
  # The sampled baselines that shadow-bench measures against the exact engine.
  libembree-dev
  # The Python module (python/, docs/python.md) and its tests.
  pybind11-dev python3-dev python3-numpy python3-pytest python3-hypothesis
)
# The test suite also needs ParaView (its headless test opens a result in pvpython) and clang with
# libFuzzer and the sanitizers' runtimes (scripts/run-fuzz.sh; GCC 12's UBSan miscompiles an
# idiom of culling.hpp, so the sanitizer build uses clang): `install-deps.sh --tests`, as
# scripts/run-tests.sh does.
with_tests=0
for arg in "$@"; do
  case "$arg" in
    --tests) with_tests=1 ;;
    *) echo "install-deps: unknown option $arg (known: --tests)" >&2; exit 2 ;;
  esac
done
if ((with_tests)); then
  packages+=(paraview clang-14 libclang-rt-14-dev)
  # SeriesResult.to_pandas() and `pip install .` (docs/python.md), tested by ctest python and
  # python_pip.
  packages+=(python3-pandas python3-pip python3-setuptools python3-wheel)
fi
# Optional: plotting benchmarks (tools/bench/plot_bench.py) and rendering results headless
# (tools/inspect/render_result.py). LIBSHADOW_WITH_EXTRAS=1 bash scripts/install-deps.sh
if [[ "${LIBSHADOW_WITH_EXTRAS:-0}" == 1 ]]; then
  packages+=(python3-matplotlib python3-vtk9 xvfb xauth)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

finish() {
  # pvpython beside libvtk9-dev: see scripts/setup-pvpython.sh.
  if ((with_tests)); then bash "$(dirname "$0")/setup-pvpython.sh"; fi
}

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  finish
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
finish
