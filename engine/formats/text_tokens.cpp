#include "formats/text_tokens.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>

#include "core/error.h"
#include "core/number_parsing.h"

namespace th::formats {
namespace {

constexpr std::string_view kBlanks = " \t\r\v\f";

bool isBlank(char c) {
  return kBlanks.find(c) != std::string_view::npos;
}

}  // namespace

std::string formatNumber(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.9g", value);
  return buffer.data();
}

// printf rounds exactly; at the fewest digits that read back as the same double, it gives to_chars' text for
// every value below 2^53 (above, to_chars pads the shortest digits with zeros where printf writes the exact
// integer). The fallback where the library has no floating-point to_chars (LLVM's before 16: the WebAssembly
// build's).
namespace {

enum class Notation { kFixed, kScientific };

std::string printed(Notation notation, int precision, double value) {
  std::array<char, 768> buffer{};
  const int length = notation == Notation::kFixed
                         ? std::snprintf(buffer.data(), buffer.size(), "%.*f", precision, value)
                         : std::snprintf(buffer.data(), buffer.size(), "%.*e", precision, value);
  return std::string(buffer.data(), static_cast<std::size_t>(std::clamp(length, 0, 767)));
}

// The first precision from 0 at which the text reads back; `most` always does.
std::string fewestDigits(Notation format, double value, int most) {
  for (int precision = 0; precision < most; ++precision) {
    std::string text = printed(format, precision, value);
    if (std::strtod(text.c_str(), nullptr) == value) return text;
  }
  return printed(format, most, value);
}

std::string nonFinite(double value) {
  if (std::isnan(value)) return std::signbit(value) ? "-nan" : "nan";
  return value < 0 ? "-inf" : "inf";
}

}  // namespace

std::string printfShortest(double value) {
  if (!std::isfinite(value)) return nonFinite(value);
  const std::string scientific = fewestDigits(Notation::kScientific, value, 16);
  const std::string fixed = fewestDigits(Notation::kFixed, value, 340);
  return fixed.size() <= scientific.size() ? fixed : scientific;
}

std::string printfFixed(double value, std::optional<int> decimals) {
  if (!std::isfinite(value)) return nonFinite(value);
  return decimals ? printed(Notation::kFixed, *decimals, value) : fewestDigits(Notation::kFixed, value, 340);
}

#if defined(__cpp_lib_to_chars)
std::string shortest(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string fixedNotation(double value, std::optional<int> decimals) {
  // Room for the 309 integer digits of the largest double and the decimals a CSV time can ask for.
  std::array<char, 768> buffer{};
  char* const first = buffer.data();
  char* const last = first + buffer.size();
  const auto result = decimals ? std::to_chars(first, last, value, std::chars_format::fixed, *decimals)
                               : std::to_chars(first, last, value, std::chars_format::fixed);
  return std::string(first, result.ptr);
}
#else
std::string shortest(double value) {
  return printfShortest(value);
}
std::string fixedNotation(double value, std::optional<int> decimals) {
  return printfFixed(value, decimals);
}
#endif

std::optional<double> parseNumber(std::string_view text) {
  return parseWholeNumber<double>(text);
}
std::optional<int> parseInt(std::string_view text) {
  return parseWholeNumber<int>(text);
}
std::optional<long long> parseLong(std::string_view text) {
  return parseWholeNumber<long long>(text);
}

std::string counted(std::size_t count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

std::string fapColumnName(int fap) {
  return "fap" + std::to_string(fap);
}

void failAt(const std::filesystem::path& path, int line, const std::string& what) {
  throw fileError(path, "line " + std::to_string(line) + ": " + what);
}

bool TextLines::nextContent(std::string_view& line, bool skipComments) {
  while (next(line)) {
    const auto first = line.find_first_not_of(kBlanks);
    if (first == std::string_view::npos) continue;
    if (skipComments && line[first] == '#') continue;
    return true;
  }
  return false;
}

bool TextLines::next(std::string_view& line) {
  if (rest_.empty()) return false;
  const auto end = rest_.find('\n');
  line = rest_.substr(0, end);
  rest_ = end == std::string_view::npos ? std::string_view() : rest_.substr(end + 1);
  if (line.ends_with('\r')) line.remove_suffix(1);
  ++number_;
  return true;
}

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

std::size_t firstUnevenTime(const std::vector<double>& times, double framesPerSecond) {
  for (std::size_t i = 1; i < times.size(); ++i) {
    const double expected = times[0] + static_cast<double>(i) / framesPerSecond;
    if (!(std::abs(times[i] - expected) <= kSpacingTolerance / framesPerSecond)) return i;
  }
  return times.size();
}

}  // namespace th::formats
