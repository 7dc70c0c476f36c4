#!/usr/bin/env bash
# The Debian package, tested as a user installs it: builds liblogrid-dev with
# `cpack -G DEB` (libraries only, installed under /usr), installs it with apt-get together
# with the dependencies it declares, and builds and runs the install consumer
# (tests/install/consumer) against the installed package twice: through CMake
# (find_package(logrid 0.1)) and through pkg-config alone (logrid, logrid-core).
#
# Meant for a throwaway Debian 12 root (a container or a chroot, as root): it installs
# packages with apt-get and logrid into /usr. It refuses to run where liblogrid-dev is
# already installed. The packages that only building logrid needs (libepoxy-dev,
# libglm-dev, pkgconf) are removed again before the package goes in if this script
# installed them, so that on a fresh root apt-get has to bring back what the package
# declares; where they were installed before, they stay and that check is weaker. The
# package is removed again at the end. Not part of .ci/run (it takes minutes: apt-get,
# a build of the libraries from scratch).
#
# Usage: scripts/package-test.sh [build directory, default build-package/]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build-package}")  # absolute: apt-get takes ./ or / paths
start=$SECONDS
export DEBIAN_FRONTEND=noninteractive

say() { echo "package-test: $*" >&2; }
fail() {
  say "FAILED: $*"
  exit 1
}
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || fail "needs root or sudo (apt-get, dpkg)"
  sudo_cmd=(sudo)
fi
installed() { [[ $(dpkg-query -W -f='${Status}' "$1" 2>/dev/null || true) == "install ok installed" ]]; }
missing_of() {
  local p
  for p; do installed "$p" || echo "$p"; done
}

installed liblogrid-dev && fail "liblogrid-dev is already installed; run this in a fresh Debian 12 root"

