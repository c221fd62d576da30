// cameraModule(): libtalkinghead_camera.so opened on first use (camera_module.h).
#include <dlfcn.h>

#include <algorithm>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "tracking/camera_module.h"

namespace th::tracking {
namespace {

constexpr const char* kModuleFile = "libtalkinghead_camera.so";

std::vector<std::filesystem::path> modulePlaces() {
  std::vector<std::filesystem::path> places;
  std::error_code error;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    places.push_back(program.parent_path() / kModuleFile);
    places.push_back(program.parent_path().parent_path() / TALKINGHEAD_CAMERA_MODULE_INSTALLED / kModuleFile);
  }
  const std::filesystem::path built(TALKINGHEAD_CAMERA_MODULE_BUILT);
  if (std::find(places.begin(), places.end(), built) == places.end()) places.push_back(built);
  return places;
}

const CameraModule& openModule() {
  std::string tried;
  for (const std::filesystem::path& place : modulePlaces()) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(place, error)) {
      tried += (tried.empty() ? "" : ", ") + place.string();
      continue;
    }
    // Never closed: the devices and writers it makes have their code there.
    void* module = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr) {
      const char* reason = dlerror();
      throw fileError(place, std::string("cannot be loaded (") + (reason != nullptr ? reason : "unknown error") + ")");
    }
    const auto entry = reinterpret_cast<CameraModuleEntry>(dlsym(module, TALKINGHEAD_CAMERA_MODULE_ENTRY));
    const CameraModule* loaded = entry != nullptr ? entry() : nullptr;
    if (loaded == nullptr || loaded->openCamera == nullptr)
      throw fileError(place, "is not talkinghead's camera module");
    return *loaded;
  }
  throw Error(std::string("the camera module ") + kModuleFile + " is missing (looked in " + tried + ")");
}

}  // namespace

const CameraModule& cameraModule() {
  static const CameraModule& module = openModule();
  return module;
}

}  // namespace th::tracking
