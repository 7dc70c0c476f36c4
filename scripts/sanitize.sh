#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer run of the core, the depth readers and the
# scene loaders: builds into build-sanitize/ (gcc, RelWithDebInfo) and runs the unit and
# fuzz labels and the GL tests of the readers (the GL-state guard, the multisample
# resolve, the GL sources, the context and framebuffers). Called by .ci/run after
# scripts/test.sh; about 25 minutes on 2 cores from scratch. Any sanitizer report fails
# the run. Leaks inside Mesa (its LLVM JIT, the llvmpipe/swrast driver, EGL) are
# suppressed by name in tests/sanitize/lsan.supp; nothing of logrid's is.
# Usage: scripts/sanitize.sh [extra ctest arguments]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"
build="$root/build-sanitize"
jobs=$(nproc 2>/dev/null || echo 2)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [[ ! -f "$build/build.ninja" ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
    "-DLOGRID_SANITIZE=address;undefined" -DLOGRID_BUILD_BENCHMARKS=OFF >/dev/null
fi
# Only what the labels below run (not the logrid command, the oracle walks or the example).
targets=(unit_test gl_test)
if grep -q '^build bin/scenes_test' "$build/build.ninja"; then
  targets+=(scenes_test loader_fuzz_test)
fi
targets+=($(sed -n 's/^build bin\/\([a-z_]*_replay\):.*/\1/p' "$build/build.ninja"))
cmake --build "$build" -j "$jobs" --target "${targets[@]}"

export LOGRID_REQUIRE_GL=1
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1:check_initialization_order=1
export LSAN_OPTIONS=suppressions=$root/tests/sanitize/lsan.supp:print_suppressions=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
cd "$build"
# Unit and fuzz labels whole (install_consumer reinstalls and rebuilds the tree; the
# normal test run covers it), and the GL tests of the readers.
ctest --output-on-failure -j "$jobs" -L 'unit|fuzz' -E '^install_consumer$' "$@"
ctest --output-on-failure -j "$jobs" -L gl \
  -R 'GlState|Multisample|Sources|GlSource|Context|Triangle|Framebuffer|BadInput' "$@"
echo "sanitize.sh: no AddressSanitizer, LeakSanitizer or UndefinedBehaviorSanitizer findings" >&2