# What a consumer needs as well (kept), and what only building logrid needs (removed again
# before the package is installed, if this script installed it).
consumer_tools=(g++ cmake ninja-build)
build_only=(libepoxy-dev libglm-dev pkgconf)
mapfile -t new_build_only < <(missing_of "${build_only[@]}")
mapfile -t new_tools < <(missing_of "${consumer_tools[@]}")
if [[ ${#new_build_only[@]} -gt 0 || ${#new_tools[@]} -gt 0 ]]; then
  say "installing ${new_tools[*]} ${new_build_only[*]}"
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
    "${new_tools[@]}" "${new_build_only[@]}" >/dev/null
fi

# 1. The package: the libraries alone (no tests, samples, benchmarks or viewer).
say "building the package in $build"
rm -rf "$build"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr \
  -DLOGRID_BUILD_TESTS=OFF -DLOGRID_BUILD_SAMPLES=OFF -DLOGRID_BUILD_BENCHMARKS=OFF \
  -DLOGRID_BUILD_VIEWER=OFF >"$build.configure.log" 2>&1 ||
  { cat "$build.configure.log" >&2; fail "configure"; }
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" >"$build.build.log" 2>&1 ||
  { tail -n 50 "$build.build.log" >&2; fail "build"; }
(cd "$build" && cpack -G DEB >cpack.log 2>&1) || { cat "$build/cpack.log" >&2; fail "cpack -G DEB"; }
debs=("$build"/liblogrid-dev_*.deb)
[[ ${#debs[@]} -eq 1 && -f ${debs[0]} ]] || fail "cpack made no liblogrid-dev_*.deb in $build"
deb=${debs[0]}
say "built $(basename "$deb")"
dpkg-deb -f "$deb" Package Version Architecture Depends Recommends >&2

# 2. Without the build-only packages this script brought in, install the package and let
#    apt-get resolve what it declares.
if [[ ${#new_build_only[@]} -gt 0 ]]; then
  say "removing the build-only packages installed above: ${new_build_only[*]}"
  "${sudo_cmd[@]}" apt-get purge -y -qq "${new_build_only[@]}" >/dev/null
  "${sudo_cmd[@]}" apt-get autoremove -y -qq >/dev/null
  for p in "${new_build_only[@]}"; do ! installed "$p" || fail "$p is still installed"; done
fi
say "installing $(basename "$deb") with apt-get (its Depends and Recommends)"
"${sudo_cmd[@]}" apt-get install -y -qq --install-recommends "$deb" >/dev/null ||
  fail "apt-get install $deb"
installed liblogrid-dev || fail "liblogrid-dev is not installed after apt-get"
trap 'say "removing liblogrid-dev"; "${sudo_cmd[@]}" apt-get purge -y -qq liblogrid-dev >/dev/null || true' EXIT

# What the package holds: the five static libraries, headers, CMake and pkg-config files.
files=$(dpkg -L liblogrid-dev)
for want in liblogrid_core.a liblogrid_cpu.a liblogrid_bvh.a liblogrid_zread.a liblogrid_gl.a \
  /usr/include/logrid/culler.hpp /usr/include/logrid/gl/context.hpp \
  /cmake/logrid/logridConfig.cmake /cmake/logrid/logridConfigVersion.cmake \
  /pkgconfig/logrid.pc /pkgconfig/logrid-core.pc; do
  grep -q -- "$want\$" <<<"$files" || fail "the package has no file ending in $want"
done

# The consumer's own dependency: consumer_glm uses GLM itself (logrid/glm_camera.hpp).
installed libglm-dev || "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends libglm-dev >/dev/null

# 3. CMake: find_package(logrid 0.1) from /usr, the package's files only.
work="$build/consumer"
rm -rf "$work"
say "building tests/install/consumer with CMake against the installed package"
cmake -S "$root/tests/install/consumer" -B "$work/cmake" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work.cmake.log" 2>&1 ||
  { cat "$work.cmake.log" >&2; fail "configure the consumer"; }
logrid_dir=$(sed -n 's/^logrid_DIR:[A-Z]*=//p' "$work/cmake/CMakeCache.txt")
dpkg -S "$(realpath "$logrid_dir")/logridConfig.cmake" | grep -q '^liblogrid-dev:' ||
  fail "find_package(logrid) used $logrid_dir, which is not the package's"
say "find_package(logrid 0.1): $(grep -o 'logrid [0-9.]* from [^ ]*' "$work.cmake.log")"
cmake --build "$work/cmake" >"$work.build.log" 2>&1 || { cat "$work.build.log" >&2; fail "build the consumer"; }
"$work/cmake/consumer_core" || fail "consumer_core (CMake)"
"$work/cmake/consumer_glm" || fail "consumer_glm (CMake)"
[[ -x $work/cmake/consumer_gl ]] || fail "the package has no logrid::gl: consumer_gl was not built"
"$work/cmake/consumer_gl" run || fail "consumer_gl (CMake) on a headless GL context"

# A later version is refused by the package's version file.
mkdir -p "$work/too-new"
printf 'cmake_minimum_required(VERSION 3.20)\nproject(too_new LANGUAGES CXX)\nfind_package(logrid 0.2 CONFIG REQUIRED)\n' \
  >"$work/too-new/CMakeLists.txt"
if cmake -S "$work/too-new" -B "$work/too-new/build" -G Ninja >"$work/too-new.log" 2>&1; then
  fail "find_package(logrid 0.2) accepted the installed $(dpkg-query -W -f='${Version}' liblogrid-dev)"
fi
grep -q 'version: ' "$work/too-new.log" || { cat "$work/too-new.log" >&2; fail "find_package(logrid 0.2) failed, but not on the version"; }
say "find_package(logrid 0.2): refused, as it should be"

# 4. pkg-config alone: a compiler and the flags of logrid-core and logrid.
say "building tests/install/consumer with pkg-config against the installed package"
mkdir -p "$work/pkgconfig"
say "pkg-config --modversion logrid logrid-core: $(pkg-config --modversion logrid logrid-core | tr '\n' ' ')"
core_flags=$(pkg-config --cflags --libs logrid-core)
gl_flags=$(pkg-config --cflags --libs logrid)
say "logrid-core: $core_flags"
say "logrid: $gl_flags"
# shellcheck disable=SC2086 # the flags are words
g++ -std=c++17 -Wall -Wextra -Werror "$root/tests/install/consumer/main.cpp" $core_flags \
  -o "$work/pkgconfig/consumer_core" || fail "compile consumer_core with pkg-config"
"$work/pkgconfig/consumer_core" || fail "consumer_core (pkg-config)"
# shellcheck disable=SC2086
g++ -std=c++17 -Wall -Wextra -Werror "$root/tests/install/consumer/gl_main.cpp" $gl_flags \
  -o "$work/pkgconfig/consumer_gl" || fail "compile consumer_gl with pkg-config"
"$work/pkgconfig/consumer_gl" run || fail "consumer_gl (pkg-config) on a headless GL context"

say "passed: $(basename "$deb") installed with its dependencies; the consumer built and ran through CMake and pkg-config ($((SECONDS - start)) s)"
