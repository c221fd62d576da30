#!/usr/bin/env bash
# Puts the third-party face assets into assets/ (git-ignored; never committed):
#   assets/ict-facekit/   ICT FaceKit neutral head, its jawOpen/mouthClose/mouthFunnel/mouthPucker shapes, the
#                         landmark indices and the material file (MIT licence, LICENSE copied alongside)
#   assets/candide3/      Candide-3 v3.1.6 (J. Ahlberg, research use with attribution)
# From the shared data folder when it is there ($TALKINGHEAD_DATA, default ../shared/data beside the checkout),
# else downloaded from their public upstream at pinned commits, each file checked by size.
#
#   bash scripts/fetch-assets.sh          (scripts/setup.sh runs it)
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data_dir="$(realpath -m "${TALKINGHEAD_DATA:-$repo/../shared/data}")"
assets="$repo/assets"
mkdir -p "$assets/ict-facekit" "$assets/candide3"

ict_files=(generic_neutral_mesh.obj jawOpen.obj mouthClose.obj mouthFunnel.obj mouthPucker.obj vertex_indices.json
           ICTFaceModelMaterial.mtl LICENSE)
if [[ -d "$data_dir/face/ict-facekit" && -d "$data_dir/face/candide3" ]]; then
  for file in "${ict_files[@]}" README.md; do
    cp "$data_dir/face/ict-facekit/$file" "$assets/ict-facekit/"
  done
  cp "$data_dir/face/candide3/candide3_v3.1.6.wfm" "$data_dir/face/candide3/README.md" "$assets/candide3/"
  echo "face assets: copied from $data_dir/face into $assets"
  exit 0
fi

# No shared data: fetch from upstream. Sizes are those of the pinned commits.
ict_base="https://raw.githubusercontent.com/ICT-VGL/ICT-FaceKit/da5f95a607f5e6b37755b38d3385d7f2853732e5"
candide_url="https://raw.githubusercontent.com/KenjiCpp/facial-tracker/f871f72cd0f36827e5829c2d248e2740693fb598/resources/candide3.wfm"
fetch() {  # fetch URL TARGET [EXPECTED_SIZE]
  local url="$1" target="$2" size="${3:-}"
  if ! curl -fsSL --retry 3 -o "$target.part" "$url"; then
    rm -f "$target.part"
    echo "error: could not download $url (no network? put the shared data at $data_dir instead)" >&2
    exit 1
  fi
  if [[ -n "$size" && "$(stat -c %s "$target.part")" != "$size" ]]; then
    echo "error: $url has $(stat -c %s "$target.part") bytes, expected $size" >&2
    rm -f "$target.part"
    exit 1
  fi
  mv "$target.part" "$target"
}
fetch "$ict_base/FaceXModel/generic_neutral_mesh.obj" "$assets/ict-facekit/generic_neutral_mesh.obj" 2555599
for shape in jawOpen mouthClose mouthFunnel mouthPucker; do
  fetch "$ict_base/FaceXModel/$shape.obj" "$assets/ict-facekit/$shape.obj"
done
fetch "$ict_base/FaceXModel/vertex_indices.json" "$assets/ict-facekit/vertex_indices.json"
fetch "$ict_base/FaceXModel/ICTFaceModelMaterial.mtl" "$assets/ict-facekit/ICTFaceModelMaterial.mtl"
fetch "$ict_base/LICENSE" "$assets/ict-facekit/LICENSE"
fetch "$candide_url" "$assets/candide3/candide3_v3.1.6.wfm" 26116
echo "face assets: downloaded into $assets"
