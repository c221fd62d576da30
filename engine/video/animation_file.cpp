#include "video/animation_file.h"

#include <algorithm>
#include <array>
#include <bitset>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string_view>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_files.h"
#include "face/fap.h"

namespace th::video {
namespace {

namespace fs = std::filesystem;
// Ordered: a written file reads top to bottom as the header documents it.
using Json = nlohmann::ordered_json;

constexpr std::string_view kJsonFormatName = "talkinghead-animation";
constexpr int kJsonVersion = 1;
constexpr std::string_view kFapVersion = "2.1";
// Times may stray from even spacing by this fraction of a frame period: far more than the rounding of a
// printed time, far less than a dropped or repeated frame.
constexpr double kSpacingTolerance = 1e-4;
// Refused before it is all in memory: an hour of all 68 FAPs at 30 fps is 7 million values, some 150 MB of
// text at most.
// The document nests 3 deep (root, frames, a frame); deeper input is refused while parsing, before a forged
// file can build a deep tree.
constexpr int kMaxJsonDepth = 8;
// Xface and Greta read .fap values as 32-bit ints; a value is written only if its rounding fits one.
constexpr double kFapValueBelow = -2147483648.5;
constexpr double kFapValueAbove = 2147483647.5;

// A number in a message: short, and enough digits to tell values within the spacing tolerance apart.
std::string formatNumber(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.9g", value);
  return buffer.data();
}

// The shortest text that reads back as the same double: files round-trip exactly.
std::string shortest(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

// Fixed notation (no exponent), shortest round-trip or with `decimals` digits after the point. Room for the
// 309 integer digits of the largest double and the decimals timeDecimals() can ask for.
std::string fixedNotation(double value, std::optional<int> decimals = std::nullopt) {
  std::array<char, 768> buffer{};
  char* const first = buffer.data();
  char* const last = first + buffer.size();
  const auto result = decimals ? std::to_chars(first, last, value, std::chars_format::fixed, *decimals)
                               : std::to_chars(first, last, value, std::chars_format::fixed);
  return std::string(first, result.ptr);
}

// Decimals of a CSV time: rounding moves a time by at most a tenth of the reader's spacing tolerance, so the
// reader recovers the frame rate (7 decimals at 25 and 30 fps).
int timeDecimals(double framesPerSecond) {
  const double needed = std::ceil(std::log10(framesPerSecond) + std::log10(0.5 / (0.1 * kSpacingTolerance)));
  return static_cast<int>(std::clamp(needed, 6.0, 340.0));
}

std::optional<double> parseNumber(std::string_view text) {
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

template <typename Integer>
std::optional<Integer> parseInteger(std::string_view text) {
  if (text.empty()) return std::nullopt;
  Integer value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

constexpr std::string_view kBlanks = " \t\r\v\f";
bool isBlank(char c) {
  return kBlanks.find(c) != std::string_view::npos;
}

[[noreturn]] void failAt(const fs::path& path, int line, const std::string& what) {
  throw fileError(path, "line " + std::to_string(line) + ": " + what);
}

// "1 value", "2 values".
std::string counted(std::size_t count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

std::string fapColumnName(int fap) {
  return "fap" + std::to_string(fap);
}

// Lines of a text, numbered from 1, without their "\n" or "\r\n".
class Lines {
 public:
  explicit Lines(std::string_view text) : rest_(text) {}

  // The next line holding more than whitespace (and, with skipComments, not starting with '#').
  bool nextContent(std::string_view& line, bool skipComments) {
    while (next(line)) {
      const auto first = line.find_first_not_of(kBlanks);
      if (first == std::string_view::npos) continue;
      if (skipComments && line[first] == '#') continue;
      return true;
    }
    return false;
  }

  int number() const { return number_; }

 private:
  bool next(std::string_view& line) {
    if (rest_.empty()) return false;
    const auto end = rest_.find('\n');
    line = rest_.substr(0, end);
    rest_ = end == std::string_view::npos ? std::string_view() : rest_.substr(end + 1);
    if (line.ends_with('\r')) line.remove_suffix(1);
    ++number_;
    return true;
  }

  std::string_view rest_;
  int number_ = 0;  // the file is at most kMaxTextFileBytes, so its lines fit an int
};

// The fields of a line. Only the first `keep` are stored (a line of a forged file can hold millions); all are
// counted, for the message that says how many there were.
struct Fields {
  std::vector<std::string_view> items;
  std::size_t count = 0;
};

Fields splitWhitespace(std::string_view line, std::size_t keep) {
  Fields fields;
  std::size_t i = 0;
  while (true) {
    while (i < line.size() && isBlank(line[i])) ++i;
    if (i == line.size()) return fields;
    const std::size_t start = i;
    while (i < line.size() && !isBlank(line[i])) ++i;
    if (fields.count++ < keep) fields.items.push_back(line.substr(start, i - start));
  }
}

Fields splitCommas(std::string_view line, std::size_t keep) {
  Fields fields;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    std::string_view field = line.substr(start, comma == std::string_view::npos ? comma : comma - start);
    while (!field.empty() && isBlank(field.front())) field.remove_prefix(1);
    while (!field.empty() && isBlank(field.back())) field.remove_suffix(1);
    if (fields.count++ < keep) fields.items.push_back(field);
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

// The index of the first time that is off even spacing at this rate (counted from the first time), or
// times.size() if none is.
std::size_t firstUnevenTime(const std::vector<double>& times, double framesPerSecond) {
  for (std::size_t i = 1; i < times.size(); ++i) {
    const double expected = times[0] + static_cast<double>(i) / framesPerSecond;
    if (!(std::abs(times[i] - expected) <= kSpacingTolerance / framesPerSecond)) return i;
  }
  return times.size();
}

// The rate of evenly spaced times. Printed times are rounded (1/30 s has no exact decimal), so the rate from
// the first and last times is a little off the nominal one: a whole rate, a whole rate × 1000/1001 (NTSC
// video) or a rate with up to three decimals (12.5) is taken, in that order, when every time is within the
// tolerance of it.
double frameRateOf(const std::vector<double>& times, const std::vector<int>& lines, const fs::path& path) {
  const double span = times.back() - times.front();
  if (!(span > 0)) {
    failAt(path, lines.back(),
           "time_s " + formatNumber(times.back()) + " is not after the first row's " +
               formatNumber(times.front()) + ": time_s must increase");
  }
  const double measured = static_cast<double>(times.size() - 1) / span;
  if (!std::isfinite(measured)) failAt(path, lines.back(), "time_s steps are too short to give a frame rate");
  for (const double nominal : {std::round(measured), std::round(measured * 1.001) * 1000.0 / 1001.0,
                               std::round(measured * 10.0) / 10.0, std::round(measured * 100.0) / 100.0,
                               std::round(measured * 1000.0) / 1000.0}) {
    if (nominal > 0 && firstUnevenTime(times, nominal) == times.size()) return nominal;
  }
  if (const std::size_t i = firstUnevenTime(times, measured); i < times.size()) {
    failAt(path, lines[i],
           "time_s " + formatNumber(times[i]) + " breaks the even spacing of frames: at " +
               formatNumber(measured) + " fps (from the first and last rows) this row is at " +
               formatNumber(times[0] + static_cast<double>(i) / measured));
  }
  return measured;
}

Eigen::MatrixXd toMatrix(const std::vector<double>& rowMajor, std::size_t rows, std::size_t cols) {
  Eigen::MatrixXd matrix(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < cols; ++c) {
      matrix(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rowMajor[r * cols + c];
    }
  }
  return matrix;
}

// The writers' checks; readAnimation applies them too, so whatever it returns writes back in its own format.
void checkAnimation(const fs::path& path, const Animation& animation, AnimationFormat format) {
  const double fps = animation.framesPerSecond;
  if (!(std::isfinite(fps) && fps > 0)) {
    throw fileError(path, "the frame rate " + formatNumber(fps) + " fps is not positive and finite");
  }
  const auto& faps = animation.faps;
  for (std::size_t c = 0; c < faps.size(); ++c) {
    if (faps[c] < 1 || faps[c] > face::kNumFaps) {
      throw fileError(
          path, "FAP number " + std::to_string(faps[c]) + " is outside 1.." + std::to_string(face::kNumFaps));
    }
    if (c > 0 && faps[c] <= faps[c - 1]) {
      throw fileError(path, "FAP " + std::to_string(faps[c]) + " follows FAP " + std::to_string(faps[c - 1]) +
                                ": the FAP numbers must be ascending and unique");
    }
  }
  if (animation.values.cols() != static_cast<Eigen::Index>(faps.size())) {
    throw fileError(path, "the values have " + std::to_string(animation.values.cols()) +
                              " columns, but the animation lists " + counted(faps.size(), "FAP"));
  }
  const int numFrames = animation.numFrames();
  if (numFrames == 0) throw fileError(path, "the animation has no frames");
  if (format == AnimationFormat::kCsv && numFrames == 1) {
    throw fileError(path,
                    "one frame: a CSV file gives its frame rate only through time_s, which takes two "
                    "frames (write .json or .fap)");
  }
  if (format != AnimationFormat::kFap && !std::isfinite((numFrames - 1) / fps)) {
    throw fileError(path,
                    "at " + formatNumber(fps) + " fps the last frame's time is beyond the range of a double");
  }
  for (int f = 0; f < numFrames; ++f) {
    for (std::size_t c = 0; c < faps.size(); ++c) {
      const double value = animation.values(f, static_cast<Eigen::Index>(c));
      const auto where = [&] {
        return "frame " + std::to_string(f) + ", " + fapColumnName(faps[c]) + " is ";
      };
      if (!std::isfinite(value)) {
        throw fileError(path, where() + formatNumber(value) + ": values must be finite");
      }
      if (format == AnimationFormat::kFap && !(value > kFapValueBelow && value < kFapValueAbove)) {
        throw fileError(path, where() + formatNumber(value) + ": a .fap holds 32-bit integer values");
      }
    }
  }
}

// ---- CSV ----

// "fap48" → 48; 0 if the column name is not of that form.
int fapOfColumn(std::string_view name) {
  if (!name.starts_with("fap")) return 0;
  const auto number = parseInteger<int>(name.substr(3));
  return number && *number >= 1 && *number <= face::kNumFaps ? *number : 0;
}

Animation parseCsv(std::string_view text, const fs::path& path) {
  Lines lines(text);
  std::string_view line;
  if (!lines.nextContent(line, false)) {
    throw fileError(path, "is empty (expected a header line time_s,fap3,...)");
  }
  const int headerLine = lines.number();
  constexpr std::size_t kMaxColumns = 1 + face::kNumFaps;
  const Fields header = splitCommas(line, kMaxColumns);
  if (header.items[0] != "time_s") {
    if (parseNumber(header.items[0])) {
      failAt(path, headerLine, "the header is missing: expected time_s,fap3,...");
    }
    failAt(path, headerLine, "the first column is '" + printable(header.items[0]) + "'; expected time_s");
  }
  // Columns may come in any order; the animation's are ascending.
  std::array<std::size_t, face::kNumFaps + 1> columnOfFap{};  // header column of each FAP, 0 if absent
  for (std::size_t c = 1; c < header.items.size(); ++c) {
    const int fap = fapOfColumn(header.items[c]);
    if (fap == 0) {
      failAt(path, headerLine,
             "column " + std::to_string(c + 1) + " '" + printable(header.items[c]) +
                 "' is not a FAP column (fap1 .. fap68)");
    }
    if (columnOfFap[static_cast<std::size_t>(fap)] != 0) {
      failAt(path, headerLine,
             "columns " + std::to_string(columnOfFap[static_cast<std::size_t>(fap)] + 1) + " and " +
                 std::to_string(c + 1) + " are both " + fapColumnName(fap));
    }
    columnOfFap[static_cast<std::size_t>(fap)] = c;
  }
  if (header.count > kMaxColumns) {
    failAt(
        path, headerLine,
        "the header has " + std::to_string(header.count) + " columns; there are only time_s and the 68 FAPs");
  }
  Animation animation;
  for (int fap = 1; fap <= face::kNumFaps; ++fap) {
    if (columnOfFap[static_cast<std::size_t>(fap)] != 0) animation.faps.push_back(fap);
  }

  std::vector<double> times;
  std::vector<double> values;  // row-major, in the animation's column order
  std::vector<int> rowLines;
  std::array<double, kMaxColumns> row{};
  while (lines.nextContent(line, false)) {
    const Fields fields = splitCommas(line, header.count);
    if (fields.count != header.count) {
      failAt(path, lines.number(),
             counted(fields.count, "value") + ", but the header has " + counted(header.count, "column"));
    }
    for (std::size_t c = 0; c < fields.count; ++c) {
      const auto value = parseNumber(fields.items[c]);
      if (!value || !std::isfinite(*value)) {
        failAt(path, lines.number(),
               std::string(header.items[c]) + " '" + printable(fields.items[c]) + "' is not a finite number");
      }
      row[c] = *value;
    }
    times.push_back(row[0]);
    for (int fap : animation.faps) values.push_back(row[columnOfFap[static_cast<std::size_t>(fap)]]);
    rowLines.push_back(lines.number());
  }
  if (times.empty()) failAt(path, headerLine, "no frames follow the header");
  if (times.size() == 1) failAt(path, rowLines[0], "one frame: the frame rate cannot be derived from time_s");
  animation.framesPerSecond = frameRateOf(times, rowLines, path);
  animation.values = toMatrix(values, times.size(), animation.faps.size());
  return animation;
}

void writeCsv(std::ostream& out, const Animation& animation) {
  out << "time_s";
  for (int fap : animation.faps) out << ',' << fapColumnName(fap);
  out << '\n';
  const int decimals = timeDecimals(animation.framesPerSecond);
  for (int f = 0; f < animation.numFrames(); ++f) {
    out << fixedNotation(f / animation.framesPerSecond, decimals);
    for (Eigen::Index c = 0; c < animation.values.cols(); ++c) out << ',' << shortest(animation.values(f, c));
    out << '\n';
  }
}

// ---- .fap ----

Animation parseFap(std::string_view text, const fs::path& path) {
  Lines lines(text);
  std::string_view line;
  if (!lines.nextContent(line, true)) {
    throw fileError(path, "is empty (expected a header line `2.1 NAME FPS NFRAMES`)");
  }
  const int headerLine = lines.number();
  const Fields header = splitWhitespace(line, 4);
  if (header.count != 4) {
    failAt(path, headerLine,
           "the header `2.1 NAME FPS NFRAMES` is missing: this line has " + std::to_string(header.count) +
               " fields");
  }
  if (header.items[0] != kFapVersion) {
    failAt(path, headerLine,
           "version '" + printable(header.items[0]) + "' is not 2.1 (the header is " +
               "`2.1 NAME FPS NFRAMES`)");
  }
  Animation animation;
  animation.name = std::string(header.items[1]);
  const auto fps = parseNumber(header.items[2]);
  if (!fps || !std::isfinite(*fps) || *fps <= 0) {
    failAt(path, headerLine, "the frame rate '" + printable(header.items[2]) + "' is not a positive number");
  }
  animation.framesPerSecond = *fps;
  // Only compared with the frames read, never used to size anything: a forged header costs nothing.
  const auto announced = parseInteger<std::int64_t>(header.items[3]);
  if (!announced || *announced < 0) {
    failAt(path, headerLine,
           "the frame count '" + printable(header.items[3]) + "' is not a whole number (0 or more)");
  }

  // Kept as sent (masks and the values they flag) and filled in at the end, once the columns are known.
  std::vector<std::bitset<face::kNumFaps>> masks;
  std::vector<std::int32_t> sent;
  std::bitset<face::kNumFaps> everSent;
  std::int64_t previousFrame = -1;
  while (lines.nextContent(line, true)) {
    const int maskLine = lines.number();
    if (static_cast<std::int64_t>(masks.size()) == *announced) {
      failAt(path, maskLine,
             "a frame beyond the " + std::to_string(*announced) + " that the header on line " +
                 std::to_string(headerLine) + " announces");
    }
    const Fields flags = splitWhitespace(line, face::kNumFaps);
    if (flags.count != face::kNumFaps) {
      failAt(path, maskLine,
             "the mask has " + std::to_string(flags.count) + " flags; expected 68 (a 0 or 1 per FAP)");
    }
    std::bitset<face::kNumFaps> mask;
    for (std::size_t i = 0; i < flags.items.size(); ++i) {
      if (flags.items[i] == "1") {
        mask.set(i);
      } else if (flags.items[i] != "0") {
        failAt(path, maskLine,
               "mask flag " + std::to_string(i + 1) + " is '" + printable(flags.items[i]) +
                   "'; expected 0 or 1");
      }
    }
    if (!lines.nextContent(line, true)) {
      failAt(path, maskLine,
             "the file ends after this mask; expected a line with the frame number and values");
    }
    const int valueLine = lines.number();
    const Fields items = splitWhitespace(line, mask.count() + 1);
    if (items.count != mask.count() + 1) {
      failAt(path, valueLine,
             "the frame number is followed by " + counted(items.count - 1, "value") +
                 ", but the mask on line " + std::to_string(maskLine) + " flags " +
                 counted(mask.count(), "FAP"));
    }
    const auto frame = parseInteger<std::int64_t>(items.items[0]);
    if (!frame || *frame < 0) {
      failAt(path, valueLine,
             "the frame number '" + printable(items.items[0]) + "' is not a whole number (0 or more)");
    }
    if (*frame <= previousFrame) {
      failAt(path, valueLine,
             "frame number " + std::to_string(*frame) + " follows " + std::to_string(previousFrame) +
                 ": frame numbers must increase");
    }
    previousFrame = *frame;
    std::size_t item = 1;
    for (std::size_t i = 0; i < mask.size(); ++i) {
      if (!mask.test(i)) continue;
      const std::string_view token = items.items[item++];
      const auto value = parseInteger<std::int32_t>(token);
      if (!value) {
        failAt(
            path, valueLine,
            fapColumnName(static_cast<int>(i) + 1) + " '" + printable(token) + "' is not a 32-bit integer");
      }
      sent.push_back(*value);
    }
    masks.push_back(mask);
    everSent |= mask;
  }
  if (masks.empty()) failAt(path, headerLine, "no frames follow the header");
  if (static_cast<std::int64_t>(masks.size()) != *announced) {
    failAt(path, headerLine,
           "the header announces " + std::to_string(*announced) + " frames, but the file has " +
               std::to_string(masks.size()));
  }

  for (std::size_t i = 0; i < everSent.size(); ++i) {
    if (everSent.test(i)) animation.faps.push_back(static_cast<int>(i) + 1);
  }
  // A FAP not sent in a frame holds its last value; 0 before it is first sent.
  std::array<double, face::kNumFaps> current{};
  std::vector<double> values;
  values.reserve(masks.size() * animation.faps.size());
  std::size_t next = 0;
  for (const auto& mask : masks) {
    for (std::size_t i = 0; i < mask.size(); ++i) {
      if (mask.test(i)) current[i] = sent[next++];
    }
    for (int fap : animation.faps) values.push_back(current[static_cast<std::size_t>(fap - 1)]);
  }
  animation.values = toMatrix(values, masks.size(), animation.faps.size());
  return animation;
}

// The header's NAME is one whitespace-free token.
std::string fapName(const std::string& name) {
  if (name.empty()) return Animation{}.name;
  std::string token = name;
  for (char& c : token) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte <= 0x20 || byte == 0x7f) c = '_';
  }
  return token;
}

void writeFap(std::ostream& out, const Animation& animation) {
  // Shortest fixed notation: "30" for a whole rate, "29.97" otherwise; readers expect no exponent.
  out << kFapVersion << ' ' << fapName(animation.name) << ' ' << fixedNotation(animation.framesPerSecond)
      << ' ' << animation.numFrames() << '\n';
  // Every column in every frame, so the mask is the same line each time.
  std::string mask;
  for (int fap = 1; fap <= face::kNumFaps; ++fap) {
    mask += fap > 1 ? " " : "";
    mask += animation.columnOf(fap) >= 0 ? '1' : '0';
  }
  for (int f = 0; f < animation.numFrames(); ++f) {
    out << mask << '\n' << f;
    for (Eigen::Index c = 0; c < animation.values.cols(); ++c) {
      out << ' ' << std::lround(animation.values(f, c));
    }
    out << '\n';
  }
}

// ---- JSON ----

std::string kindOf(const Json& value) {
  switch (value.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::object:
      return "an object";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::string:
      return "a string";
    case Json::value_t::boolean:
      return "a boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
      return "an integer";
    case Json::value_t::number_float:
      return "a number";
    default:
      return "not a JSON value";
  }
}

std::string describe(const Json& value) {
  if (value.is_string()) return "\"" + printable(value.get_ref<const std::string&>()) + "\"";
  if (value.is_number()) return value.dump();  // "1.0" for a float, so "is 1.0, not an integer" reads right
  return kindOf(value);
}

Json parseJsonText(std::string_view text, const fs::path& path) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) throw fileError(path, "is empty");
  const Json::parser_callback_t limitDepth = [&](int depth, Json::parse_event_t event, Json&) {
    if ((event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start) &&
        depth >= kMaxJsonDepth) {
      throw fileError(path, "nests arrays and objects more than " + std::to_string(kMaxJsonDepth) +
                                " deep (an animation needs 3)");
    }
    return true;
  };
  try {
    return Json::parse(text.begin(), text.end(), limitDepth);
  } catch (const Json::out_of_range& e) {
    // nlohmann refuses a number beyond the range of double ("number overflow parsing '1e999'").
    throw fileError(path, "holds a number that is not finite (" + jsonReason(e.what()) + ")");
  } catch (const Json::exception& e) {
    throw fileError(path, "is not valid JSON (" + jsonReason(e.what()) + ")");
  }
}

// Reads the fields of an animation document; every message names the field at fault ("frames[12][3]").
class JsonReader {
 public:
  explicit JsonReader(const fs::path& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw fileError(path_, field + " " + what);
  }

  const Json* find(const Json& object, const std::string& key) const {
    const auto it = object.find(key);
    return it == object.end() ? nullptr : &*it;
  }

  const Json& member(const Json& object, const std::string& key, const std::string& objectField) const {
    const Json* value = find(object, key);
    if (value == nullptr) fail(objectField.empty() ? key : objectField + "." + key, "is missing");
    return *value;
  }

  // Unknown fields are refused: a misspelt "name" must not be dropped without a word.
  void onlyKnownFields(const Json& object, std::initializer_list<std::string_view> known,
                       const std::string& objectField) const {
    for (auto it = object.begin(); it != object.end(); ++it) {
      if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
      std::string list;
      for (std::string_view key : known) list += (list.empty() ? "" : ", ") + std::string(key);
      const std::string field = printable(it.key());
      fail(objectField.empty() ? field : objectField + "." + field,
           "is not a known field (there are " + list + ")");
    }
  }

  const Json& array(const Json& value, const std::string& field) const {
    if (!value.is_array()) fail(field, "is " + kindOf(value) + ", not an array");
    return value;
  }

  const std::string& string(const Json& value, const std::string& field) const {
    if (!value.is_string()) fail(field, "is " + kindOf(value) + ", not a string");
    return value.get_ref<const std::string&>();
  }

  // JSON has no NaN or infinity, and the parser refuses numbers beyond a double: any number is finite.
  double number(const Json& value, const std::string& field) const {
    if (!value.is_number()) fail(field, "is " + describe(value) + ", not a number");
    return value.get<double>();
  }

  int fapNumber(const Json& value, const std::string& field) const {
    // nlohmann reads a non-negative integer as unsigned and a negative one as signed.
    if (value.is_number_unsigned()) {
      const auto number = value.get<std::uint64_t>();
      if (number >= 1 && number <= face::kNumFaps) return static_cast<int>(number);
    }
    if (value.is_number_float()) fail(field, "is " + describe(value) + ", not an integer");
    fail(field, "is " + describe(value) + ", not a FAP number (1.." + std::to_string(face::kNumFaps) + ")");
  }

  Animation read(const Json& document) const {
    if (!document.is_object()) {
      throw fileError(path_, "holds " + kindOf(document) + ", not an animation object");
    }
    onlyKnownFields(document, {"format", "version", "fps", "name", "faps", "time_s", "frames"}, "");
    const Json& format = member(document, "format", "");
    if (!format.is_string() || format.get_ref<const std::string&>() != kJsonFormatName) {
      fail("format", "is " + describe(format) + ", not \"" + std::string(kJsonFormatName) + "\"");
    }
    const Json& version = member(document, "version", "");
    if (!(version.is_number_unsigned() && version.get<std::uint64_t>() == kJsonVersion)) {
      fail("version",
           "is " + describe(version) + "; this program reads version " + std::to_string(kJsonVersion));
    }
    Animation animation;
    animation.framesPerSecond = number(member(document, "fps", ""), "fps");
    if (!(animation.framesPerSecond > 0)) {
      fail("fps", "is " + formatNumber(animation.framesPerSecond) + "; it must be positive");
    }
    if (const Json* name = find(document, "name")) animation.name = string(*name, "name");
    readFaps(array(member(document, "faps", ""), "faps"), animation.faps);
    const Json& frames = array(member(document, "frames", ""), "frames");
    if (frames.empty()) fail("frames", "is empty: no frames");
    // Field names are made only for a message: a file can hold millions of values.
    const auto frameField = [](std::size_t f) { return "frames[" + std::to_string(f) + "]"; };
    std::vector<double> values;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      const Json& row = frames[f];
      if (!row.is_array()) fail(frameField(f), "is " + kindOf(row) + ", not an array");
      if (row.size() != animation.faps.size()) {
        fail(frameField(f), "has " + counted(row.size(), "value") + ", but faps lists " +
                                counted(animation.faps.size(), "FAP"));
      }
      for (std::size_t c = 0; c < row.size(); ++c) {
        if (!row[c].is_number()) {
          fail(frameField(f) + "[" + std::to_string(c) + "]", "is " + describe(row[c]) + ", not a number");
        }
        values.push_back(row[c].get<double>());
      }
    }
    animation.values = toMatrix(values, frames.size(), animation.faps.size());
    if (const Json* times = find(document, "time_s")) {
      checkTimes(array(*times, "time_s"), frames.size(), animation.framesPerSecond);
    }
    return animation;
  }

 private:
  void readFaps(const Json& faps, std::vector<int>& numbers) const {
    for (std::size_t i = 0; i < faps.size(); ++i) {
      const std::string field = "faps[" + std::to_string(i) + "]";
      const Json& entry = faps[i];
      if (!entry.is_object()) fail(field, "is " + kindOf(entry) + ", not an object");
      onlyKnownFields(entry, {"number", "name", "unit"}, field);
      const int number = fapNumber(member(entry, "number", field), field + ".number");
      if (!numbers.empty() && number <= numbers.back()) {
        fail(field + ".number", "is " + std::to_string(number) + ", after " + std::to_string(numbers.back()) +
                                    ": the FAP numbers must be ascending and unique");
      }
      // Name and unit are for people reading the file; if present they must agree with the number, which
      // catches a column renumbered by hand.
      const face::FapDefinition& definition = face::fapDefinition(number);
      if (const Json* name = find(entry, "name");
          name != nullptr && string(*name, field + ".name") != definition.name) {
        fail(field + ".name", "is " + describe(*name) + ", but FAP " + std::to_string(number) + " is \"" +
                                  std::string(definition.name) + "\"");
      }
      const std::string_view unit = face::fapuName(definition.unit);
      if (const Json* given = find(entry, "unit");
          given != nullptr && string(*given, field + ".unit") != unit) {
        fail(field + ".unit", "is " + describe(*given) + ", but FAP " + std::to_string(number) + " is in \"" +
                                  std::string(unit) + "\"");
      }
      numbers.push_back(number);
    }
  }

  // time_s repeats what fps says; a disagreement means one of them was edited without the other.
  void checkTimes(const Json& times, std::size_t numFrames, double framesPerSecond) const {
    if (times.size() != numFrames) {
      fail("time_s",
           "has " + counted(times.size(), "time") + ", but there are " + counted(numFrames, "frame"));
    }
    std::vector<double> seconds;
    for (std::size_t i = 0; i < times.size(); ++i) {
      if (!times[i].is_number()) {
        fail("time_s[" + std::to_string(i) + "]", "is " + describe(times[i]) + ", not a number");
      }
      seconds.push_back(times[i].get<double>());
    }
    if (const std::size_t i = firstUnevenTime(seconds, framesPerSecond); i < seconds.size()) {
      fail("time_s[" + std::to_string(i) + "]",
           "is " + formatNumber(seconds[i]) + ", but at " + formatNumber(framesPerSecond) + " fps frame " +
               std::to_string(i) + " is at " +
               formatNumber(seconds[0] + static_cast<double>(i) / framesPerSecond));
    }
  }

  const fs::path& path_;
};

Animation parseJsonAnimation(std::string_view text, const fs::path& path) {
  const Json document = parseJsonText(text, path);
  try {
    return JsonReader(path).read(document);
  } catch (const Json::exception& e) {
    // Every access in JsonReader checks the type first; this only keeps a missed case from escaping as an
    // nlohmann exception, which callers do not expect.
    throw fileError(path, "is malformed (" + jsonReason(e.what()) + ")");
  }
}

void writeJson(std::ostream& out, const Animation& animation) {
  // Laid out by hand around nlohmann's scalars, so that a frame is one line (dump() would give every number a
  // line of its own). A name that is not UTF-8 has its bad bytes replaced rather than failing the write.
  const auto json = [](const Json& value) {
    return value.dump(-1, ' ', false, Json::error_handler_t::replace);
  };
  out << "{\n  \"format\": " << json(std::string(kJsonFormatName)) << ",\n  \"version\": " << kJsonVersion
      << ",\n  \"fps\": " << json(animation.framesPerSecond) << ",\n  \"name\": " << json(animation.name)
      << ",\n  \"faps\": [";
  for (std::size_t c = 0; c < animation.faps.size(); ++c) {
    const face::FapDefinition& definition = face::fapDefinition(animation.faps[c]);
    const Json entry = {{"number", definition.number},
                        {"name", std::string(definition.name)},
                        {"unit", std::string(face::fapuName(definition.unit))}};
    out << (c > 0 ? ",\n    " : "\n    ") << json(entry);
  }
  out << "\n  ],\n  \"time_s\": [";
  for (int f = 0; f < animation.numFrames(); ++f) {
    out << (f > 0 ? ", " : "") << json(f / animation.framesPerSecond);
  }
  out << "],\n  \"frames\": [";
  for (int f = 0; f < animation.numFrames(); ++f) {
    out << (f > 0 ? ",\n    [" : "\n    [");
    for (Eigen::Index c = 0; c < animation.values.cols(); ++c) {
      out << (c > 0 ? ", " : "") << json(animation.values(f, c));
    }
    out << ']';
  }
  out << "\n  ]\n}\n";
}

}  // namespace

int Animation::columnOf(int fap) const {
  const auto it = std::find(faps.begin(), faps.end(), fap);
  return it == faps.end() ? -1 : static_cast<int>(it - faps.begin());
}

AnimationFormat animationFormatOf(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; });
  if (extension == ".csv") return AnimationFormat::kCsv;
  if (extension == ".json") return AnimationFormat::kJson;
  if (extension == ".fap") return AnimationFormat::kFap;
  throw fileError(path, (extension.empty() ? std::string("has no extension")
                                           : "has the extension '" + printable(extension) + "'") +
                            "; an animation file is .csv, .json or .fap");
}

void writeAnimation(const fs::path& path, const Animation& animation) {
  const AnimationFormat format = animationFormatOf(path);
  checkAnimation(path, animation, format);
  AtomicFile file(path);
  switch (format) {
    case AnimationFormat::kCsv:
      writeCsv(file.stream(), animation);
      break;
    case AnimationFormat::kJson:
      writeJson(file.stream(), animation);
      break;
    case AnimationFormat::kFap:
      writeFap(file.stream(), animation);
      break;
  }
  file.commit();
}

Animation readAnimation(const fs::path& path) {
  const AnimationFormat format = animationFormatOf(path);
  const std::string text = readTextFile(path, "animation file");
  Animation animation;
  switch (format) {
    case AnimationFormat::kCsv:
      animation = parseCsv(text, path);
      break;
    case AnimationFormat::kJson:
      animation = parseJsonAnimation(text, path);
      break;
    case AnimationFormat::kFap:
      animation = parseFap(text, path);
      break;
  }
  checkAnimation(path, animation, format);
  return animation;
}

}  // namespace th::video
