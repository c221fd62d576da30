#include "core/temporary_file.h"

#include <unistd.h>

#include <atomic>
#include <system_error>

namespace th {

TemporaryFile::TemporaryFile(const std::string& suffix) {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("talkinghead-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + suffix);
}

TemporaryFile::~TemporaryFile() {
  std::error_code ignored;
  std::filesystem::remove(path_, ignored);
}

}  // namespace th
