// glTF animation checked by programs other than the one that wrote it: the Khronos glTF validator (npm's
// gltf-validator, run by tools/gltf_validate.js on node) finds no errors in either form (the avatar with the
// animation, the animation alone) written as .glb and .gltf for both real avatars, and assimp reads the written
// files and counts the animation; the same for what `talkinghead animate --avatar` writes from a recording. Missing
// node, validator or assimp fail the test with what to install: these tools are the point of the test, and
// scripts/test.sh installs them.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "cli/cli_runner.h"
#include "core/data_path.h"
#include "core/temporary_file.h"
#include "formats/gltf_animation.h"
#include "formats/gltf_test_tracks.h"

namespace th::formats {
namespace {

namespace fs = std::filesystem;

std::string shellQuote(const std::string& argument) {
  std::string quoted = "'";
  for (char c : argument) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

struct ProcessResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};

ProcessResult run(const std::string& command) {
  ProcessResult result;
  FILE* pipe = ::popen((command + " </dev/null 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer{};
  std::size_t got = 0;
  while ((got = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), got);
  const int status = ::pclose(pipe);
  result.exitCode = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// Where scripts/install-node-tools.sh installs gltf-validator (BUILD/node); TALKINGHEAD_NODE_MODULES
// overrides it.
std::string nodeModules() {
  const char* set = std::getenv("TALKINGHEAD_NODE_MODULES");
  return set && *set ? std::string(set) : std::string(TALKINGHEAD_NODE_MODULES);
}

std::string validatorScript() {
  return std::string(TALKINGHEAD_SOURCE_DIR) + "/tools/gltf_validate.js";
}

// The validator's one-line summary ("FILE: 0 errors, N warnings, ...") and, on errors, the report's messages.
ProcessResult validate(const fs::path& file) {
  return run("NODE_PATH=" + shellQuote(nodeModules()) + " node " + shellQuote(validatorScript()) + " " +
             shellQuote(file.string()));
}

// The tools are the point of these tests: their absence fails them, saying what installs them.
void requireValidator() {
  ASSERT_EQ(run("command -v node").exitCode, 0)
      << "node is not installed: scripts/install-packages.sh installs nodejs and npm (scripts/packages.txt)";
  ASSERT_TRUE(fs::exists(fs::path(nodeModules()) / "gltf-validator" / "package.json"))
      << "gltf-validator is not installed in " << nodeModules()
      << ": run `bash scripts/install-node-tools.sh <build folder>` (scripts/test.sh does), or set "
         "TALKINGHEAD_NODE_MODULES to a node_modules folder that has it";
}

void requireAssimp() {
  ASSERT_EQ(run("command -v assimp").exitCode, 0)
      << "assimp is not installed: scripts/install-packages.sh installs assimp-utils";
}

class GltfCrosscheck : public ::testing::Test {
 protected:
  // Both forms of `avatar` as .glb and .gltf, in the folder.
  std::vector<fs::path> writeAll(const std::string& avatarName) {
    const fs::path avatar = sharedDataPath("face/avatars/" + avatarName);
    const GltfAnimationTracks tracks = test::speechTracks(readGltfAvatar(avatar));
    const std::string stem = fs::path(avatarName).stem().string();
    std::vector<fs::path> files;
    for (const char* extension : {".glb", ".gltf"}) {
      files.push_back(folder.path() / (stem + "-talk" + extension));
      writeAvatarAnimation(avatar, tracks, files.back());
      files.push_back(folder.path() / (stem + "-animation" + extension));
      writeAnimationOnly(avatar, tracks, files.back());
    }
    return files;
  }

  // What the CLI writes from a recording: each avatar with its speech (.glb) and the animation alone (.gltf).
  std::vector<fs::path> writeWithCli() {
    std::vector<fs::path> files;
    const fs::path logs = folder.path() / "logs";
    fs::create_directories(logs);
    for (const char* avatarName : {"brunette-t.glb", "vroid.glb"}) {
      const std::string stem = fs::path(avatarName).stem().string();
      for (const auto& [suffix, only] : {std::pair{"-cli-talk.glb", false}, std::pair{"-cli-animation.gltf", true}}) {
        files.push_back(folder.path() / (stem + suffix));
        std::vector<std::string> arguments{
            "animate",  sharedDataPath("speech/arctic/arctic_a0001.wav").string(),         "-o", files.back().string(),
            "--avatar", sharedDataPath("face/avatars/" + std::string(avatarName)).string()};
        if (only) arguments.emplace_back("--animation-only");
        const th::test::CliResult result = th::test::runCli(arguments, logs);
        EXPECT_EQ(result.exitCode, 0) << result.err;
      }
    }
    return files;
  }

  TemporaryFolder folder;
};

TEST_F(GltfCrosscheck, KhronosValidatorFindsNoErrors) {
  ASSERT_NO_FATAL_FAILURE(requireValidator());
  for (const char* avatar : {"brunette-t.glb", "vroid.glb"}) {
    for (const auto& file : writeAll(avatar)) {
      const ProcessResult result = validate(file);
      // The report is long (every warning with its JSON pointer); the summary is its last line.
      const std::string summary = result.output.substr(result.output.rfind('\n', result.output.size() - 2) + 1);
      EXPECT_EQ(result.exitCode, 0) << file.filename() << ":\n" << result.output;
      EXPECT_NE(summary.find(": 0 errors"), std::string::npos) << summary;
      std::cout << summary;
    }
  }
}

TEST_F(GltfCrosscheck, AssimpReadsTheWrittenFilesAndTheirAnimation) {
  ASSERT_NO_FATAL_FAILURE(requireAssimp());
  for (const char* avatar : {"brunette-t.glb", "vroid.glb"}) {
    for (const auto& file : writeAll(avatar)) {
      const ProcessResult result = run("assimp info " + shellQuote(file.string()));
      EXPECT_EQ(result.exitCode, 0) << file.filename() << ":\n" << result.output;
      std::smatch match;
      ASSERT_TRUE(std::regex_search(result.output, match, std::regex(R"(Animations:\s*(\d+))")))
          << file.filename() << ": assimp printed no animation count:\n"
          << result.output;
      EXPECT_EQ(std::stoi(match[1]), 1) << file.filename();
      std::cout << file.filename().string() << ": assimp: Animations: " << match[1] << "\n";
    }
  }
}

TEST_F(GltfCrosscheck, TheClisFilesPassTheValidatorAndAssimpReadsThem) {
  ASSERT_NO_FATAL_FAILURE(requireValidator());
  ASSERT_NO_FATAL_FAILURE(requireAssimp());
  for (const auto& file : writeWithCli()) {
    ASSERT_TRUE(fs::exists(file)) << file;
    const ProcessResult validated = validate(file);
    const std::string summary = validated.output.substr(validated.output.rfind('\n', validated.output.size() - 2) + 1);
    EXPECT_EQ(validated.exitCode, 0) << file.filename() << ":\n" << validated.output;
    EXPECT_NE(summary.find(": 0 errors"), std::string::npos) << summary;
    std::cout << summary;
    const ProcessResult read = run("assimp info " + shellQuote(file.string()));
    EXPECT_EQ(read.exitCode, 0) << file.filename() << ":\n" << read.output;
    std::smatch match;
    ASSERT_TRUE(std::regex_search(read.output, match, std::regex(R"(Animations:\s*(\d+))")))
        << file.filename() << ": assimp printed no animation count:\n"
        << read.output;
    EXPECT_EQ(std::stoi(match[1]), 1) << file.filename();
    std::cout << file.filename().string() << ": assimp: Animations: " << match[1] << "\n";
  }
}

}  // namespace
}  // namespace th::formats
