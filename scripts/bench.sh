#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, and runs the forest and
# city benchmark, writing its report, JSON, plots and images under out/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
out=${LOGRID_OUT:-$root/out}
mkdir -p "$out"
"$root/build/bin/logrid" render --out "$out/render.png"
echo "wrote $out/render.png" >&2
