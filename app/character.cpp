#include "character.h"

#include <iostream>

#include "avatar/avatar_pose.h"

namespace th::app {

std::optional<avatar::Avatar> loadCharacter(const std::string& path) {
  if (path.empty()) return std::nullopt;
  avatar::Avatar character = avatar::loadAvatar(path);
  const avatar::AvatarRig rig = avatar::rigAvatar(character);
  std::cerr << character.name << ": " << avatar::schemeName(rig.scheme);
  for (const std::string& missing : rig.missing) std::cerr << "; " << missing;
  std::cerr << '\n';
  return character;
}

void addAvatarOption(CLI::App& command, std::string& path) {
  command.add_option("--avatar", path,
                     "A character (.glb, .gltf, .vrm) to speak instead of our face: its ARKit, Oculus viseme or VRM "
                     "morph targets, its neck, head and eye bones");
}

}  // namespace th::app
