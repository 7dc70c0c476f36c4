#!/usr/bin/env bash
# ThreadSanitizer run of everything in logrid that starts threads: the BVH builder's
# parallel subtrees, the DDO build (welding, edge linking, the face workers) and the CPU
# occlusion buffer's worker threads (tests/unit/thread_test.cpp drives each above the
# size at which it really starts threads, and compares with one thread). Called by
# .ci/run after scripts/sanitize.sh. GL-free: builds only thread_test and the libraries it
# links (core, cpu, bvh) into build-tsan/ (gcc, RelWithDebInfo), so Mesa's own threads
# are not in the run and nothing needs suppressing. A few minutes on 2 cores from
# scratch. Any ThreadSanitizer report fails the run.
# Usage: scripts/tsan.sh [extra gtest arguments]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"
build="$root/build-tsan"
jobs=$(nproc 2>/dev/null || echo 2)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [[ ! -f "$build/build.ninja" ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
    -DLOGRID_SANITIZE=thread -DLOGRID_BUILD_GL=OFF -DLOGRID_BUILD_SAMPLES=OFF \
    -DLOGRID_BUILD_BENCHMARKS=OFF >/dev/null
fi
cmake --build "$build" -j "$jobs" --target thread_test

# halt_on_error: the first report fails the run; exitcode 66 tells it from a test failure.
export TSAN_OPTIONS=halt_on_error=1:exitcode=66:second_deadlock_stack=1:history_size=4
"$build/bin/thread_test" "$@"
echo "tsan.sh: no ThreadSanitizer findings" >&2
