#!/usr/bin/env bash
# Builds the engine's speech -> animation path as WebAssembly (web/CMakeLists.txt) with Debian's emscripten, and
# puts the module in web/dist/:
#
#   bash scripts/build-web.sh            # -> web/dist/ (the core, its .wasm, the models); build folder build-web/
#   bash scripts/build-web.sh --prepare  # only what it installs (no compiler at work: scripts/test.sh runs this
#                                        # during the native build)
#
# Installs what it needs first (scripts/web-packages.txt; idempotent, as scripts/install-packages.sh). The module
# is an ES module factory: `createTalkingheadCore({wasmBinary})` in Node (whose fetch cannot read a file path),
# `createTalkingheadCore()` in a page, next to its .wasm. Models are read from its file system's /models/.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
build="${TALKINGHEAD_WEB_BUILD:-$repo/build-web}"

prepare_only=0
case "${1:-}" in
  "") ;;
  --prepare) prepare_only=1 ;;
  *)
    echo "usage: bash scripts/build-web.sh [--prepare]" >&2
    exit 2
    ;;
esac

bash "$here/install-packages.sh" "$here/web-packages.txt"
# The package's development dependencies (web/package-lock.json: three for the example page, puppeteer-core for
# the browser test, TalkingHead for its recipe), from the npm registry; no browser is downloaded (the tests use
# Debian's chromium). Skipped when web/node_modules matches the lock file.
if ! cmp -s "$repo/web/package-lock.json" "$repo/web/node_modules/.package-lock.json.installed" 2>/dev/null; then
  (cd "$repo/web" && npm ci --no-audit --no-fund --loglevel=error)
  cp "$repo/web/package-lock.json" "$repo/web/node_modules/.package-lock.json.installed"
fi
if ((prepare_only)); then
  echo "build-web: the packages and web/node_modules are in place"
  exit 0
fi
# emscripten's optimizer imports acorn, which Debian installs for its own Node under /usr/share/nodejs.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"

if [[ ! -f "$build/build.ninja" ]]; then
  mkdir -p "$build"
  emcmake cmake -S "$repo/web" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release > "$build/configure.log" 2>&1 || {
    cat "$build/configure.log" >&2
    exit 1
  }
fi
cmake --build "$build"
mkdir -p "$repo/web/dist/models"
cp "$build/talkinghead_core.js" "$build/talkinghead_core.wasm" "$repo/web/dist/"
# The models the package carries: the live presets default and low-latency (the accurate preset's and animate
# --online's offline models would take the package past 5 MB; a page fetches them from elsewhere: docs/web.md).
for model in head.json visemes.json mouth_live.json articulation_live.json mouth_instant.json \
  articulation_instant.json; do
  cp "$repo/models/$model" "$repo/web/dist/models/"
done
echo "build-web: web/dist/talkinghead_core.js and .wasm ($(stat -c %s "$repo/web/dist/talkinghead_core.wasm") bytes), \
$(ls "$repo/web/dist/models" | wc -l) models"
