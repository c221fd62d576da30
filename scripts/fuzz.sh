#!/usr/bin/env bash
# Fuzzes the audio reader (th::audio::decodeAudio) with libFuzzer + ASan + UBSan for a bounded time:
#
#   scripts/fuzz.sh                        # 60 s
#   FUZZ_SECONDS=180 scripts/fuzz.sh
#
# Builds build-fuzz/ with clang (its own tree: every target there is instrumented), writes the seed corpus
# from the shared data (TALKINGHEAD_DATA, default ../shared/data), and runs the fuzzer on a working corpus
# under build-fuzz/fuzz/ that persists between runs. Exits non-zero if the fuzzer finds a crash, a leak, a
# timeout (10 s per input) or an allocation beyond the memory limit; the input that did it is saved as
# build-fuzz/fuzz/artifacts/crash-* (or leak-, timeout-, oom-) and reproduces with
#   build-fuzz/fuzz/audio_reader_fuzzer build-fuzz/fuzz/artifacts/crash-...
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
build_dir="${FUZZ_BUILD_DIR:-build-fuzz}"
seconds="${FUZZ_SECONDS:-60}"

data_option=()
if [[ -n "${TALKINGHEAD_DATA:-}" ]]; then
    data_option=(-DTALKINGHEAD_DEFAULT_DATA_DIR="$TALKINGHEAD_DATA")
fi
CC=clang CXX=clang++ cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DTALKINGHEAD_FUZZ=ON -DTALKINGHEAD_WERROR=OFF "${data_option[@]}" > /dev/null
ninja -C "$build_dir" audio_reader_fuzzer audio_reader_fuzzer_seeds

fuzz_dir="$build_dir/fuzz"
mkdir -p "$fuzz_dir/corpus" "$fuzz_dir/artifacts"
echo "fuzz: audio_reader_fuzzer for ${seconds} s (corpus $fuzz_dir/corpus, seeds $fuzz_dir/audio_reader_seeds)"
# New inputs go to the first folder (corpus); the seeds are read only. Known leaks in third-party decoders
# are suppressed (each with its upstream report) in fuzz/lsan_suppressions.txt.
LSAN_OPTIONS="suppressions=$repo/fuzz/lsan_suppressions.txt${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
    "$fuzz_dir/audio_reader_fuzzer" "$fuzz_dir/corpus" "$fuzz_dir/audio_reader_seeds" \
    -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
    -artifact_prefix="$fuzz_dir/artifacts/" -print_final_stats=1
