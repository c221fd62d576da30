// Running the built `talkinghead` executable as a child process, as a user meets it, and checking how it fails.
//
//   th::test::CliResult result = th::test::runCli({"animate", "in.wav", "-o", "out.csv"}, logFolder);
//   th::test::expectOneLineFailure(result, "in.wav", "no such file");
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace th::test {

struct CliResult {
  bool exited = false;  // false: killed by a signal (a crash)
  int exitCode = -1;
  int signal = 0;
  std::string out;
  std::string err;
};

std::string readText(const std::filesystem::path& path);

// Runs the CLI with `arguments`, stdout and stderr captured in files under `logFolder`. With `asUser`, the
// child drops to that user id first (root ignores permission bits, so a read-only folder needs a plain user).
CliResult runCli(const std::vector<std::string>& arguments, const std::filesystem::path& logFolder,
                 std::optional<uid_t> asUser = std::nullopt);

// A failure as the CLI must report it: a normal non-zero exit (not a signal, not exec trouble), and stderr
// exactly one line that names `path` and contains `reason`.
void expectOneLineFailure(const CliResult& result, const std::string& path, const std::string& reason);

}  // namespace th::test
