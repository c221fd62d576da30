#include "cli_runner.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <sstream>

namespace th::test {

namespace fs = std::filesystem;

namespace {

CliResult run(const std::vector<std::string>& arguments, const fs::path& logFolder, std::optional<uid_t> asUser,
              const std::function<bool()>& interruptWhen) {
  const fs::path outPath = logFolder / "stdout.txt";
  const fs::path errPath = logFolder / "stderr.txt";
  std::vector<std::string> words = {TALKINGHEAD_CLI};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);

  const pid_t child = ::fork();
  if (child == 0) {
    // Only async-signal-safe calls between fork and exec.
    const int out = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0 || ::dup2(out, 1) < 0 || ::dup2(err, 2) < 0) ::_exit(126);
    if (asUser && (::setgid(*asUser) != 0 || ::setuid(*asUser) != 0)) ::_exit(125);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  CliResult result;
  int status = 0;
  if (child > 0 && interruptWhen) {
    // Poll (for at most a minute, and only while the child runs) until the moment has come, then press Ctrl-C.
    for (int i = 0; i < 1200 && !interruptWhen() && ::waitpid(child, &status, WNOHANG) == 0; ++i) ::usleep(50000);
    ::kill(child, SIGINT);
  }
  if (child < 0 || ::waitpid(child, &status, 0) != child) {
    ADD_FAILURE() << "could not run " << TALKINGHEAD_CLI;
    return result;
  }
  result.exited = WIFEXITED(status);
  result.exitCode = result.exited ? WEXITSTATUS(status) : -1;
  result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  result.out = readText(outPath);
  result.err = readText(errPath);
  return result;
}

}  // namespace

CliResult runCli(const std::vector<std::string>& arguments, const fs::path& logFolder, std::optional<uid_t> asUser) {
  return run(arguments, logFolder, asUser, {});
}

CliResult runCliInterrupted(const std::vector<std::string>& arguments, const fs::path& logFolder,
                            const std::function<bool()>& when) {
  return run(arguments, logFolder, std::nullopt, when);
}

void CliTest::SetUp() {
  fs::create_directory(folder_.path() / "logs");
  fs::create_directory(folder_.path() / "out");
}

void expectOneLineFailure(const CliResult& result, const std::string& path, const std::string& reason) {
  ASSERT_TRUE(result.exited) << "killed by signal " << result.signal << "; stderr: " << result.err;
  EXPECT_NE(result.exitCode, 0);
  EXPECT_LT(result.exitCode, 125) << "the command did not run (exec failed)";
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << "stderr: " << result.err;
  EXPECT_TRUE(!result.err.empty() && result.err.back() == '\n') << "stderr: " << result.err;
  EXPECT_NE(result.err.find(path), std::string::npos) << "does not name " << path << ": " << result.err;
  EXPECT_NE(result.err.find(reason), std::string::npos) << "does not say \"" << reason << "\": " << result.err;
}

}  // namespace th::test
