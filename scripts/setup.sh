#!/usr/bin/env bash
# Installs the Debian 12 packages logrid needs, only those missing. Quiet when
# everything is present. Run by scripts/build.sh (for test.sh and bench.sh); scripts that
# need more (scripts/fuzz.sh: clang) name the extra packages as arguments.
set -euo pipefail

# Exactly what the README's two commands use (each line says who needs it).
packages=(
  # toolchain
  g++ cmake ninja-build pkg-config
  # GL through EGL: libepoxy at build time (it brings the EGL and GL headers); at run time
  # it loads libEGL and libGL (GLVND), which need Mesa's EGL and its drivers (llvmpipe
  # works without a GPU)
  libepoxy-dev libegl1 libgl1 libegl-mesa0 libgl1-mesa-dri
  # libraries: GLM (core), OpenImageIO with the tools its CMake targets name, CLI11,
  # assimp and the zlib its target links, nlohmann-json, meshoptimizer (the samples'
  # clusters, --cluster)
  libglm-dev libopenimageio-dev openimageio-tools libcli11-dev libassimp-dev zlib1g-dev
  nlohmann-json3-dev libmeshoptimizer-dev
  # logrid view (built where these are found): a window through GLFW with GLX (Mesa's GLX
  # vendor library), a Dear ImGui panel (its pkg-config file requires stb)
  libglfw3-dev libimgui-dev libstb-dev libglx-mesa0
  # tests (GoogleTest; Xvfb gives the viewer's tests a display), micro-benchmarks (Google
  # Benchmark), plots of `logrid bench`
  libgtest-dev xvfb libbenchmark-dev gnuplot-nox
  # extra packages named by the caller (scripts/fuzz.sh: clang)
  "$@"
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
