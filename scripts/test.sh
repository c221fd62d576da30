#!/usr/bin/env bash
# Every test, the way CI runs them (.ci/run calls this):
#
#   bash scripts/test.sh
#
# or the quick tier, for the edit-build-test loop (a few minutes on two cores after scripts/setup.sh):
#
#   bash scripts/test.sh --quick
#
# which builds the tests labelled `unit` (tests/CMakeLists.txt says what each label means) in setup's Release
# build (BUILD_DIR, default build/) and runs them, no sanitizers, nothing that needs a window, a sound server,
# the CLI or tens of seconds; the full run below is what a change must pass.
#
# Parts, in order (each is timed; a failed part does not stop the later independent ones):
#   1. packages     scripts/install-packages.sh (no network when everything is installed)
#   2. node tools   scripts/install-node-tools.sh into build-asan/node: the Khronos glTF validator the
#                   crosscheck tests run (no network when it is there)
#   3. format       clang-format --dry-run over every C++ source: the tree is formatted (.clang-format)
#   4. build        one build of everything (engine, app, tests, benchmarks, tools, fuzzers) in build-asan/ with
#                   clang and lld, AddressSanitizer + UBSan, at -O1 with libstdc++'s assertions and -Werror: the
#                   tests, the fuzzers and the benchmarks' smoke pass run on it. (The Release build, with GCC, is
#                   scripts/setup.sh's.)
#   5. web packages what scripts/build-web.sh needs (emscripten and chromium from Debian's archive, its development
#                   packages from npm), fetched while the native build compiles
#   6. tests        ctest --parallel (cores) --output-on-failure on it, every label (tests/CMakeLists.txt says
#                   what each means), leak detection on; any sanitizer report fails its test. Longest first, from
#                   tests/ctest_costs.txt (below). Among them the benchmarks' smoke pass (label bench: one pass of
#                   every benchmark, which proves it runs and times nothing) and the web package's build,
#                   Web.Build (scripts/build-web.sh into web/dist/), which the other tests labelled web need
#   7. tsan         ThreadSanitizer build in build-tsan/ of the tests labelled `threads` only (the thread
#                   hand-offs: the export's pipeline, the live session's ring, worker and frame queue), then those
#                   tests; any report fails them
#   8. fuzz         scripts/fuzz.sh on build-asan/'s fuzzers for FUZZ_SECONDS (default 60)
# Then a summary of the parts; the last line is "N passed, M failed", the ctest results of both runs together.
# Exits non-zero if any part failed.
#
# Environment: ASAN_BUILD_DIR (default build-asan), TSAN_BUILD_DIR (default build-tsan), FUZZ_SECONDS (default
# 60), CTEST_TIMEOUT_SECONDS (per test without its own TIMEOUT, default 900), TALKINGHEAD_DATA (shared data).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"

quick=0
case "${1:-}" in
  "") ;;
  --quick) quick=1 ;;
  *)
    echo "usage: bash scripts/test.sh [--quick]" >&2
    exit 2
    ;;
esac

