#include "face/candide.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/data_path.h"
#include "core/error.h"

namespace th::face {
namespace {

// Reads the file as lines, keeping line numbers for errors.
class Lines {
 public:
  explicit Lines(const std::filesystem::path& path) : path_(path) {
    std::ifstream file(path);
    if (!file) throw fileError(path, "cannot be opened");
    std::string line;
    while (std::getline(file, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(line);
    }
  }
  bool done() const { return next_ >= lines_.size(); }
  const std::string& peek() const { return lines_[next_]; }
  std::string take() { return lines_[next_++]; }
  // The next line that is neither blank nor a comment.
  std::string data() {
    while (!done()) {
      const std::string line = take();
      if (line.find_first_not_of(" \t") != std::string::npos && line[line.find_first_not_of(" \t")] != '#') return line;
    }
    throw error("ends early");
  }
  // Skips forward to the line that starts with `heading`.
  void seek(const std::string& heading) {
    while (!done() && peek().rfind(heading, 0) != 0) ++next_;
    if (done()) throw fileError(path_, "has no \"" + heading + "\" section (not a Candide .wfm file?)");
    ++next_;
  }
  Error error(const std::string& what) const { return fileError(path_, "line " + std::to_string(next_) + ": " + what); }

 private:
  std::filesystem::path path_;
  std::vector<std::string> lines_;
  std::size_t next_ = 0;
};

int countFrom(Lines& lines, int limit) {
  const std::string line = lines.data();
  std::istringstream in(line);
  int count = -1;
  if (!(in >> count) || count < 0 || count > limit) throw lines.error("expected a count, found \"" + line + "\"");
  return count;
}

}  // namespace

int CandideFap::mainVertex() const {
  int best = -1;
  double largest = -1.0;
  for (const auto& [vertex, displacement] : displacements)
    if (displacement.norm() > largest) largest = displacement.norm(), best = vertex;
  return best;
}

std::filesystem::path candideFile() {
  const std::filesystem::path copied =
      std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "assets" / "candide3" / "candide3_v3.1.6.wfm";
  std::error_code error;
  if (std::filesystem::is_regular_file(copied, error)) return copied;
  return sharedDataPath("face/candide3/candide3_v3.1.6.wfm");
}

Candide loadCandide(const std::filesystem::path& path) {
  Lines lines(path);
  Candide candide;
  lines.seek("# VERTEX LIST:");
  const int numVertices = countFrom(lines, 100000);
  candide.mesh.positions.resize(3, numVertices);
  for (int v = 0; v < numVertices; ++v) {
    std::istringstream in(lines.data());
    double x, y, z;
    if (!(in >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw lines.error("expected a vertex \"x y z\"");
    candide.mesh.positions.col(v) << x, y, z;
  }
  lines.seek("# FACE LIST:");
  const int numFaces = countFrom(lines, 1000000);
  candide.mesh.materials.push_back({.name = "Candide"});
  for (int f = 0; f < numFaces; ++f) {
    std::istringstream in(lines.data());
    std::array<int, 3> triangle{};
    if (!(in >> triangle[0] >> triangle[1] >> triangle[2])) throw lines.error("expected a triangle \"a b c\"");
    for (int vertex : triangle)
      if (vertex < 0 || vertex >= numVertices) throw lines.error("a triangle refers to a vertex that does not exist");
    candide.mesh.triangles.push_back(triangle);
    candide.mesh.triangleMaterial.push_back(0);
  }
  lines.seek("# ANIMATION UNITS LIST:");
  const int numUnits = countFrom(lines, 1000);
  for (int u = 0; u < numUnits; ++u) {
    // The unit's name and its FAPU tag are comments before its count.
    std::string name, tag;
    while (!lines.done() && (lines.peek().empty() || lines.peek()[0] == '#')) {
      const std::string comment = lines.take();
      if (comment.rfind("# FAP", 0) == 0 || comment.rfind("# AUV", 0) == 0)
        name = comment, tag.clear();
      else if (comment.size() > 2 && comment.find(' ', 2) == std::string::npos)
        tag = comment.substr(2);
    }
    const int count = countFrom(lines, numVertices);
    CandideFap unit{.unit = tag, .displacements = {}};
    for (int i = 0; i < count; ++i) {
      std::istringstream in(lines.data());
      int vertex;
      double dx, dy, dz;
      if (!(in >> vertex >> dx >> dy >> dz) || vertex < 0 || vertex >= numVertices)
        throw lines.error("expected \"vertex dx dy dz\"");
      unit.displacements.emplace_back(vertex, Eigen::Vector3d(dx, dy, dz));
    }
    if (name.rfind("# FAP", 0) == 0) {
      // "# FAP 3 open_jaw" or "# FAP14 thrust_jaw": the number follows "FAP", with or without a space.
      std::istringstream in(name.substr(5));
      int number = 0;
      if (!(in >> number) || number < 1 || number > 68)
        throw lines.error("cannot read the FAP number in \"" + name + "\"");
      candide.faps[number] = std::move(unit);
    }
  }
  return candide;
}

}  // namespace th::face
