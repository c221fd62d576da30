// What the text animation formats share (formats/*_format.cpp, not a public API): numbers written so they read
// back exactly, lines and fields of a text read without copying, and evenly spaced frame times.
//
//   th::formats::TextLines lines(text);
//   std::string_view line;
//   while (lines.nextContent(line, /*skipComments=*/true)) { Fields f = splitWhitespace(line, 68); ... }
//
// Thread contract: pure functions; a TextLines belongs to one thread.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace th::formats {

// Times may stray from even spacing by this fraction of a frame period: far more than the rounding of a
// printed time, far less than a dropped or repeated frame.
inline constexpr double kSpacingTolerance = 1e-4;

std::string formatNumber(double value);  // short, with enough digits to tell values within the tolerance apart
std::string shortest(double value);      // the shortest text that reads back as the same double
// Fixed notation (no exponent): shortest round-trip, or with `decimals` digits after the point.
std::string fixedNotation(double value, std::optional<int> decimals = std::nullopt);
// The same by printf, for a standard library without floating-point to_chars (equal below 2^53).
std::string printfShortest(double value);
std::string printfFixed(double value, std::optional<int> decimals = std::nullopt);
std::optional<double> parseNumber(std::string_view text);  // the whole text, or nothing
std::optional<int> parseInt(std::string_view text);
std::optional<long long> parseLong(std::string_view text);
std::string counted(std::size_t count, const std::string& noun);  // "1 value", "2 values"
std::string fapColumnName(int fap);                               // "fap48"

[[noreturn]] void failAt(const std::filesystem::path& path, int line, const std::string& what);

// Lines of a text, numbered from 1, without their "\n" or "\r\n".
class TextLines {
 public:
  explicit TextLines(std::string_view text) : rest_(text) {}
  // The next line holding more than whitespace (and, with skipComments, not starting with '#').
  bool nextContent(std::string_view& line, bool skipComments);
  int number() const { return number_; }

 private:
  bool next(std::string_view& line);
  std::string_view rest_;
  int number_ = 0;  // a text file is at most kMaxTextFileBytes, so its lines fit an int
};

// The fields of a line. Only the first `keep` are stored (a line of a forged file can hold millions); all are
// counted, for the message that says how many there were.
struct Fields {
  std::vector<std::string_view> items;
  std::size_t count = 0;
};
Fields splitWhitespace(std::string_view line, std::size_t keep);
Fields splitCommas(std::string_view line, std::size_t keep);  // each field trimmed of blanks

// The index of the first time off even spacing at this rate (counted from the first time), or times.size().
std::size_t firstUnevenTime(const std::vector<double>& times, double framesPerSecond);

}  // namespace th::formats
