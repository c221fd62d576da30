#include "core/pending_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <utility>

namespace th {

namespace fs = std::filesystem;

PendingFile::PendingFile(fs::path target, bool unnamed) : target_(std::move(target)) {
  folder_ = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  if (unnamed && openUnnamed()) return;
  // The fallback: a named hidden file, created here so that a name clash or a permission problem shows now.
  for (int attempt = 0;; ++attempt) {
    const fs::path candidate = hiddenName(attempt);
    const int created = ::open(candidate.c_str(), O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0666);
    if (created >= 0) {
      ::close(created);
      path_ = candidate;
      named_ = true;
      return;
    }
    if (errno != EEXIST || attempt >= 100) throw cannotWrite(errno);
  }
}

PendingFile::~PendingFile() {
  if (named_ && !committed_) {
    std::error_code ignored;
    fs::remove(path_, ignored);
  }
  if (descriptor_ >= 0) ::close(descriptor_);
}

void PendingFile::commit() {
  fs::path named = path_;
  if (!named_) {  // an unnamed file gets a hidden name first: rename() is what replaces atomically
    for (int attempt = 0;; ++attempt) {
      named = hiddenName(attempt);
      if (::linkat(AT_FDCWD, path_.c_str(), AT_FDCWD, named.c_str(), AT_SYMLINK_FOLLOW) == 0) break;
      if (errno != EEXIST || attempt >= 100) throw cannotWrite(errno);
    }
  }
  if (::rename(named.c_str(), target_.c_str()) != 0) {
    const int code = errno;
    std::error_code ignored;
    fs::remove(named, ignored);
    throw cannotWrite(code);
  }
  committed_ = true;
}

bool PendingFile::openUnnamed() {
  descriptor_ = ::open(folder_.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
  if (descriptor_ < 0) {
    if (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL || errno == ENOENT) return false;
    throw cannotWrite(errno);  // permission denied, read-only, ...
  }
  const std::string procPath = "/proc/self/fd/" + std::to_string(descriptor_);
  const int probe = ::open(procPath.c_str(), O_RDONLY | O_CLOEXEC);
  if (probe < 0) {
    ::close(descriptor_);
    descriptor_ = -1;
    return false;
  }
  ::close(probe);
  path_ = procPath;
  return true;
}

fs::path PendingFile::hiddenName(int attempt) const {
  return folder_ / ("." + target_.filename().string() + "." + std::to_string(::getpid()) + "." +
                    std::to_string(attempt) + ".tmp");
}

Error PendingFile::cannotWrite(int code) const {
  return fileError(target_, "cannot be written: " + std::error_code(code, std::generic_category()).message());
}

}  // namespace th
