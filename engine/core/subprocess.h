// Running another program (the peer pitch trackers) and capturing what it prints.
//
//   std::string out = th::runProgram({"praat", "--run", script, wav});
//
// Arguments are single-quoted for the shell, so file names with spaces are safe. Throws th::Error naming
// the program when it cannot be run or exits non-zero. Thread contract: any thread.
#pragma once

#include <string>
#include <vector>

namespace th {

std::string shellQuote(const std::string& argument);
std::string runProgram(const std::vector<std::string>& argv, const std::string& stdinPath = {});
bool programExists(const std::string& name);

}  // namespace th
