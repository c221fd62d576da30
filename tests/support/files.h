// File helpers shared by the test suites: a folder's entries, a file's bytes, and the check that an error
// message is the project's one-line "PATH: what is wrong".
//
//   EXPECT_EQ(th::test::listFolder(folder.path()), std::vector<std::string>{});   // nothing left behind
//   th::test::expectFileError(message, path, "does not exist");
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace th::test {

// The names of the entries of `folder`, sorted.
std::vector<std::string> listFolder(const std::filesystem::path& folder);

// The whole file as bytes ("" if it cannot be read).
std::string readText(const std::filesystem::path& path);

// One line that starts with "PATH: " and contains `problem` (gtest expectations).
void expectFileError(const std::string& message, const std::filesystem::path& path, const std::string& problem);

}  // namespace th::test
