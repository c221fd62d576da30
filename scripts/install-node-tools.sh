#!/usr/bin/env bash
# Installs the npm packages the tests and evaluation tools run into a build folder (not into the source tree, not
# system-wide):
#
#   bash scripts/install-node-tools.sh build-asan      # -> build-asan/node/node_modules/{gltf-validator,@met4citizen/headaudio}
#
# gltf-validator is the Khronos glTF validator (a library; tools/gltf_validate.js runs it), used by
# tests/formats/gltf_crosscheck_test, which finds it in BUILD/node/node_modules. @met4citizen/headaudio is the
# browser lip-sync peer HeadAudio (an AudioWorklet; tools/headaudio_visemes.mjs runs it under Node). The versions
# are pinned so that reports compare across runs. Idempotent: when those versions are there it touches nothing (no
# network). Both are installed by one npm command, since `npm install --no-save` prunes packages it was not given.
# Needs node and npm (scripts/packages.txt: nodejs, npm).
set -euo pipefail

build_dir="${1:?usage: install-node-tools.sh BUILD_DIR}"
prefix="$build_dir/node"
validator_version="2.0.0-dev.3.10"
headaudio_version="0.1.0"

# installed_version PACKAGE: the version of BUILD/node/node_modules/PACKAGE, empty when it is not there.
installed_version() {
  node -e 'try { console.log(require(process.argv[1]).version) } catch (e) {}' \
    "$(realpath -m "$prefix/node_modules/$1/package.json")" 2>/dev/null || true
}

all_installed() {
  [[ "$(installed_version gltf-validator)" == "$validator_version" &&
     "$(installed_version @met4citizen/headaudio)" == "$headaudio_version" ]]
}

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "install-node-tools: node and npm are needed (scripts/install-packages.sh installs nodejs and npm)" >&2
  exit 1
fi
if all_installed; then
  echo "install-node-tools: gltf-validator $validator_version is in $prefix"
  echo "install-node-tools: @met4citizen/headaudio $headaudio_version is in $prefix"
  exit 0
fi
mkdir -p "$prefix"
npm install --prefix "$prefix" --no-audit --no-fund --no-save \
  "gltf-validator@$validator_version" "@met4citizen/headaudio@$headaudio_version"
if [[ "$(installed_version gltf-validator)" != "$validator_version" ]]; then
  echo "install-node-tools: gltf-validator $validator_version is not in $prefix after npm install" >&2
  exit 1
fi
if [[ "$(installed_version @met4citizen/headaudio)" != "$headaudio_version" ]]; then
  echo "install-node-tools: @met4citizen/headaudio $headaudio_version is not in $prefix after npm install" >&2
  exit 1
fi
echo "install-node-tools: installed gltf-validator $validator_version into $prefix"
echo "install-node-tools: installed @met4citizen/headaudio $headaudio_version into $prefix"
