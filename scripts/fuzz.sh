#!/usr/bin/env bash
# Fuzzes the engine's file readers with libFuzzer + ASan + UBSan for a bounded time:
#   audio_reader_fuzzer     th::audio::decodeAudio (recordings)
#   model_file_fuzzer       th::hmm::parseModel (HMM model files)
#   animation_file_fuzzer   th::formats::readAnimation (CSV, JSON and .fap animation files)
#
#   scripts/fuzz.sh                        # 60 s of fuzzing in all, split between the three, two at a time
#   FUZZ_SECONDS=180 scripts/fuzz.sh
#
# Builds build-fuzz/ with clang (its own tree: every target there is instrumented), or uses FUZZ_BUILD_DIR as it is
# when that is a sanitizer tree configured with TALKINGHEAD_FUZZ (scripts/test.sh's), writes the seed corpora
# (recordings from the shared data, TALKINGHEAD_DATA, default ../shared/data; small models from the engine's
# model writer), and runs each fuzzer on a working corpus under build-fuzz/fuzz/ that persists between runs.
# All three always run; exits non-zero if any finds a crash, a leak, a timeout (10 s per input) or an allocation
# beyond the memory limit. The input that did it is saved as build-fuzz/fuzz/artifacts/<fuzzer>-crash-* (or
# -leak-, -timeout-, -oom-) and reproduces with
#   build-fuzz/fuzz/model_file_fuzzer build-fuzz/fuzz/artifacts/model_file_fuzzer-crash-...
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
build_dir="${FUZZ_BUILD_DIR:-build-fuzz}"
seconds="${FUZZ_SECONDS:-60}"
# 40 % for the audio decoders (the largest input space), 30 % each for the two text formats; at least 1 s each
# (libFuzzer reads -max_total_time=0 as "no limit").
audio_seconds=$((seconds * 4 / 10 > 0 ? seconds * 4 / 10 : 1))
model_seconds=$((seconds * 3 / 10 > 0 ? seconds * 3 / 10 : 1))
animation_seconds=$((seconds * 3 / 10 > 0 ? seconds * 3 / 10 : 1))

data_option=()
if [[ -n "${TALKINGHEAD_DATA:-}" ]]; then
    data_option=(-DTALKINGHEAD_DEFAULT_DATA_DIR="$TALKINGHEAD_DATA")
fi
if grep -qs '^TALKINGHEAD_FUZZ:BOOL=ON$' "$build_dir/CMakeCache.txt" &&
    grep -qs '^TALKINGHEAD_SANITIZE:BOOL=ON$' "$build_dir/CMakeCache.txt"; then
    # A sanitizer tree that has the fuzzers already (scripts/test.sh builds them with the tests): used as it is.
    echo "fuzz: the fuzzers of $build_dir"
else
    # -O1 -g1: the build is most of this script's time; line tables are enough for crash reports.
    CC=clang CXX=clang++ cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
        -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DTALKINGHEAD_FUZZ=ON -DTALKINGHEAD_WERROR=OFF "${data_option[@]}" \
        > /dev/null
fi
ninja -C "$build_dir" audio_reader_fuzzer audio_reader_fuzzer_seeds model_file_fuzzer model_file_fuzzer_seeds \
    animation_file_fuzzer

fuzz_dir="$build_dir/fuzz"
# A tree built earlier wrote its audio seeds from the data folder it was configured with; TALKINGHEAD_DATA, when
# given, is where they come from now.
if [[ -n "${TALKINGHEAD_DATA:-}" ]]; then
    "$fuzz_dir/make_audio_seeds" "$TALKINGHEAD_DATA" "$fuzz_dir/audio_reader_seeds"
fi
mkdir -p "$fuzz_dir/corpus" "$fuzz_dir/model_file_corpus" "$fuzz_dir/animation_file_corpus" \
    "$fuzz_dir/animation_file_seeds" "$fuzz_dir/artifacts"
# Animation seeds: one small valid file per format; the first byte picks the format (0 CSV, 1 JSON, 2 .fap).
printf '\000time_s,fap3,fap48\n0.0000000,12.5,-1745\n0.0333333,40,0\n0.0666667,7.25,1745\n' \
    > "$fuzz_dir/animation_file_seeds/seed.csv"
printf '\001{"format":"talkinghead-animation","version":1,"fps":30,"name":"seed","faps":[{"number":3,"name":"open_jaw","unit":"MNS"}],"time_s":[0,0.0333333],"frames":[[12.5],[40]]}' \
    > "$fuzz_dir/animation_file_seeds/seed.json"
{
    printf '\0022.1 seed 25 2\n'
    printf '0 0 1 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n'
    printf '0 12 -1745\n'
    printf '0 0 1 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n'
    printf '1 40\n'
} > "$fuzz_dir/animation_file_seeds/seed.fap"

# run_fuzzer NAME SECONDS CORPUS SEEDS [libFuzzer options...]: new inputs go to CORPUS; SEEDS are read only.
# Known leaks in third-party decoders are suppressed (each with its upstream report) in fuzz/lsan_suppressions.txt.
# Returns non-zero if the fuzzer found something.
run_fuzzer() {
    local name="$1" time="$2" corpus="$3" seeds="$4"
    shift 4
    echo "fuzz: $name for ${time} s (corpus $corpus, seeds $seeds)"
    if ! LSAN_OPTIONS="suppressions=$repo/fuzz/lsan_suppressions.txt${LSAN_OPTIONS:+:$LSAN_OPTIONS}" \
        "$fuzz_dir/$name" "$corpus" "$seeds" \
        -max_total_time="$time" -rss_limit_mb=2048 -timeout=10 \
        -artifact_prefix="$fuzz_dir/artifacts/$name-" -print_final_stats=1 "$@"; then
        echo "fuzz: $name FAILED (see $fuzz_dir/artifacts/$name-*)"
        return 1
    fi
}

# Two at a time, one per core: the audio fuzzer beside the two text fuzzers one after the other (each writes
# its own log, shown in order afterwards). The audio fuzzer's corpus keeps its first name (corpus/), so earlier
# runs' inputs are not lost.
run_fuzzer audio_reader_fuzzer "$audio_seconds" "$fuzz_dir/corpus" "$fuzz_dir/audio_reader_seeds" \
    >"$fuzz_dir/audio_reader_fuzzer.log" 2>&1 &
audio_pid=$!
{
    status=0
    run_fuzzer model_file_fuzzer "$model_seconds" "$fuzz_dir/model_file_corpus" "$fuzz_dir/model_file_seeds" \
        -dict="$repo/fuzz/model_file.dict" -max_len=16384 || status=1
    run_fuzzer animation_file_fuzzer "$animation_seconds" "$fuzz_dir/animation_file_corpus" \
        "$fuzz_dir/animation_file_seeds" -max_len=16384 || status=1
    exit "$status"
} >"$fuzz_dir/text_fuzzers.log" 2>&1 &
text_pid=$!
failed=0
wait "$audio_pid" || failed=1
wait "$text_pid" || failed=1
cat "$fuzz_dir/audio_reader_fuzzer.log" "$fuzz_dir/text_fuzzers.log"
exit "$failed"
