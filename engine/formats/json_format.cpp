// FAP curves as JSON, with each FAP's name and unit for people reading the file:
//   {"format": "talkinghead-animation", "version": 1, "fps": 30, "name": "...",
//    "faps": [{"number": 3, "name": "open_jaw", "unit": "MNS"}, ...],
//    "time_s": [...], "frames": [[v3, v48, ...], ...]}
// Reading refuses unknown fields (a misspelt one must not be dropped without a word), checks a FAP's name and
// unit against its number (a column renumbered by hand), and time_s against fps when present.
#include <cmath>
#include <cstdint>
#include <ostream>

#include "core/error.h"
#include "core/json_reading.h"
#include "core/text_files.h"
#include "formats/animation_format.h"
#include "formats/text_tokens.h"

namespace th::formats {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kJsonFormatName = "talkinghead-animation";
constexpr int kJsonVersion = 1;
// The document nests 3 deep (root, frames, a frame); deeper input is refused while parsing.
constexpr int kMaxJsonDepth = 8;

// Reads the fields of an animation document; every message names the field at fault ("frames[12][3]").
class TrackReader : public JsonFields {
 public:
  explicit TrackReader(const fs::path& path) : JsonFields(path.string()), path_(path) {}

  face::FapTrack read(const Json& document) const {
    if (!document.is_object()) throw fileError(path_, "holds " + kindOf(document) + ", not an animation object");
    onlyKnownFields(document, {"format", "version", "fps", "name", "faps", "time_s", "frames"}, "");
    const Json& format = member(document, "format", "");
    if (!format.is_string() || format.get_ref<const std::string&>() != kJsonFormatName)
      fail("format", "is " + describe(format) + ", not \"" + std::string(kJsonFormatName) + "\"");
    const Json& version = member(document, "version", "");
    if (!(version.is_number_unsigned() && version.get<std::uint64_t>() == kJsonVersion))
      fail("version", "is " + describe(version) + "; this program reads version " + std::to_string(kJsonVersion));
    face::FapTrack track;
    track.framesPerSecond = number(member(document, "fps", ""), "fps");
    if (!(track.framesPerSecond > 0))
      fail("fps", "is " + formatNumber(track.framesPerSecond) + "; it must be positive");
    if (const Json* name = find(document, "name")) track.name = string(*name, "name");
    readFaps(array(member(document, "faps", ""), "faps"), track.faps);
    const Json& frames = array(member(document, "frames", ""), "frames");
    if (frames.empty()) fail("frames", "is empty: no frames");
    track.values.resize(static_cast<Eigen::Index>(track.faps.size()), static_cast<Eigen::Index>(frames.size()));
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const Json& row = frames[f];
      if (!row.is_array()) fail(indexed("frames", f), "is " + kindOf(row) + ", not an array");
      if (row.size() != track.faps.size()) {
        fail(indexed("frames", f),
             "has " + counted(row.size(), "value") + ", but faps lists " + counted(track.faps.size(), "FAP"));
      }
      for (std::size_t r = 0; r < row.size(); ++r) {
        if (!row[r].is_number()) fail(indexed(indexed("frames", f), r), "is " + describe(row[r]) + ", not a number");
        track.values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(f)) = row[r].get<double>();
      }
    }
    if (const Json* times = find(document, "time_s"))
      checkTimes(array(*times, "time_s"), frames.size(), track.framesPerSecond);
    return track;
  }

 private:
  int fapNumber(const Json& value, const std::string& field) const {
    // nlohmann reads a non-negative integer as unsigned and a negative one as signed.
    if (value.is_number_unsigned()) {
      const auto number = value.get<std::uint64_t>();
      if (number >= 1 && number <= face::kNumFaps) return static_cast<int>(number);
    }
    if (value.is_number_float()) fail(field, "is " + describe(value) + ", not an integer");
    fail(field, "is " + describe(value) + ", not a FAP number (1.." + std::to_string(face::kNumFaps) + ")");
  }

  void readFaps(const Json& faps, std::vector<int>& numbers) const {
    for (std::size_t i = 0; i < faps.size(); ++i) {
      const std::string field = indexed("faps", i);
      const Json& entry = faps[i];
      if (!entry.is_object()) fail(field, "is " + kindOf(entry) + ", not an object");
      onlyKnownFields(entry, {"number", "name", "unit"}, field);
      const int number = fapNumber(member(entry, "number", field), field + ".number");
      if (!numbers.empty() && number <= numbers.back()) {
        fail(field + ".number", "is " + std::to_string(number) + ", after " + std::to_string(numbers.back()) +
                                    ": the FAP numbers must be ascending and unique");
      }
      // Name and unit are for people reading the file; if present they must agree with the number.
      const face::FapDefinition& definition = face::fapDefinition(number);
      if (const Json* name = find(entry, "name");
          name != nullptr && string(*name, field + ".name") != definition.name) {
        fail(field + ".name", "is " + describe(*name) + ", but FAP " + std::to_string(number) + " is \"" +
                                  std::string(definition.name) + "\"");
      }
      const std::string_view unit = face::fapuName(definition.unit);
      if (const Json* given = find(entry, "unit"); given != nullptr && string(*given, field + ".unit") != unit) {
        fail(field + ".unit",
             "is " + describe(*given) + ", but FAP " + std::to_string(number) + " is in \"" + std::string(unit) + "\"");
      }
      numbers.push_back(number);
    }
  }

  // time_s repeats what fps says; a disagreement means one of them was edited without the other.
  void checkTimes(const Json& times, std::size_t numFrames, double framesPerSecond) const {
    if (times.size() != numFrames)
      fail("time_s", "has " + counted(times.size(), "time") + ", but there are " + counted(numFrames, "frame"));
    std::vector<double> seconds;
    for (std::size_t i = 0; i < times.size(); ++i) {
      if (!times[i].is_number()) fail(indexed("time_s", i), "is " + describe(times[i]) + ", not a number");
      seconds.push_back(times[i].get<double>());
    }
    if (const std::size_t i = firstUnevenTime(seconds, framesPerSecond); i < seconds.size()) {
      fail(indexed("time_s", i), "is " + formatNumber(seconds[i]) + ", but at " + formatNumber(framesPerSecond) +
                                     " fps frame " + std::to_string(i) + " is at " +
                                     formatNumber(seconds[0] + static_cast<double>(i) / framesPerSecond));
    }
  }

  const fs::path& path_;
};

