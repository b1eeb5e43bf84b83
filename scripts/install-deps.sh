#!/usr/bin/env bash
# Installs what Tracegraph needs from Debian 12's packages; installs only what is missing, so
# running it again is cheap. Must run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libtbb-dev libglm-dev libboost-test-dev libstb-dev libpugixml-dev libassimp-dev
  libglfw3-dev libcli11-dev libembree-dev
  doxygen clang clang-format xvfb xauth python3
  # tg-view: OpenGL headers, and Mesa's software rasteriser for its test under Xvfb
  libgl-dev libgl1-mesa-dri
  # Valgrind: the kernels' dispatch tested as on a CPU without AVX-512, and Callgrind's counts
  # (scripts/count-instructions.sh)
  valgrind
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
