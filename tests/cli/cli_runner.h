// Running the built `talkinghead` executable as a child process, as a user meets it, and checking how it fails.
//
//   th::test::CliResult result = th::test::runCli({"animate", "in.wav", "-o", "out.csv"}, logFolder);
//   th::test::expectOneLineFailure(result, "in.wav", "no such file");
#pragma once

#include <gtest/gtest.h>
#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/temporary_file.h"
#include "support/files.h"  // readText, listFolder, expectFileError

namespace th::test {

struct CliResult {
  bool exited = false;  // false: killed by a signal (a crash)
  int exitCode = -1;
  int signal = 0;
  std::string out;
  std::string err;
};

// Runs the CLI with `arguments`, stdout and stderr captured in files under `logFolder`. With `asUser`, the
// child drops to that user id first (root ignores permission bits, so a read-only folder needs a plain user).
CliResult runCli(const std::vector<std::string>& arguments, const std::filesystem::path& logFolder,
                 std::optional<uid_t> asUser = std::nullopt);

// The same, with SIGINT (Ctrl-C) sent as soon as `when` returns true (polled every 50 ms, for at most a minute).
CliResult runCliInterrupted(const std::vector<std::string>& arguments, const std::filesystem::path& logFolder,
                            const std::function<bool()>& when);

// A failure as the CLI must report it: a normal non-zero exit (not a signal, not exec trouble), and stderr
// exactly one line that names `path` and contains `reason`.
void expectOneLineFailure(const CliResult& result, const std::string& path, const std::string& reason);

// A test with its own temporary folder: logs/ for the CLI's output, out/ for what it writes.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override;
  std::filesystem::path logs() const { return folder_.path() / "logs"; }
  std::filesystem::path out() const { return folder_.path() / "out"; }
  bool outFolderIsEmpty() const { return std::filesystem::is_empty(out()); }

  th::TemporaryFolder folder_;
};

}  // namespace th::test
