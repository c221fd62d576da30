#!/usr/bin/env bash
# Speed of the feature extraction against Praat and SPTK RAPT, on one core (the design's budgets are per core):
#
#   bash scripts/bench.sh                       # builds build/ (Release) if needed, then
#                                               # taskset -c 0 build/bench/features_bench
#   bash scripts/bench.sh --benchmark_filter=features   # extra arguments go to the benchmark binary
#
# Prints Google Benchmark's table (realtime_factor = audio seconds per second) and a summary:
# "ours N× real time, Praat M×, RAPT K×; ours/Praat = R". The peers' times include process start-up and file
# reading; the *_startup rows measure that alone on 0.1 s of audio. Environment: BUILD_DIR (default build),
# BENCH_CPU (default 0), TALKINGHEAD_DATA (shared data folder).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
build_dir="${BUILD_DIR:-build}"
cpu="${BENCH_CPU:-0}"

if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
if ! grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$build_dir/CMakeCache.txt"; then
  echo "bench: warning: $build_dir/ is not a Release build; numbers will not be representative" >&2
fi
cmake --build "$build_dir" --parallel "$(nproc 2>/dev/null || echo 2)" --target features_bench

exec taskset -c "$cpu" "$build_dir/bench/features_bench" "$@"
