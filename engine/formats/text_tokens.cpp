#include "formats/text_tokens.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
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
