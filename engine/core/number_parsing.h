// A whole text as a number, as std::from_chars reads it (no leading blank or '+', C locale), for every standard
// library the project builds with: the WebAssembly build's (libc++) has no from_chars for floating point, so
// there it is strtod's reading of the same text, which is correctly rounded too.
//
//   const std::optional<double> gain = th::parseWholeNumber<double>("0.25");
//
// Thread contract: pure functions.
#pragma once

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

namespace th {

// The number the whole of `text` is, or nothing (empty, trailing characters, out of the type's range).
template <typename Number>
std::optional<Number> parseWholeNumber(std::string_view text) {
  if (text.empty()) return std::nullopt;
#if defined(__cpp_lib_to_chars)
  constexpr bool kFromCharsReadsFloats = true;
#else
  constexpr bool kFromCharsReadsFloats = false;
#endif
  if constexpr (std::is_floating_point_v<Number> && !kFromCharsReadsFloats) {
    // from_chars's grammar: an optional '-', then digits, "inf" or "nan"; no blanks, '+' or hexadecimal prefix.
    const std::string_view body = text.front() == '-' ? text.substr(1) : text;
    if (body.empty() || body.front() == '+' || body.front() == '-' ||
        (!std::isdigit(static_cast<unsigned char>(body.front())) && body.front() != '.' && body.front() != 'i' &&
         body.front() != 'I' && body.front() != 'n' && body.front() != 'N') ||
        (body.size() > 1 && body[0] == '0' && (body[1] == 'x' || body[1] == 'X')))
      return std::nullopt;
    const std::string copy(text);
    char* end = nullptr;
    errno = 0;
    const double parsed = std::strtod(copy.c_str(), &end);
    if (end != copy.c_str() + copy.size() || errno == ERANGE) return std::nullopt;
    return static_cast<Number>(parsed);
  } else {
    Number value{};
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
  }
}

}  // namespace th
