#!/usr/bin/env bash
# First command for a newcomer on a fresh Debian 12 machine:
#
#   bash scripts/setup.sh
#
# 1. installs the Debian packages in scripts/packages.txt (scripts/install-packages.sh; needs root or sudo),
# 2. puts the face assets (ICT FaceKit, Candide-3) into the git-ignored assets/ (scripts/fetch-assets.sh: copied
#    from the shared data, or downloaded from upstream where that is absent),
# 3. configures the Release build in build/ with Ninja and builds the product in it, on all cores: the CLI, the
#    library and the Python module (the tests, benchmarks and tools build when scripts/test.sh runs, or with
#    `cmake --build build`),
# 4. runs the main job on the shipped default input: the recording spoken by the face, with the shipped models,
#    rendered off-screen and written as build/demo.mp4 (plus its animation curves, build/demo_animation.csv):
#      build/talkinghead export "$DATA/beat2/2_scott_0_1_1.wav" -o build/demo.mp4
#    where DATA is $TALKINGHEAD_DATA, else ../shared/data beside the checkout. Without that recording it says so
#    and uses a sentence synthesised with espeak-ng instead (build/example.wav).
#
# Environment: BUILD_DIR (default build), TALKINGHEAD_DATA (the shared data folder).
# Besides assets/, nothing is written into the source tree; everything it makes lives in the build folder.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo"
build_dir="${BUILD_DIR:-build}"
data_dir="${TALKINGHEAD_DATA:-$repo/../shared/data}"
data_dir="$(realpath -m "$data_dir")"
jobs="$(nproc 2>/dev/null || echo 2)"

step() { printf '\n== %s\n' "$*"; }

step "Installing Debian packages (scripts/packages.txt)"
bash scripts/install-packages.sh

step "Face assets (scripts/fetch-assets.sh)"
bash scripts/fetch-assets.sh

step "Configuring Release in $build_dir/ and building the product (Ninja, $jobs jobs)"
generator=(-G Ninja)
if [[ -f "$build_dir/CMakeCache.txt" ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$build_dir/CMakeCache.txt"; then
  echo "note: $build_dir/ was configured with another generator; keeping it (remove $build_dir/ to switch to Ninja)"
  generator=()
fi
# Warnings do not stop a user's build: the tests' build (scripts/test.sh, CI) treats every one as an error.
cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DTALKINGHEAD_WERROR=OFF
cmake --build "$build_dir" --parallel "$jobs" --target talkinghead talkinghead_library talkinghead_python

step "Running the main job: the default recording spoken by the face, as an MP4 (talkinghead export)"
input="$data_dir/beat2/2_scott_0_1_1.wav"
if [[ -r "$input" ]]; then
  echo "input: $input"
else
  echo "The shared recording $input is not there"
  echo "(set TALKINGHEAD_DATA to the shared data folder, or put it at ../shared/data beside the checkout)."
  input="$build_dir/example.wav"
  if command -v espeak-ng >/dev/null 2>&1; then
    echo "Using a sentence synthesised with espeak-ng instead: $input"
    espeak-ng -v en-us -s 150 -w "$input" \
      "The quick brown fox jumps over the lazy dog. A talking head moves its lips, jaw and head with the voice."
  else
    echo "error: espeak-ng is not installed either, so there is no recording to run on" >&2
    exit 1
  fi
fi
output="$build_dir/demo.mp4"
"$build_dir/talkinghead" export "$input" -o "$output" --save-anim "$build_dir/demo_animation.csv"

cat <<EOF

Done: $output (1280x720, H.264 + AAC) and its animation curves, $build_dir/demo_animation.csv. Next:
  the face in a window:           $build_dir/talkinghead show
  speech features as CSV:         $build_dir/talkinghead features "$input" -o features.csv
  the other subcommands:          $build_dir/talkinghead --help
  all tests:                      bash scripts/test.sh
  the tests, benchmarks and tools in $build_dir/ too:  cmake --build $build_dir
  speed, on one core:             bash scripts/bench.sh
EOF
