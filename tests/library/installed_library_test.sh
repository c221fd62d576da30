#!/usr/bin/env bash
# The library as a user installs it: `cmake --install` of this build into a fresh prefix; the C and C++ examples
# built against the installed tree (find_package, and the C one also with pkg-config) and run on a recording; and
# the Python module's tests (pytest, a Dask LocalCluster of worker processes among them) importing the installed
# package. Run by ctest (tests/library/CMakeLists.txt):
#
#   installed_library_test.sh BUILD_DIR SOURCE_DIR C_COMPILER CXX_COMPILER SANITIZER_RUNTIME
#
# SANITIZER_RUNTIME: the AddressSanitizer runtime a sanitized build's library needs inside Python (preloaded), or
# empty.
set -euo pipefail
build="$1" source="$2" cc="$3" cxx="$4" runtime="${5:-}"
work="$(mktemp -d "${TMPDIR:-/tmp}/talkinghead-installed.XXXXXX")"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
speech="${TALKINGHEAD_DATA:-$source/../shared/data}/speech/arctic/arctic_a0001.wav"

echo "== cmake --install $build --prefix $prefix"
# A step's own output is shown only when it fails.
quietly() {
  local log="$work/step.log"
  "$@" > "$log" 2>&1 || { cat "$log"; return 1; }
}
quietly cmake --install "$build" --prefix "$prefix"
for file in include/talkinghead/talkinghead.h include/talkinghead/version.h lib/libtalkinghead.so lib/pkgconfig/talkinghead.pc \
  lib/cmake/talkinghead/talkingheadConfig.cmake share/talkinghead/models/visemes.json \
  share/talkinghead/models/articulation_live.json share/talkinghead/models/articulation.json \
  lib/python3/dist-packages/talkinghead/__init__.py; do
  [[ -e "$prefix/$file" ]] || { echo "not installed: $file"; exit 1; }
done
# Only the C API is exported.
if nm -D --defined-only "$prefix/lib/libtalkinghead.so" | awk '$2 == "T" && $3 !~ /^th_/' | grep -q .; then
  echo "libtalkinghead exports more than th_*:"
  nm -D --defined-only "$prefix/lib/libtalkinghead.so" | awk '$2 == "T" && $3 !~ /^th_/' | head
  exit 1
fi

# The models are the installed ones: the build's source tree is not where they are looked for.
export TALKINGHEAD_MODELS="$prefix/share/talkinghead/models"
# A sanitized library reports leaks of the interpreter's own; the sanitizer still stops on any error.
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"

echo "== the examples, with find_package(talkinghead)"
quietly cmake -S "$source/examples" -B "$work/examples" -G Ninja -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix"
quietly cmake --build "$work/examples"
"$work/examples/stream" "$speech"
"$work/examples/animate" "$speech" "$work/cues.tsv" "$work/faps.csv"
head -n 3 "$work/cues.tsv"
[[ "$(head -n 1 "$work/cues.tsv")" == $'0.00\tX' ]]

echo "== the C example with pkg-config"
# shellcheck disable=SC2046 # pkg-config's words are separate arguments
"$cc" "$source/examples/stream.c" $(PKG_CONFIG_PATH="$prefix/lib/pkgconfig" pkg-config --cflags --libs talkinghead) \
  -o "$work/stream_pc"
LD_LIBRARY_PATH="$prefix/lib" "$work/stream_pc" "$speech" | tail -n 1

echo "== the Python module (pytest), installed"
cd "$work"
LD_PRELOAD="$runtime" PYTHONPATH="$prefix/lib/python3/dist-packages" \
  /usr/bin/python3 -m pytest -q -p no:cacheprovider "$source/tests/python"
