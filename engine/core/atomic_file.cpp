#include "core/atomic_file.h"

#include <unistd.h>

#include <system_error>

#include "core/error.h"

namespace th {

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  if (std::filesystem::is_directory(target_)) throw fileError(target_, "is a directory");
  // Renaming onto a device, pipe or socket would replace it with a plain file (think /dev/null).
  std::error_code status;
  if (std::filesystem::exists(target_, status) && !std::filesystem::is_regular_file(target_, status))
    throw fileError(target_, "exists and is not a regular file");
  const auto parent = target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(parent)) throw fileError(target_, "the folder it should go in does not exist");
  temporary_ = parent / ("." + target_.filename().string() + ".tmp" + std::to_string(::getpid()));
  stream_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!stream_) throw fileError(target_, "cannot be written (permission denied or read-only location)");
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    stream_.close();
    std::error_code ignored;
    std::filesystem::remove(temporary_, ignored);
  }
}

void AtomicFile::commit() {
  stream_.flush();
  const bool good = static_cast<bool>(stream_);
  stream_.close();
  if (!good || stream_.fail()) throw fileError(target_, "write failed (disk full?)");
  std::error_code error;
  std::filesystem::rename(temporary_, target_, error);
  if (error) throw fileError(target_, "cannot be written: " + error.message());
  committed_ = true;
}

void checkOutputTarget(const std::filesystem::path& target) {
  const std::filesystem::path folder = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) throw fileError(target, "its folder does not exist");
  if (std::filesystem::is_directory(target, error)) throw fileError(target, "is a folder");
  if (std::filesystem::exists(target, error) && !std::filesystem::is_regular_file(target, error))
    throw fileError(target, "exists and is not a regular file");
}

}  // namespace th
