#!/usr/bin/env bash
# The md5 of every output a refactoring must leave unchanged, written by one talkinghead binary:
#
#   tools/output_fingerprints.sh BINARY OUT_FOLDER > fingerprints.txt
#
# Build two commits (e.g. main and a worktree of the commit before a change) and diff their lists:
#   tools/output_fingerprints.sh build/talkinghead /tmp/after > after.txt
#   tools/output_fingerprints.sh /tmp/base/build/talkinghead /tmp/before > before.txt
#   diff before.txt after.txt
# It writes, from the shared data (TALKINGHEAD_DATA, default ../shared/data): `animate` of a minute of BEAT2
# speech as CSV, JSON and .fap and with the posterior head; `export` of an ARCTIC prompt at 320x240 with its
# track, and at 64x48 and 5 fps; `features`; `render` frames; `strip`; `live --headless --dump`. A command that
# fails is reported and its files are missing from the list, so the diff shows it. Also: `live --headless` with
# other decoder options (under their first names, which every build takes), `animate --online`, visemes, and the
# Ready Player Me test character exported and written as a glTF animation. What a character receives live: the
# datagrams `live --headless` sends to VMC (perfect-sync names), VRChat (with binary parameters) and plain OSC.
# And the library's stream: every field of every frame libtalkinghead (BINARY's folder's capi/) gives for the
# prompt pushed in 10 ms blocks, with and without waiting for the head (tools/fingerprints/library_frames.c,
# compiled here against that library).
set -uo pipefail

if (($# != 2)); then
  echo "usage: tools/output_fingerprints.sh BINARY OUT_FOLDER" >&2
  exit 2
fi
binary="$(realpath "$1")"
out="$2"
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export TALKINGHEAD_DATA="${TALKINGHEAD_DATA:-$repo/../shared/data}"  # also for a binary built elsewhere (a worktree)
data="$TALKINGHEAD_DATA"
speech="$data/beat2/2_scott_0_1_1.wav"
prompt="$(find "$data" -name arctic_a0001.wav -print -quit 2>/dev/null)"
avatar="$data/face/avatars/brunette-t.glb"
for input in "$speech" "$prompt"; do
  [[ -f "$input" ]] || { echo "output_fingerprints: $input: not found (TALKINGHEAD_DATA)" >&2; exit 1; }
done

rm -rf "$out"
mkdir -p "$out"
cd "$out"
run() {
  "$binary" "$@" > /dev/null 2>&1 || echo "output_fingerprints: failed: talkinghead $*" >&2
}
run animate "$speech" -o speech.csv
run animate "$speech" -o speech.json
run animate "$speech" -o speech.fap
run animate "$speech" --head posterior -o posterior.fap
run export "$prompt" -o prompt.mp4 --size 320x240 --save-anim prompt.csv
run export "$prompt" -o small.mp4 --size 64x48 --fps 5
run features "$prompt" -o features.csv
run render prompt.csv -o frames --size 160x120 --fps 5
run strip prompt.csv -o strip.png --from 0.5
run live --headless --input "$prompt" --speed 8 --dump live.csv
run live --headless --input "$prompt" --speed 8 --lag 4 --window 2 --wait-for-head --dump live_options.csv
run animate "$speech" --online -o online.csv
run animate "$prompt" -o prompt_visemes.csv --format oculus
if [[ -f "$avatar" ]]; then
  run export "$prompt" -o avatar.mp4 --size 160x120 --fps 10 --avatar "$avatar"
  run animate "$prompt" -o avatar_animation.gltf --avatar "$avatar" --animation-only
fi

# The live outputs, caught on local ports (any that are free).
ports=($(/usr/bin/python3 -c 'import socket
socks = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(3)]
for s in socks: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))'))
ready="$(mktemp -u)"
/usr/bin/python3 "$repo/tools/fingerprints/udp_capture.py" "$ready" "${ports[0]}:live_vmc.hex" \
  "${ports[1]}:live_vrchat.hex" "${ports[2]}:live_osc.hex" &
capture=$!
for _ in $(seq 100); do [[ -e "$ready" ]] && break; sleep 0.05; done
rm -f "$ready"
run live --headless --input "$prompt" --speed 4 --vmc "127.0.0.1:${ports[0]}" --vmc-names perfect-sync \
  --vrchat "127.0.0.1:${ports[1]}" --vrchat-bits 4 --osc "127.0.0.1:${ports[2]}"
wait "$capture"

# The library's stream.
library="$(dirname "$binary")/capi"
scratch="$(mktemp -d)"
# It calls only what 0.2 has, for any build to compile it; a newer header marks some of that deprecated.
if cc -std=c11 -O1 -Wno-deprecated-declarations -I "$repo/include" -I "$library/include" \
    "$repo/tools/fingerprints/library_frames.c" "$library/libtalkinghead.so" -Wl,-rpath,"$library" -lsndfile \
    -o "$scratch/library_frames"; then
  "$scratch/library_frames" "$prompt" 0 > library_stream.txt || echo "output_fingerprints: failed: library stream" >&2
  "$scratch/library_frames" "$prompt" 1 > library_stream_head.txt ||
    echo "output_fingerprints: failed: library stream (waiting for the head)" >&2
else
  echo "output_fingerprints: failed: compiling library_frames.c against $library" >&2
fi
rm -rf "$scratch"
find . -type f | sort | xargs md5sum