if ((quick)); then
  build_dir="${BUILD_DIR:-build}"
  jobs="$(nproc 2>/dev/null || echo 2)"
  started=$SECONDS
  generator=(-G Ninja)
  if [[ -f "$build_dir/CMakeCache.txt" ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$build_dir/CMakeCache.txt"; then
    generator=()
  fi
  # The same configuration as scripts/setup.sh's, so the product it built is reused.
  cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DTALKINGHEAD_WERROR=OFF >/dev/null
  cmake --build "$build_dir" --parallel "$jobs" --target quick_tests
  built_seconds=$((SECONDS - started))
  status=0
  ctest --test-dir "$build_dir" --parallel "$jobs" --output-on-failure --no-tests=error -L unit -LE slow ||
    status=$?
  echo "quick tier: build ${built_seconds}s, tests $((SECONDS - started - built_seconds))s, total $((SECONDS - started))s"
  exit "$status"
fi
asan_dir="${ASAN_BUILD_DIR:-build-asan}"
tsan_dir="${TSAN_BUILD_DIR:-build-tsan}"
jobs="$(nproc 2>/dev/null || echo 2)"
ctest_timeout="${CTEST_TIMEOUT_SECONDS:-900}"
export FUZZ_SECONDS="${FUZZ_SECONDS:-60}"

logs="$(mktemp -d "${TMPDIR:-/tmp}/talkinghead-test.XXXXXX")"
trap 'rm -rf "$logs"' EXIT

summary=()        # one line per part
any_failed=0
tests_passed=0
tests_failed=0
started=$SECONDS

# configure DIR [cmake options...]: configures with Ninja, unless DIR already uses another generator.
configure() {
  local dir="$1"
  shift
  local generator=(-G Ninja)
  if [[ -f "$dir/CMakeCache.txt" ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; then
    generator=()
  fi
  cmake -S . -B "$dir" "${generator[@]}" "$@"
}

# run_ctest DIR [ctest options...]: the tests of DIR, as many at a time as there are cores; its output is kept in
# $logs/ctest-DIR.log for counting.
run_ctest() {
  local dir="$1"
  shift
  local log="$logs/ctest-$(basename "$dir").log"
  # A fresh build folder has no record of how long each test takes, so ctest would start them in the order they
  # are declared, and a long one declared late would run alone on one core at the end. tests/ctest_costs.txt is
  # a sanitized run's record in the format of CTest's own Testing/Temporary/CTestCostData.txt ("NAME RUNS
  # SECONDS" a line: each test's time in one fresh run of this script, from its log's "Passed ... sec" lines):
  # with it ctest starts the longest first. A test missing from it (a new one) starts after those in it.
  # The suites that measure time on the real clock run alone (SERIAL_SUITES in tests/), whatever the order.
  if [[ ! -f "$dir/Testing/Temporary/CTestCostData.txt" ]]; then
    mkdir -p "$dir/Testing/Temporary"
    cp tests/ctest_costs.txt "$dir/Testing/Temporary/CTestCostData.txt"
  fi
  ctest --test-dir "$dir" --parallel "$jobs" --output-on-failure --no-tests=error --timeout "$ctest_timeout" "$@" 2>&1 |
    tee "$log"
  return "${PIPESTATUS[0]}"
}

# count_ctest DIR: adds the "X% tests passed, F tests failed out of T" line of DIR's ctest log to the totals
# and describes it in $ctest_counts.
ctest_counts=""
count_ctest() {
  local log="$logs/ctest-$(basename "$1").log"
  local line failed total
  line="$(grep -E '[0-9]+ tests? failed out of [0-9]+' "$log" 2>/dev/null | tail -n 1 || true)"
  if [[ -z "$line" ]]; then
    ctest_counts="no ctest summary"
    return 0
  fi
  failed="$(sed -E 's/.* ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")"
  total="$(sed -E 's/.* ([0-9]+) tests? failed out of ([0-9]+).*/\2/' <<<"$line")"
  tests_passed=$((tests_passed + total - failed))
  tests_failed=$((tests_failed + failed))
  ctest_counts="$((total - failed)) passed, $failed failed"
}

# part NAME COMMAND...: runs COMMAND in a subshell with errexit, times it and records the outcome in the summary
# and in $part_status. Always returns 0: call it as a plain command, never under if/&&/|| (bash ignores
# errexit inside anything called from such a context, so a failing step would not stop the part).
part_status=0
part() {
  local name="$1"
  shift
  printf '\n==== %s: %s\n' "$name" "$*"
  local begin=$SECONDS
  set +e
  (
    set -euo pipefail
    "$@"
  )
  part_status=$?
  set -e
  local seconds=$((SECONDS - begin))
  if ((part_status == 0)); then
    summary+=("$(printf '  %-20s %-8s %5ss' "$name" ok "$seconds")")
  else
    summary+=("$(printf '  %-20s %-8s %5ss  (exit %s)' "$name" FAILED "$seconds" "$part_status")")
    any_failed=1
  fi
}

skip() {
  summary+=("$(printf '  %-20s %-8s         %s' "$1" skipped "$2")")
}

# Annotates the last summary line with the ctest counts of DIR.
annotate_counts() {
  count_ctest "$1"
  summary[-1]="${summary[-1]}  $ctest_counts"
}

# Every C++ source of the project formatted as .clang-format says (usage blocks in comments, indented, are left
# as written: its CommentPragmas).
check_format() {
  local files
  mapfile -t files < <(git ls-files '*.cpp' '*.h' 2>/dev/null || find engine app tests bench fuzz tools -name '*.cpp' -o -name '*.h')
  clang-format --dry-run --Werror "${files[@]}"
  echo "${#files[@]} files formatted"
}

# LLVM's linker: a sanitized test links in a third of GNU ld's time, and there are some eighty executables.
lld=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DCMAKE_SHARED_LINKER_FLAGS=-fuse-ld=lld)

# Clang: with the sanitizers it builds this code in two thirds of GCC's time. GCC builds the Release
# (scripts/setup.sh) and the ThreadSanitizer part below. A unity build: a target's files compiled sixteen to a
# translation unit, so the Eigen and standard library templates they share are instantiated, optimised and
# instrumented once per sixteen files instead of once per file (the few files whose file-local names clash are
# compiled alone: SKIP_UNITY_BUILD_INCLUSION in their folder's CMakeLists.txt). Sixteen against eight: the
# engine's animation, hmm, eval, outputs and face stages with what they use, 286 s against 325 s on two cores.
build_sanitized() {
  configure "$asan_dir" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
    -DTALKINGHEAD_SANITIZE=ON -DTALKINGHEAD_BENCHMARKS=ON -DTALKINGHEAD_FUZZ=ON "${lld[@]}" -DCMAKE_UNITY_BUILD=ON \
    -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 -DTALKINGHEAD_WEB_BUILD_TEST=ON \
    -DCMAKE_CXX_FLAGS_DEBUG="-g1 -O1 -D_GLIBCXX_ASSERTIONS" -DCMAKE_C_FLAGS_DEBUG="-g1 -O1"
  cmake --build "$asan_dir" --parallel "$jobs"
}

# Mesa's software rasteriser (llvmpipe: OSMesa and the live window under Xvfb) draws in the calling thread instead
# of starting a thread per core: tests run two at a time on two cores, and its threads only contend with the other
# test (the render-heavy tests took 123.7 s with them, 103.1 s without; the pictures are the same).
export LP_NUM_THREADS="${LP_NUM_THREADS:-0}"
# The sanitizer settings apply to everything after this point, including test discovery at build time.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# tests/tsan_suppressions.txt: false reports inside PulseAudio's client library (the file says why).
export TSAN_OPTIONS="${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1:suppressions=$repo/tests/tsan_suppressions.txt}"

part "packages" bash scripts/install-packages.sh

# The web package's packages (emscripten, chromium) and npm dependencies download while the native build
# compiles; the web packages part waits for them.
# (Each part runs in a subshell, which cannot `wait` for this shell's child: the job leaves its status in a file.)
(
  status=0
  bash scripts/build-web.sh --prepare > "$logs/web-prepare.log" 2>&1 || status=$?
  echo "$status" > "$logs/web-prepare.status"
) &
web_packages() {
  while [[ ! -f "$logs/web-prepare.status" ]]; do sleep 1; done
  cat "$logs/web-prepare.log"
  return "$(cat "$logs/web-prepare.status")"
}

part "node tools" bash scripts/install-node-tools.sh "$asan_dir"

part "format" check_format

part "build (asan+ubsan)" build_sanitized
built=$part_status

part "web packages" web_packages
if ((built == 0)); then
  part "asan+ubsan tests" run_ctest "$asan_dir"
  annotate_counts "$asan_dir"
else
  skip "asan+ubsan tests" "(build failed)"
fi

build_tsan() {
  configure "$tsan_dir" -DCMAKE_BUILD_TYPE=Debug -DTALKINGHEAD_TSAN=ON "${lld[@]}" -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
    -DCMAKE_C_FLAGS_DEBUG="-g -O1"
  cmake --build "$tsan_dir" --parallel "$jobs" --target slot_queue_test parallel_for_test live_session_test stream_close_test
}
part "tsan build" build_tsan
if ((part_status == 0)); then
  part "tsan tests" run_ctest "$tsan_dir" -L threads
  annotate_counts "$tsan_dir"
else
  skip "tsan tests" "(build failed)"
fi

# The fuzzer's own output is long (libFuzzer status lines, decoder chatter): it goes to a log in the build
# folder, and only its tail is shown (a longer tail when it fails, which holds the crash report).
run_fuzz() {
  local log="$asan_dir/fuzz.log"
  mkdir -p "$asan_dir"
  echo "full output: $log"
  if FUZZ_BUILD_DIR="$asan_dir" bash scripts/fuzz.sh >"$log" 2>&1; then
    tail -n 25 "$log"
  else
    local status=$?
    tail -n 200 "$log"
    return "$status"
  fi
}

if ((built == 0)); then
  part "fuzz (${FUZZ_SECONDS}s)" run_fuzz
else
  skip "fuzz" "(the build failed)"
fi

printf '\n==== Summary (%s)\n' "$(if ((any_failed)); then echo FAILED; else echo all parts ok; fi)"
printf '%s\n' "${summary[@]}"
printf '  %-20s %-8s %5ss\n' "total" "" "$((SECONDS - started))"
echo "$tests_passed passed, $tests_failed failed"
exit "$any_failed"
