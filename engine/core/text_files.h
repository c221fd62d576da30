// Reading a whole text file that the engine parses (model files, animation files), with errors that say which
// file and what is wrong in one line, and a cap so a huge or endless input (a pipe) cannot exhaust memory; and
// the pieces of such errors that quote the file.
//
//   const std::string text = th::readTextFile(path, "model file");   // "PATH: is a directory, not a model file"
//   throw th::fileError(path, "unknown key \"" + th::printable(key) + "\"");
//
// Thread contract: pure functions.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace th {

inline constexpr std::size_t kMaxTextFileBytes = std::size_t{1} << 30;

// The file's bytes. `kind` names what the file should be ("model file"), for the messages: missing,
// a directory, unreadable, or larger than kMaxTextFileBytes (read in chunks, so the cap holds for pipes too).
std::string readTextFile(const std::filesystem::path& path, std::string_view kind);

// Text from a file (keys, names) in an error message: one line (control characters as '?'), cut at
// maxLength with "...".
std::string printable(std::string_view text, std::size_t maxLength = 40);

// An nlohmann exception's message without its "[json.exception.parse_error.101] " tag and without the raw
// bytes it quotes ("; last read: '...'" can be long), on one line.
std::string jsonReason(const std::string& what);

// A file name's extension in lower case, with its dot (".MP4" -> ".mp4"; "" if it has none): for choosing a
// reader or checking an output's kind by name.
std::string lowercaseExtension(const std::filesystem::path& path);

}  // namespace th
