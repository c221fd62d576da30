// Shared by the glTF tests: speech-like tracks for an avatar (a weight wave on every mesh with morph targets,
// jawOpen opening and closing where the mesh has it, and a yaw on Head) and readers for the files.
#pragma once

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "formats/gltf_animation.h"

namespace th::formats::test {

// A written file through tinygltf, as other programs will read it.
inline tinygltf::Model loadGltf(const std::filesystem::path& path) {
  tinygltf::TinyGLTF loader;
  // The pixels are not looked at: keep tinygltf from decoding the textures.
  loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                           void*) { return true; },
                        nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const bool binary = path.extension() != ".gltf";
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, path.string())
                         : loader.LoadASCIIFromFile(&model, &error, &warning, path.string());
  if (!ok) throw std::runtime_error(path.string() + ": tinygltf: " + error);
  return model;
}

// An avatar's JSON chunk as is (tinygltf cannot read vroid.glb, which is meshopt-compressed).
inline nlohmann::json glbJson(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  std::string bytes(static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0)), '\0');
  in.seekg(0);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0) throw std::runtime_error(path.string() + ": not a GLB");
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return nlohmann::json::parse(bytes.substr(20, length));
}

inline std::size_t countOf(const nlohmann::json& json, const char* key) {
  return json.contains(key) ? json[key].size() : 0;
}

// Head's rest rotation turned by a yaw that swings ±0.3 rad; every other frame given as -q (the same rotation),
// which the writer must bring to one hemisphere.
inline GltfAnimationTracks speechTracks(const GltfAvatar& avatar, int frames = 60) {
  GltfAnimationTracks tracks;
  tracks.framesPerSecond = 30.0;
  for (const int node : avatar.morphNodes()) {
    const int targets = avatar.nodes[node].targetCount;
    Eigen::MatrixXf weights(targets, frames);
    for (int t = 0; t < frames; ++t)
      for (int k = 0; k < targets; ++k)
        weights(k, t) = 0.05f * (1.0f + std::sin(0.2f * static_cast<float>(t) + 0.1f * static_cast<float>(k)));
    const int jaw = avatar.targetIndex(node, "jawOpen");
    if (jaw >= 0)
      for (int t = 0; t < frames; ++t)
        weights(jaw, t) = 1.0f - std::abs(2.0f * static_cast<float>(t) / static_cast<float>(frames - 1) - 1.0f);
    tracks.morphs.push_back({node, weights});
  }
  const int head = avatar.findNode("Head");
  if (head >= 0) {
    GltfRotationTrack rotation{head, {}};
    for (int t = 0; t < frames; ++t) {
      const float yaw = 0.3f * std::sin(2.0f * static_cast<float>(M_PI) * static_cast<float>(t) / 30.0f);
      Eigen::Quaternionf q =
          avatar.nodes[head].rotation * Eigen::Quaternionf(Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitY()));
      if (t % 2 == 1) q.coeffs() = -q.coeffs();
      rotation.rotations.push_back(q);
    }
    tracks.rotations.push_back(rotation);
  }
  return tracks;
}

}  // namespace th::formats::test