class JsonFormat final : public AnimationFormat {
 public:
  std::string_view name() const override { return "json"; }
  std::string_view extension() const override { return ".json"; }
  std::string_view description() const override { return "FAP curves with each FAP's name and unit, and the times"; }
  bool readable() const override { return true; }

  void check(const fs::path& path, const face::FapTrack& track) const override {
    if (!std::isfinite((track.numFrames() - 1) / track.framesPerSecond))
      throw fileError(path, "at " + formatNumber(track.framesPerSecond) +
                                " fps the last frame's time is beyond the range of a double");
  }

  void write(std::ostream& out, const face::FapTrack& track) const override {
    // Laid out by hand around nlohmann's scalars, so that a frame is one line (dump() would give every number
    // a line of its own). A name that is not UTF-8 has its bad bytes replaced rather than failing the write.
    const auto json = [](const Json& value) { return value.dump(-1, ' ', false, Json::error_handler_t::replace); };
    out << "{\n  \"format\": " << json(std::string(kJsonFormatName)) << ",\n  \"version\": " << kJsonVersion
        << ",\n  \"fps\": " << json(track.framesPerSecond) << ",\n  \"name\": " << json(track.name)
        << ",\n  \"faps\": [";
    for (std::size_t r = 0; r < track.faps.size(); ++r) {
      const face::FapDefinition& definition = face::fapDefinition(track.faps[r]);
      const Json entry = {{"number", definition.number},
                          {"name", std::string(definition.name)},
                          {"unit", std::string(face::fapuName(definition.unit))}};
      out << (r > 0 ? ",\n    " : "\n    ") << json(entry);
    }
    out << "\n  ],\n  \"time_s\": [";
    for (int f = 0; f < track.numFrames(); ++f) out << (f > 0 ? ", " : "") << json(f / track.framesPerSecond);
    out << "],\n  \"frames\": [";
    for (int f = 0; f < track.numFrames(); ++f) {
      out << (f > 0 ? ",\n    [" : "\n    [");
      for (Eigen::Index r = 0; r < track.values.rows(); ++r) out << (r > 0 ? ", " : "") << json(track.values(r, f));
      out << ']';
    }
    out << "\n  ]\n}\n";
  }

  face::FapTrack read(std::string_view text, const fs::path& path) const override {
    const Json document =
        parseJson(text, path.string(), {.maxDepth = kMaxJsonDepth, .depthNote = "an animation needs 3", .subject = ""});
    try {
      return TrackReader(path).read(document);
    } catch (const Json::exception& e) {
      // Every access in TrackReader checks the type first; this only keeps a missed case from escaping as an
      // nlohmann exception, which callers do not expect.
      throw fileError(path, "is malformed (" + jsonReason(e.what()) + ")");
    }
  }
};

}  // namespace

const AnimationFormat& jsonFormat() {
  static const JsonFormat format;
  return format;
}

}  // namespace th::formats
