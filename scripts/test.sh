#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs every test
# (labels unit, gl, oracle, fuzz). GL tests must not be skipped here.
# Usage: scripts/test.sh [ctest arguments, e.g. -L unit]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
export LOGRID_REQUIRE_GL=1
jobs=$(nproc 2>/dev/null || echo 2)
cd "$root/build"
ctest --output-on-failure -j "$jobs" "$@"
