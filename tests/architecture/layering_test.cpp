// The engine's stages include only the stages below them. The build already refuses a header of a stage a
// target does not link (each stage has its own include root); this test reads the sources, so that a path
// written around the roots ("../render/x.h") or a graph edited the wrong way round fails too.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The stages from the lowest to the highest (docs/architecture.md's order).
const std::vector<std::string> kOrder{"core",      "audio",  "hmm",    "nn",       "face", "features", "formats",
                                      "animation", "avatar", "render", "tracking", "eval", "pipeline", "outputs"};

// stage -> the stages it declares it uses.
std::map<std::string, std::set<std::string>> readGraph() {
  std::ifstream in(TALKINGHEAD_STAGE_GRAPH);
  std::map<std::string, std::set<std::string>> graph;
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream uses(line.substr(colon + 1));
    std::set<std::string>& set = graph[line.substr(0, colon)];
    for (std::string stage; uses >> stage;) set.insert(stage);
  }
  return graph;
}

std::set<std::string> reachable(const std::map<std::string, std::set<std::string>>& graph, const std::string& from) {
  std::set<std::string> seen{from};
  std::vector<std::string> toVisit{from};
  while (!toVisit.empty()) {
    const std::string stage = toVisit.back();
    toVisit.pop_back();
    const auto found = graph.find(stage);
    if (found == graph.end()) continue;
    for (const std::string& next : found->second)
      if (seen.insert(next).second) toVisit.push_back(next);
  }
  return seen;
}

int rankOf(const std::string& stage) {
  const auto it = std::find(kOrder.begin(), kOrder.end(), stage);
  return it == kOrder.end() ? -1 : static_cast<int>(it - kOrder.begin());
}

TEST(Layering, TheGraphHasEveryStageAndRunsFromLowerStagesToHigher) {
  const auto graph = readGraph();
  ASSERT_FALSE(graph.empty()) << "no graph at " << TALKINGHEAD_STAGE_GRAPH;
  for (const std::string& stage : kOrder) EXPECT_TRUE(graph.count(stage)) << stage << " is not a stage of the build";
  for (const auto& [stage, uses] : graph) {
    ASSERT_GE(rankOf(stage), 0) << stage << " is not in the order";
    for (const std::string& used : uses)
      EXPECT_LT(rankOf(used), rankOf(stage)) << stage << " uses " << used << ", which is not below it";
  }
  // Every folder under engine/ is a stage.
  for (const auto& entry : fs::directory_iterator(TALKINGHEAD_ENGINE_DIR))
    if (entry.is_directory()) {
      EXPECT_GE(rankOf(entry.path().filename().string()), 0) << entry.path();
    }
}

// The file named by a line `#include "path"` (spaces allowed around '#' and after "include"); nothing for any
// other line.
std::optional<std::string> quotedInclude(const std::string& line) {
  std::size_t at = line.find_first_not_of(" \t");
  if (at == std::string::npos || line[at] != '#') return std::nullopt;
  at = line.find_first_not_of(" \t", at + 1);
  const std::string_view directive = "include";
  if (at == std::string::npos || line.compare(at, directive.size(), directive) != 0) return std::nullopt;
  at = line.find_first_not_of(" \t", at + directive.size());
  if (at == std::string::npos || line[at] != '"') return std::nullopt;
  const std::size_t end = line.find('"', at + 1);
  if (end == std::string::npos || end == at + 1) return std::nullopt;
  return line.substr(at + 1, end - at - 1);
}

TEST(Layering, NoIncludeRunsFromALowerStageToAHigherOne) {
  const auto graph = readGraph();
  int includes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(TALKINGHEAD_ENGINE_DIR)) {
    const std::string extension = entry.path().extension().string();
    if (!entry.is_regular_file() || (extension != ".h" && extension != ".cpp")) continue;
    const std::string stage = fs::relative(entry.path(), TALKINGHEAD_ENGINE_DIR).begin()->string();
    const std::set<std::string> allowed = reachable(graph, stage);
    std::ifstream in(entry.path());
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
      const std::optional<std::string> quoted = quotedInclude(line);
      if (!quoted) continue;
      const std::string& path = *quoted;
      const std::string where = entry.path().string() + ":" + std::to_string(number) + ": " + path;
      EXPECT_EQ(path.find(".."), std::string::npos) << where << " reaches around the include roots";
      const auto slash = path.find('/');
      if (slash == std::string::npos) continue;  // the stage's own private header ("shader_sources.h")
      const std::string target = path.substr(0, slash);
      if (rankOf(target) < 0) continue;  // not a stage ("glad/gl.h" is quoted by some)
      ++includes;
      EXPECT_TRUE(allowed.count(target)) << where << ": " << stage << " may not include " << target;
    }
  }
  EXPECT_GT(includes, 300) << "the scan found the sources";
}

// The stages as the build declares them, in its order (stage_graph.txt's lines are in engine/CMakeLists.txt's
// order), each with the stages it uses in the same order.
std::vector<std::pair<std::string, std::vector<std::string>>> readGraphInOrder() {
  std::ifstream in(TALKINGHEAD_STAGE_GRAPH);
  std::vector<std::pair<std::string, std::vector<std::string>>> stages;
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream uses(line.substr(colon + 1));
    stages.emplace_back(line.substr(0, colon), std::vector<std::string>{});
    for (std::string stage; uses >> stage;) stages.back().second.push_back(stage);
  }
  return stages;
}

// docs/architecture.md's table of the stages ("| `name` | what it is | uses |" under "## The stages, lowest
// first"), as (name, uses) in its order; "—" uses nothing.
std::vector<std::pair<std::string, std::vector<std::string>>> readDocumentedStages() {
  std::ifstream in(std::string(TALKINGHEAD_SOURCE_DIR) + "/docs/architecture.md");
  std::vector<std::pair<std::string, std::vector<std::string>>> stages;
  std::string line;
  bool inSection = false;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) inSection = line == "## The stages, lowest first";
    if (!inSection || line.rfind("| `", 0) != 0) continue;
    const std::size_t nameEnd = line.find('`', 3);
    const std::size_t lastBar = line.rfind('|', line.size() - 2);
    if (nameEnd == std::string::npos || lastBar == std::string::npos) continue;
    std::vector<std::string> uses;
    std::istringstream column(line.substr(lastBar + 1, line.size() - lastBar - 2));
    for (std::string stage; std::getline(column, stage, ',');) {
      stage.erase(0, stage.find_first_not_of(' '));
      stage.erase(stage.find_last_not_of(' ') + 1);
      if (!stage.empty() && stage != "—") uses.push_back(stage);
    }
    stages.emplace_back(line.substr(3, nameEnd - 3), uses);
  }
  return stages;
}

// The architecture page's table is the build's graph: every stage, in the build's order, using what the build
// says it uses (a stage added or a dependency changed without the page fails here).
TEST(Layering, TheArchitecturePagesStageTableIsTheBuildsGraph) {
  const auto built = readGraphInOrder();
  const auto documented = readDocumentedStages();
  ASSERT_FALSE(built.empty()) << "no graph at " << TALKINGHEAD_STAGE_GRAPH;
  ASSERT_EQ(documented.size(), built.size()) << "docs/architecture.md's stage table has a row per stage";
  for (std::size_t i = 0; i < built.size(); ++i) {
    EXPECT_EQ(documented[i].first, built[i].first) << "row " << i + 1;
    EXPECT_EQ(documented[i].second, built[i].second) << built[i].first << "'s uses";
  }
}

}  // namespace
