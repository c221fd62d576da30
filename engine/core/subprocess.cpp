#include "core/subprocess.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <memory>

#include "core/error.h"

namespace th {

std::string shellQuote(const std::string& argument) {
  std::string quoted = "'";
  for (char c : argument) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

std::string runProgram(const std::vector<std::string>& argv, const std::string& stdinPath) {
  std::string command;
  for (const auto& argument : argv) command += (command.empty() ? "" : " ") + shellQuote(argument);
  command += stdinPath.empty() ? " </dev/null" : " <" + shellQuote(stdinPath);
  command += " 2>/dev/null";
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw Error(argv.front() + ": cannot start");
  std::string output;
  std::array<char, 65536> buffer{};
  size_t got = 0;
  while ((got = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) output.append(buffer.data(), got);
  const int status = ::pclose(pipe);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error(argv.front() + ": failed (exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                ") running: " + command);
  }
  return output;
}

bool programExists(const std::string& name) {
  const std::string command = "command -v " + shellQuote(name) + " >/dev/null 2>&1";
  return std::system(command.c_str()) == 0;
}

}  // namespace th
