// The documentation where it can drift from what it describes: every stage header a source, a doc or a script
// names is there, and the README's results at a glance are the results page's numbers (docs/results.md is the
// one place a measurement is written, with the command that measures it).
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kSource = TALKINGHEAD_SOURCE_DIR;

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The stages' names, from the graph the build writes (stage_graph.txt: "name:uses...").
std::set<std::string> stageNames() {
  std::ifstream in(TALKINGHEAD_STAGE_GRAPH);
  std::set<std::string> names;
  for (std::string line; std::getline(in, line);)
    if (const auto colon = line.find(':'); colon != std::string::npos) names.insert(line.substr(0, colon));
  return names;
}

bool isNameCharacter(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// A header a source names in a comment or a doc names ("eval/talking_corpus.h") is there: a file moved or
// renamed leaves no pointer to where it was.
TEST(Docs, EveryStageHeaderTheSourcesAndDocsNameExists) {
  const std::set<std::string> stages = stageNames();
  ASSERT_FALSE(stages.empty()) << "no graph at " << TALKINGHEAD_STAGE_GRAPH;
  int named = 0;
  for (const char* folder :
       {"engine", "app", "capi", "python", "tests", "bench", "tools", "fuzz", "docs", "examples"}) {
    const fs::path root = kSource / folder;
    if (!fs::exists(root)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
      const std::string extension = entry.path().extension().string();
      if (!entry.is_regular_file() || (extension != ".h" && extension != ".cpp" && extension != ".md" &&
                                       extension != ".py" && extension != ".sh" && extension != ".c"))
        continue;
      std::ifstream in(entry.path());
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        for (std::size_t at = line.find(".h"); at != std::string::npos; at = line.find(".h", at + 2)) {
          if (at + 2 < line.size() && isNameCharacter(line[at + 2])) continue;  // ".hpp", ".html"
          std::size_t begin = at;
          while (begin > 0 && (isNameCharacter(line[begin - 1]) || line[begin - 1] == '/')) --begin;
          if (begin > 0 && line[begin - 1] == '.') continue;  // "../x/y.h": a relative path, not a stage's
          std::string path = line.substr(begin, at + 2 - begin);
          if (path.rfind("engine/", 0) == 0) path.erase(0, 7);  // from the checkout's root: the same header
          const auto slash = path.find('/');
          if (slash == std::string::npos || !stages.count(path.substr(0, slash))) continue;
          ++named;
          // A stage's header, or a test's own beside the stage's tests ("formats/gltf_test_tracks.h").
          EXPECT_TRUE(fs::exists(kSource / "engine" / path) || fs::exists(kSource / "tests" / path))
              << entry.path().string() << ":" << number << " names " << path << ", which is not in engine/ or tests/";
        }
      }
    }
  }
  EXPECT_GT(named, 500) << "the scan found the names";
}

// Every number in the README's "Results at a glance" table (past its first column, which says what is measured)
// is written in docs/results.md too: the README summarises the results page and cannot drift from it.
TEST(Docs, TheReadmesResultsAreOnTheResultsPage) {
  const std::string readme = readText(kSource / "README.md");
  const std::string results = readText(kSource / "docs" / "results.md");
  const auto section = readme.find("## Results at a glance");
  ASSERT_NE(section, std::string::npos);
  const auto end = readme.find("\n## ", section + 1);
  std::istringstream table(readme.substr(section, end - section));
  const std::regex numberPattern(R"(\d+(\.\d+)?)");
  int rows = 0;
  int numbers = 0;
  for (std::string line; std::getline(table, line);) {
    if (line.rfind("| ", 0) != 0 || line.rfind("| what", 0) == 0) continue;
    ++rows;
    const std::string measured = line.substr(line.find('|', 1));  // past the first column
    for (std::sregex_iterator it(measured.begin(), measured.end(), numberPattern), last; it != last; ++it) {
      const std::string number = it->str();
      // The same number standing alone in the results page (not inside a longer one: "4.4" is not in "4.47"; a
      // name's dot before it is no decimal point: "BT.1359").
      const std::regex alone("(^|[^0-9.]|[A-Za-z]\\.)" + std::regex_replace(number, std::regex(R"(\.)"), R"(\.)") +
                             "($|[^0-9])");
      ++numbers;
      EXPECT_TRUE(std::regex_search(results, alone))
          << number << " in the README's results (" << line.substr(0, 60) << "…) is not on docs/results.md";
    }
  }
  EXPECT_GT(rows, 10);
  EXPECT_GT(numbers, 50);
}

}  // namespace
