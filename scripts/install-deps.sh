#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian 12 packages plancheck needs, only when some are missing.
# Idempotent: a second run with everything present does nothing and needs no root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libtbb-dev libembree-dev libassimp-dev
  nlohmann-json3-dev libcli11-dev libgmp-dev libcairo2-dev fonts-dejavu-core
  liburdfdom-dev libtinyxml2-dev
  libgdal-dev gdal-bin
  python3-dev pybind11-dev python3-numpy
  python3-venv python3-pip python3-setuptools python3-wheel python3-build python3-pybind11 mypy
  libgtest-dev libgmock-dev libbenchmark-dev
  libfcl-dev libcgal-dev
  # OMPL for <plancheck/ompl.h>'s example and bench; Debian's omplConfig.cmake
  # names libboost_filesystem.so, which libompl-dev does not pull in.
  libompl-dev libboost-filesystem-dev
  assimp-testmodels dart-doc
  clang libclang-rt-14-dev
  chromium
  libopenmpi-dev openmpi-bin
)
# report.html's viewer is bundled with node/npm (src/viewer). Debian's nodejs
# and npm only when the commands are missing: a NodeSource node brings its
# own npm and conflicts with Debian's.
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    SUDO=sudo
  else
    echo "install-deps: these Debian packages are missing: ${missing[*]}" >&2
    echo "install-deps: run as root (or with passwordless sudo): apt-get install ${missing[*]}" >&2
    exit 1
  fi
else
  SUDO=
fi
$SUDO apt-get update -q >&2
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
