#!/usr/bin/env bash
# The soak run (not part of CI): at least 10,000 frames over random scenes (forest, city,
# a model file through the loader), seeds, sizes, tile sizes, depth formats, conventions,
# sample counts, every method with the settings it takes (lookahead, coherence, query
# schedules), every reader (cpu included), moving objects on each motion hierarchy, and
# DDO, each frame checked against the object-ID oracle,
# in one process whose memory is watched (tests/soak/soak.cpp). About an hour on 2 cores
# with llvmpipe. Writes the summary to out/soak.json (or $LOGRID_OUT/soak.json) and the
# progress to stderr; exits 1 on any missed visible object or error.
# Usage: scripts/soak.sh [--frames N] [--frames-per-run K] [--seed S] [--memory-trace FILE]
#   --memory-trace FILE  one line a run: RSS, peak, C heap in use and held, threads, setting
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh" >/dev/null
out=${LOGRID_OUT:-$root/out}
mkdir -p "$out"
exec "$root/build/bin/logrid_soak" --json "$out/soak.json" "$@"
