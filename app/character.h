// The user's character as the commands that take --avatar load it (export, render, animate): read and rigged
// before any work, its morph scheme and what it lacks said once on stderr ("brunette-t: ARKit blendshapes").
//
//   const std::optional<th::avatar::Avatar> character = loadCharacter(arguments.avatar);   // "": none
//
// Errors (th::Error) name the file. Thread contract: none (the CLI's main thread).
#pragma once

#include <optional>
#include <string>

#include "avatar/avatar_model.h"

namespace th::app {

std::optional<avatar::Avatar> loadCharacter(const std::string& path);

}  // namespace th::app
