#include "live/settings_file.h"

#include <cstdlib>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_reading.h"

namespace th::app {

std::filesystem::path configFolder() {
  if (const char* config = std::getenv("XDG_CONFIG_HOME"); config != nullptr && *config != '\0')
    return std::filesystem::path(config) / "talkinghead";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".config" / "talkinghead";
  return {};
}

std::filesystem::path defaultLiveSettingsPath() {
  const std::filesystem::path folder = configFolder();
  return folder.empty() ? folder : folder / "live.json";
}

outputs::LiveSessionSettings loadLiveSettings(const std::filesystem::path& path) {
  outputs::LiveSessionSettings settings;
  if (path.empty() || !std::filesystem::exists(path)) return settings;
  const Json document =
      readJsonFile(path, "settings file", {.maxDepth = 4, .depthNote = "settings are one flat object", .subject = ""});
  optionsFromJson(document, settings, path);
  try {
    settings.check();
  } catch (const Error& error) {
    throw fileError(path, error.what());
  }
  return settings;
}

void saveLiveSettings(const std::filesystem::path& path, outputs::LiveSessionSettings settings) {
  if (path.empty()) return;
  std::filesystem::create_directories(path.parent_path());
  AtomicFile out(path);
  out.stream() << optionsToJson(settings).dump(2) << '\n';
  out.commit();
}

}  // namespace th::app
