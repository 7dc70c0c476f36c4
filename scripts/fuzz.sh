#!/usr/bin/env bash
# Builds and runs one libFuzzer target for a given time (not part of the test run).
# Usage: scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]
#   TARGET   loader | camera_path | grid | ddo_file | animation | config
#            (tests/fuzz/TARGET_fuzzer.cpp)
#   SECONDS  how long to fuzz (libFuzzer's -max_total_time)
# Builds with clang, AddressSanitizer and UndefinedBehaviorSanitizer into build-fuzz/
# (installs clang-14 and libclang-rt-14-dev if missing). The fuzzer starts from the
# committed corpus tests/fuzz/corpus/TARGET/ and keeps what it adds in
# build-fuzz/corpus/TARGET/; a failing input is written to build-fuzz/findings/TARGET/.
# Once it is fixed, copy the finding into tests/fuzz/corpus/TARGET/: the fuzz label of
# ctest replays that directory on every run (fuzz_replay_TARGET).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ $# -lt 2 ]]; then
  echo "usage: $0 TARGET SECONDS [libFuzzer options...]   (TARGET: loader, camera_path, grid, ddo_file, animation, config)" >&2
  exit 2
fi
target=$1 seconds=$2
shift 2
if [[ ! -f "$root/tests/fuzz/${target}_fuzzer.cpp" ]]; then
  echo "fuzz.sh: unknown target '$target'; the targets are tests/fuzz/*_fuzzer.cpp:" \
    "$(cd "$root/tests/fuzz" && ls *_fuzzer.cpp | sed 's/_fuzzer.cpp//' | tr '\n' ' ')" >&2
  exit 2
fi
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [[ "$seconds" -lt 1 ]]; then
  echo "fuzz.sh: SECONDS must be a whole number of seconds, at least 1 (got '$seconds')" >&2
  exit 2
fi
"$root/scripts/setup.sh" clang-14 libclang-rt-14-dev

build="$root/build-fuzz"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
if [[ ! -f "$build/build.ninja" ]]; then
  CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -G Ninja \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
    "-DLOGRID_SANITIZE=address;undefined;fuzzer-no-link" -DLOGRID_LIBFUZZER=ON \
    -DLOGRID_BUILD_BENCHMARKS=OFF >/dev/null
fi
cmake --build "$build" --target "${target}_fuzzer" -j "$(nproc 2>/dev/null || echo 2)"

corpus="$build/corpus/$target" findings="$build/findings/$target"
mkdir -p "$corpus" "$findings"
# Inputs are written to files by some targets (loader): keep them in memory where possible.
[[ -z "${TMPDIR:-}" && -d /dev/shm && -w /dev/shm ]] && export TMPDIR=/dev/shm
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
echo "fuzz.sh: $target for ${seconds}s; corpus $corpus, findings $findings" >&2
# The first directory receives new inputs; the committed corpus is only read. The timeout
# is wall-clock time: generous, because a fuzzer at low priority on a busy machine may wait
# long for the CPU (inputs it reported at -timeout=20 replayed in milliseconds).
exec "$build/bin/${target}_fuzzer" "$corpus" "$root/tests/fuzz/corpus/$target" \
  -max_total_time="$seconds" -timeout=120 -rss_limit_mb=2048 -max_len=65536 \
  -artifact_prefix="$findings/" -print_final_stats=1 "$@"
