// The user's character for the commands that draw one (`--avatar FILE` on live, show, render, export,
// sidebyside and animate): the option, and the file read and rigged before any work starts, so that a bad
// file is one line and no output.
//
//   std::string path;
//   th::app::addAvatarOption(command, path);
//   const std::optional<th::avatar::Avatar> character = th::app::loadCharacter(path);   // nullopt: our face
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "avatar/avatar_model.h"

namespace th::app {

// Reads and rigs the character (throws th::Error naming the file if it cannot be read or nothing in it can be
// driven); says on stderr what drives it and what it lacks. An empty path: none.
std::optional<avatar::Avatar> loadCharacter(const std::string& path);

void addAvatarOption(CLI::App& command, std::string& path);

}  // namespace th::app
