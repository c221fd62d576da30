#include "core/data_path.h"

#include <cstdlib>

namespace th {

std::filesystem::path sharedDataDir() {
  if (const char* fromEnvironment = std::getenv("TALKINGHEAD_DATA"); fromEnvironment && *fromEnvironment) {
    return fromEnvironment;
  }
  return TALKINGHEAD_DEFAULT_DATA_DIR;
}

std::filesystem::path sharedDataPath(const std::filesystem::path& relative) {
  return sharedDataDir() / relative;
}

}  // namespace th
