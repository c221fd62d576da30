#!/usr/bin/env bash
# Builds the engine's speech -> animation path as WebAssembly (web/CMakeLists.txt) with Debian's emscripten, and
# puts the module in web/dist/:
#
#   bash scripts/build-web.sh            # -> web/dist/talkinghead_core.{js,wasm}; build folder build-web/
#
# Installs what it needs first (scripts/web-packages.txt; idempotent, as scripts/install-packages.sh). The module
# is an ES module factory: `createTalkingheadCore({wasmBinary})` in Node (whose fetch cannot read a file path),
# `createTalkingheadCore()` in a page, next to its .wasm. Models are read from its file system's /models/.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
build="${TALKINGHEAD_WEB_BUILD:-$repo/build-web}"

bash "$here/install-packages.sh" "$here/web-packages.txt"
# emscripten's optimizer imports acorn, which Debian installs for its own Node under /usr/share/nodejs.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"

if [[ ! -f "$build/build.ninja" ]]; then
  mkdir -p "$build"
  emcmake cmake -S "$repo/web" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release > "$build/configure.log" 2>&1 || {
    cat "$build/configure.log" >&2
    exit 1
  }
fi
ninja -C "$build"
mkdir -p "$repo/web/dist"
cp "$build/talkinghead_core.js" "$build/talkinghead_core.wasm" "$repo/web/dist/"
echo "build-web: web/dist/talkinghead_core.js and .wasm ($(stat -c %s "$repo/web/dist/talkinghead_core.wasm") bytes)"
