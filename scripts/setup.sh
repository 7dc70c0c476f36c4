#!/usr/bin/env bash
# Installs the Debian 12 packages logrid needs, only those missing. Quiet when
# everything is present. Sourced or run by scripts/test.sh and scripts/bench.sh.
set -euo pipefail

packages=(
  # toolchain
  g++ cmake ninja-build pkg-config
  # GL through EGL (Mesa llvmpipe works without a GPU)
  libepoxy-dev libegl-dev libopengl-dev libglvnd-dev libegl-mesa0 libgl1-mesa-dri
  # libraries
  libglm-dev libopenimageio-dev openimageio-tools libcli11-dev libassimp-dev zlib1g-dev
  nlohmann-json3-dev fonts-dejavu-core
  # the interactive viewer (logrid view): a window through GLFW with GLX, a Dear ImGui panel
  libglfw3-dev libimgui-dev libstb-dev libgl1 libglx-mesa0
  # tests, benchmarks, plots; Xvfb runs the viewer's tests without a screen
  libgtest-dev libgmock-dev libbenchmark-dev gnuplot-nox xvfb xauth
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "setup: installing ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
