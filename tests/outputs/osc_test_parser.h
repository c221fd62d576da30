// A reader of OSC datagrams as uOSC (hecomi/uOSC 2.2, Runtime/Core/Parser.cs; the library of EVMC4U and
// VMagicMirror) reads them: bundles and nested bundles, every message with a type tag string, arguments of the
// types it knows (i, f, s; T and F carry no bytes). For the output tests: receivers modelled on their code.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace th::outputs {

struct ParsedArgument {
  char type = 0;
  std::int32_t integer = 0;
  float real = 0.0f;
  std::string text;
  bool flag = false;
};

struct ParsedMessage {
  std::string path;
  std::vector<ParsedArgument> arguments;
};

// uOSC's parser: big-endian words, strings NUL-terminated and padded to 4 bytes. Returns false where uOSC would
// misread (no type tags, a type it does not know, a message running past its element).
class UoscParser {
 public:
  explicit UoscParser(const std::vector<char>& bytes) : bytes_(bytes) {}
  bool parse(std::vector<ParsedMessage>& out) { return element(0, bytes_.size(), out); }

 private:
  bool element(std::size_t at, std::size_t end, std::vector<ParsedMessage>& out) {
    std::string path;
    std::size_t next = at;
    if (!string(next, end, path)) return false;
    if (path == "#bundle") {
      next += 8;  // the time tag (uOSC ignores it)
      while (next < end) {
        std::int32_t size = 0;
        if (!int32(next, end, size) || size < 0 || next + static_cast<std::size_t>(size) > end) return false;
        if (!element(next, next + static_cast<std::size_t>(size), out)) return false;
        next += static_cast<std::size_t>(size);
      }
      return true;
    }
    ParsedMessage message{path, {}};
    std::string types;
    if (!string(next, end, types) || types.empty() || types[0] != ',') return false;
    for (const char type : types.substr(1)) {
      ParsedArgument argument;
      argument.type = type;
      if (type == 'i') {
        if (!int32(next, end, argument.integer)) return false;
      } else if (type == 'f') {
        std::int32_t bits = 0;
        if (!int32(next, end, bits)) return false;
        std::memcpy(&argument.real, &bits, 4);
      } else if (type == 's') {
        if (!string(next, end, argument.text)) return false;
      } else if (type == 'T' || type == 'F') {
        argument.flag = type == 'T';
      } else {
        return false;  // uOSC does not advance past other types: the rest of the message is misread
      }
      message.arguments.push_back(argument);
    }
    out.push_back(std::move(message));
    return next == end;
  }
  bool string(std::size_t& at, std::size_t end, std::string& text) {
    const auto* begin = bytes_.data() + at;
    const std::size_t length = strnlen(begin, end - at);
    if (length == end - at) return false;
    text.assign(begin, length);
    at += (length + 4) / 4 * 4;
    return at <= end;
  }
  bool int32(std::size_t& at, std::size_t end, std::int32_t& value) {
    if (at + 4 > end) return false;
    std::uint32_t word = 0;
    for (int k = 0; k < 4; ++k)
      word = (word << 8) | static_cast<unsigned char>(bytes_[at + static_cast<std::size_t>(k)]);
    value = static_cast<std::int32_t>(word);
    at += 4;
    return true;
  }
  const std::vector<char>& bytes_;
};

}  // namespace th::outputs
