#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes ParaView's Python (pvpython) usable beside libshadow's build dependencies on Debian 12.
#
# Debian's python3-paraview (which holds pvpython and ParaView's Python modules) conflicts with
# python3-vtk9, which libvtk9-dev depends on: installing it would remove the libraries libshadow
# builds against. So the paraview package is installed normally (it does not conflict), and
# python3-paraview of the same version is unpacked, not installed, into a private prefix.
# tools/paraview/pvpython.sh runs it from there with ParaView's own modules first on sys.path.
#
# Idempotent; needs root (or sudo) only to write the prefix. Prefix: $LIBSHADOW_PVPYTHON_PREFIX
# or /opt/libshadow/python3-paraview.
set -euo pipefail

prefix="${LIBSHADOW_PVPYTHON_PREFIX:-/opt/libshadow/python3-paraview}"

if dpkg-query -W -f='${Status}' python3-paraview 2>/dev/null | grep -q "install ok installed"; then
  echo "setup-pvpython: python3-paraview is installed system-wide; nothing to unpack"
  exit 0
fi
if ! dpkg-query -W -f='${Status}' paraview 2>/dev/null | grep -q "install ok installed"; then
  echo "setup-pvpython: the paraview package is not installed (scripts/install-deps.sh --tests installs it)" >&2
  exit 1
fi

version="$(dpkg-query -W -f='${Version}' paraview)"
stamp="$prefix/.libshadow-version"
if [[ -x "$prefix/usr/bin/pvpython3.11" || -x "$prefix/usr/bin/pvpython" ]] &&
   [[ -f "$stamp" && "$(cat "$stamp")" == "$version" ]]; then
  echo "setup-pvpython: python3-paraview $version already unpacked in $prefix"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
chmod 755 "$scratch"  # apt's download sandbox user must be able to write here
(
  cd "$scratch"
  if ! apt-get download -qq "python3-paraview=$version" 2>/dev/null; then
    $SUDO apt-get update -qq
    apt-get download -qq "python3-paraview=$version"
  fi
)
deb="$(ls "$scratch"/python3-paraview_*.deb)"
$SUDO rm -rf "$prefix"
$SUDO mkdir -p "$prefix"
$SUDO dpkg -x "$deb" "$prefix"
echo "$version" | $SUDO tee "$stamp" >/dev/null
echo "setup-pvpython: unpacked python3-paraview $version into $prefix"
