#include "core/text_files.h"

#include <cctype>
#include <fstream>
#include <system_error>
#include <vector>

#include "core/error.h"

namespace th {

std::string readTextFile(const std::filesystem::path& path, std::string_view kind) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    if (error && error != std::errc::no_such_file_or_directory && error != std::errc::not_a_directory) {
      throw fileError(path, "cannot be read: " + error.message());
    }
    throw fileError(path, "does not exist");
  }
  if (std::filesystem::is_directory(status))
    throw fileError(path,
                    "is a directory, not a" + std::string(kind.starts_with('a') ? "n " : " ") + std::string(kind));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fileError(path, "cannot be read (permission denied?)");
  std::string text;
  std::vector<char> buffer(std::size_t{1} << 16);
  // Chunks, not the size from stat: a pipe has none, and a file larger than the cap is refused before it is all
  // in memory.
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
    text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxTextFileBytes)
      throw fileError(path, "is larger than 1 GiB, which no " + std::string(kind) + " is");
  }
  if (in.bad()) throw fileError(path, "cannot be read (an I/O error)");
  return text;
}

std::string printable(std::string_view text, std::size_t maxLength) {
  std::string out;
  for (char c : text.substr(0, maxLength)) {
    const auto byte = static_cast<unsigned char>(c);
    out += byte < 0x20 || byte == 0x7f ? '?' : c;
  }
  if (text.size() > maxLength) out += "...";
  return out;
}

std::string jsonReason(const std::string& what) {
  std::string_view reason = what;
  if (const auto tagEnd = reason.find("] "); reason.starts_with("[json.exception.") && tagEnd != reason.npos) {
    reason.remove_prefix(tagEnd + 2);
  }
  if (const auto lastRead = reason.find("; last read"); lastRead != reason.npos) reason = reason.substr(0, lastRead);
  return printable(reason, 200);
}

std::string lowercaseExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

}  // namespace th
