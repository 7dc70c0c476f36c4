#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, and runs the forest and
# city benchmark (every method, 640x480 and 1280x960, paper-scale scenes), writing its
# markdown report, JSON and plots under out/ (or $LOGRID_OUT). About 8 minutes on 2
# cores with llvmpipe. Extra arguments go to `logrid bench` (e.g. --frames 10).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
out=${LOGRID_OUT:-$root/out}
mkdir -p "$out/plots"
"$root/build/bin/logrid" bench --scenes forest,city --sizes 640x480,1280x960 \
  --frames 30 --repeat 2 --markdown "$out/BENCHMARK.md" --json "$out/bench.json" \
  --plots "$out/plots" "$@" >/dev/null
echo "wrote $out/BENCHMARK.md, $out/bench.json and $out/plots/" >&2
