#!/usr/bin/env bash
# Installs every Debian package causticbench needs, idempotently and non-interactively.
# Usage: scripts/setup.sh            (as root, or with sudo available)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libembree-dev libceres-dev libopencv-dev libopencv-contrib-dev libopenimageio-dev openimageio-tools
  libglm-dev libvulkan-dev mesa-vulkan-drivers glslc vulkan-tools
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libfmt-dev libtbb-dev libassimp-dev
  libnanoflann-dev libpcg-cpp-dev libxxhash-dev libgtest-dev libgmock-dev libeigen3-dev
  glmark2-data blender-data embree-tools
  python3-numpy python3-openimageio
  slurm-wlm munge
  chromium
)

as_root() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} Debian packages already installed"
  exit 0
fi

echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
as_root apt-get update -qq
as_root apt-get install -y -qq --no-install-recommends "${missing[@]}"
