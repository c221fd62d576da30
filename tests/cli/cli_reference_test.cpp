// docs/cli.md is what `talkinghead reference` writes from the commands themselves: the reference cannot drift
// from the program. (After changing an option: build/talkinghead reference > docs/cli.md.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include "cli_runner.h"
#include "support/files.h"

namespace {

class CliReferenceTest : public th::test::CliTest {};

TEST_F(CliReferenceTest, TheDocsReferenceIsWhatTheProgramWrites) {
  const th::test::CliResult result = th::test::runCli({"reference"}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const std::string committed = th::test::readText(std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "docs" / "cli.md");
  EXPECT_EQ(result.out, committed) << "docs/cli.md is out of date: build/talkinghead reference > docs/cli.md";
  for (const char* command : {"## `talkinghead animate`", "## `talkinghead export`", "## `talkinghead live`",
                              "## `talkinghead train mouth`", "| `--head-amplitude` |"})
    EXPECT_NE(result.out.find(command), std::string::npos) << command;
  // The reference is the same on every machine: no default is a path into this checkout or a home folder.
  EXPECT_EQ(result.out.find(TALKINGHEAD_SOURCE_DIR), std::string::npos) << "a default names this checkout's folder";
  if (const char* home = std::getenv("HOME"); home != nullptr && std::string(home).size() > 1) {
    EXPECT_EQ(result.out.find(std::string(home) + "/"), std::string::npos) << "a default names " << home;
  }
  // Every option says what it does: the last cell of each option's row is not empty.
  std::istringstream lines(result.out);
  int options = 0;
  for (std::string line; std::getline(lines, line);) {
    if (!line.starts_with("| `-")) continue;
    ++options;
    const std::size_t lastCell = line.rfind(" | ");
    ASSERT_NE(lastCell, std::string::npos) << line;
    EXPECT_NE(line.substr(lastCell), " |  |") << "an option without help: " << line;
  }
  EXPECT_GT(options, 100);
}

}  // namespace
