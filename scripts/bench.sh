#!/usr/bin/env bash
# Speed benchmarks on one core (the design's budgets are per core):
#
#   bash scripts/bench.sh                       # features: builds build/ (Release) if needed, then
#                                               # taskset -c 0 build/bench/features_bench
#   bash scripts/bench.sh --benchmark_filter=features   # extra arguments go to the benchmark binary
#   bash scripts/bench.sh hmm [ARGS...]         # the HMM engine: taskset -c 0 build/bench/hmm_bench (~2 min)
#   bash scripts/bench.sh animation [ARGS...]   # head and mouth models' training and synthesis (mouth: batch,
#                                               # windowed and MMSE): build/bench/animation_bench
#   bash scripts/bench.sh face [ARGS...]        # off-screen rendering (render_bench) and the MP4 export, whole and
#                                               # encoding alone (export_bench), our face's and the test
#                                               # characters' (each printed over our face's: "ratio"): NOT pinned,
#                                               # these use both cores (llvmpipe's and x264's threads); run them
#                                               # on an idle machine
#   bash scripts/bench.sh all                   # all four, one after the other
#
# features_bench: speed of the feature extraction against Praat and SPTK RAPT. Prints Google Benchmark's table
# (realtime_factor = audio seconds per second) and a summary: "ours N× real time, Praat M×, RAPT K×;
# ours/Praat = R". The peers' times include process start-up and file reading; the *_startup rows measure that
# alone on 0.1 s of audio.
# hmm_bench: one Baum-Welch iteration of ours against the numpy reference (tools/hmm_reference.py, run with
# OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=MKL_NUM_THREADS=1 on the same core), then the per-frame cost of online
# Viterbi and of the emission likelihoods; the summary gives numpy/ours per case and names numpy's BLAS.
# Environment: BUILD_DIR (default build), BENCH_CPU (default 0), TALKINGHEAD_DATA (shared data folder).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
build_dir="${BUILD_DIR:-build}"
cpu="${BENCH_CPU:-0}"

which="features"
case "${1:-}" in
  features | hmm | animation | face | all)
    which="$1"
    shift
    ;;
esac
targets=()
[[ "$which" == features || "$which" == all ]] && targets+=(features_bench)
[[ "$which" == hmm || "$which" == all ]] && targets+=(hmm_bench)
[[ "$which" == animation || "$which" == all ]] && targets+=(animation_bench)
[[ "$which" == face || "$which" == all ]] && targets+=(render_bench export_bench)

if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
if ! grep -q '^CMAKE_BUILD_TYPE:STRING=Release$' "$build_dir/CMakeCache.txt"; then
  echo "bench: warning: $build_dir/ is not a Release build; numbers will not be representative" >&2
fi
cmake --build "$build_dir" --parallel "$(nproc 2>/dev/null || echo 2)" --target "${targets[@]}"

# The numpy reference (a subprocess of hmm_bench) inherits the core and these: one BLAS thread.
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1
status=0
for target in "${targets[@]}"; do
  case "$target" in
    render_bench | export_bench) "$build_dir/bench/$target" "$@" || status=$? ;;
    *) taskset -c "$cpu" "$build_dir/bench/$target" "$@" || status=$? ;;
  esac
done
exit "$status"
