// The test avatars (../shared/data/face/avatars), read once; and test characters made from them by editing a
// GLB's JSON (its binary chunk kept): VRM files from a plain glTF one, targets hidden from the schemes found by
// name.
//
//   const th::avatar::Avatar& character = th::test::brunette();
//   th::test::rewriteGlb(avatarFile("brunette-t.glb"), folder / "brunette.vrm", [](nlohmann::json& json) { ... });
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "avatar/avatar_model.h"
#include "core/data_path.h"

namespace th::test {

inline std::filesystem::path avatarFile(const std::string& name) {
  return th::sharedDataPath("face/avatars") / name;
}

inline const th::avatar::Avatar& brunette() {
  static const th::avatar::Avatar avatar = th::avatar::loadAvatar(avatarFile("brunette-t.glb"));
  return avatar;
}

inline const th::avatar::Avatar& vroid() {
  static const th::avatar::Avatar avatar = th::avatar::loadAvatar(avatarFile("vroid.glb"));
  return avatar;
}

// A GLB's JSON, changed by `edit`, written back with the same binary chunk.
inline void rewriteGlb(const std::filesystem::path& from, const std::filesystem::path& to,
                       const std::function<void(nlohmann::json&)>& edit) {
  std::ifstream in(from, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::uint32_t jsonLength = 0;
  std::memcpy(&jsonLength, bytes.data() + 12, 4);
  nlohmann::json json = nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + jsonLength);
  edit(json);
  std::string text = json.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  const std::vector<char> rest(bytes.begin() + 20 + jsonLength, bytes.end());
  std::ofstream out(to, std::ios::binary);
  const auto u32 = [&](std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
  u32(0x46546C67);
  u32(2);
  u32(static_cast<std::uint32_t>(12 + 8 + text.size() + rest.size()));
  u32(static_cast<std::uint32_t>(text.size()));
  u32(0x4E4F534A);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.write(rest.data(), static_cast<std::streamsize>(rest.size()));
}

inline int nodeNamed(const nlohmann::json& json, const std::string& name) {
  for (std::size_t n = 0; n < json["nodes"].size(); ++n)
    if (json["nodes"][n].value("name", "") == name) return static_cast<int>(n);
  return -1;
}

// The character's face mesh's targets renamed so that no scheme but VRM's expressions finds them.
inline void hideArkitAndVisemeNames(nlohmann::json& json) {
  for (nlohmann::json& mesh : json["meshes"])
    if (mesh.contains("extras") && mesh["extras"].contains("targetNames"))
      for (nlohmann::json& name : mesh["extras"]["targetNames"]) name = "x_" + name.get<std::string>();
}

inline int targetOf(const nlohmann::json& json, int mesh, const std::string& name) {
  const nlohmann::json& names = json["meshes"][static_cast<std::size_t>(mesh)]["extras"]["targetNames"];
  for (std::size_t t = 0; t < names.size(); ++t)
    if (names[t] == name || names[t] == "x_" + name) return static_cast<int>(t);
  return -1;
}

}  // namespace th::test
