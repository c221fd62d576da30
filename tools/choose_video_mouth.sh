#!/usr/bin/env bash
# Chooses the defaults of `talkinghead train --video` on training clips only: the clips `train --video DIR`
# trains on (all but every 5th by name) are split again, every 4th of them held out for validation, and each
# configuration is trained on the rest and scored there. The held-out clips of the real run are never seen.
#   tools/choose_video_mouth.sh [DIR] [TRACKS]     (defaults: ../shared/data/grid/s1, /tmp/choose_video_mouth/tracks)
# Prints one line per configuration: N M K tc, then the validation eps / rho of the inversion (jaw, all FAPs).
# The defaults are the configuration with the lowest eps over all FAPs (ties: fewer states).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
dir=$(realpath "${1:-$repo/../shared/data/grid/s1}")
work=/tmp/choose_video_mouth
tracks=${2:-$work/tracks}
mkdir -p "$work/clips" "$tracks"
rm -f "$work/clips"/*
i=0
for clip in $(ls "$dir" | grep -Ei '\.(mpg|mpeg|mp4|m4v|avi|mov|mkv|webm)$' | sort); do
  i=$((i + 1))
  ((i % 5 == 0)) && continue            # the real run's held-out clips
  ln -s "$dir/$clip" "$work/clips/$clip"
done
for context in 2 3; do
  for states in 4 6 8 12; do
    for mixtures in 1 2; do
      for components in 2 3 4; do
        line=$( ("$repo/build/talkinghead" train --video "$work/clips" -o "$work/model.json" --tracks "$tracks" \
          --hold-out 4 --states $states --mixtures $mixtures --components $components --context $context 2>/dev/null || true) |
          grep 'this model, inversion (conditional-mean start)' || echo "start) failed (a model that did not train)")
        echo "$states $mixtures $components $context ${line#*start)}"
      done
    done
  done
done
