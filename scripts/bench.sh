#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, and runs the forest and
# city benchmark (every method, 640x480 and 1280x960, paper-scale scenes), writing its
# markdown report, JSON, plots and a few overlay pictures under out/ (or $LOGRID_OUT).
# About 6 minutes on 2 cores with llvmpipe. Extra arguments go to `logrid bench` and
# override its defaults (the last of a repeated option wins); --frames N also caps the
# frames of the picture walks (e.g. --frames 2 for a quick check).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
out=${LOGRID_OUT:-$root/out}
mkdir -p "$out/plots"
# The picture walks take 4 frames, or fewer when the last --frames asks for fewer.
walk_frames=4 frames=
args=("$@")
for ((i = 0; i < ${#args[@]}; ++i)); do
  case ${args[i]} in
    --frames) frames=${args[i + 1]:-} ;;
    --frames=*) frames=${args[i]#--frames=} ;;
  esac
done
if [[ $frames =~ ^[0-9]+$ ]] && ((frames >= 1 && frames < walk_frames)); then walk_frames=$frames; fi
"$root/build/bin/logrid" bench --scenes forest,city --sizes 640x480,1280x960 \
  --frames 30 --repeat 2 --markdown "$out/BENCHMARK.md" --json "$out/bench.json" \
  --plots "$out/plots" "$@" >/dev/null
# A few verified frames of each walkthrough as pictures: the rendered frame and the
# overlay of the paper's figures 1 and 5 (tile states, tested boxes, drawn leaf boxes).
for scene in forest city; do
  "$root/build/bin/logrid" walk --scene "$scene" --frames "$walk_frames" --verify \
    --images "$out/images" --overlay --json "$out/walk_$scene.json" >/dev/null
done
echo "wrote $out/BENCHMARK.md, $out/bench.json, $out/plots/ and $out/images/" >&2
