#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, and runs the forest and
# city benchmark (every method, 640x480 and 1280x960, paper-scale scenes), writing its
# markdown report, JSON, plots and a few overlay pictures under out/ (or $LOGRID_OUT).
# About 6 minutes on 2 cores with llvmpipe. Extra arguments go to `logrid bench`
# (e.g. --frames 10).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
out=${LOGRID_OUT:-$root/out}
mkdir -p "$out/plots"
"$root/build/bin/logrid" bench --scenes forest,city --sizes 640x480,1280x960 \
  --frames 30 --repeat 2 --markdown "$out/BENCHMARK.md" --json "$out/bench.json" \
  --plots "$out/plots" "$@" >/dev/null
# A few verified frames of each walkthrough as pictures: the rendered frame and the
# overlay of the paper's figures 1 and 5 (tile states, tested boxes, drawn leaf boxes).
for scene in forest city; do
  "$root/build/bin/logrid" walk --scene "$scene" --frames 4 --verify --images "$out/images" \
    --overlay --json "$out/walk_$scene.json" >/dev/null
done
echo "wrote $out/BENCHMARK.md, $out/bench.json, $out/plots/ and $out/images/" >&2
