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

}  // namespace th::app
