#include "live_settings.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>

#include "animation_models.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "pipeline/live_presets.h"

namespace th::app {

pipeline::LiveDecoderOptions decoderOptionsOf(const LiveSettings& settings) {
  pipeline::LiveDecoderOptions options;
  options.head.variant =
      settings.headVariant == "paper" ? animation::HeadVariant::kStateMeans : animation::HeadVariant::kTrajectory;
  options.head.maxLagFrames = settings.lagFrames;
  options.mouth.method =
      settings.mouthMethod == "mmse" ? animation::MouthMethod::kMmse : animation::MouthMethod::kInversion;
  options.mouth.windowFrames = settings.windowFrames;
  options.mouth.maxIterations = settings.iterations;
  options.waitForHead = settings.waitForHead;
  options.minF0Hz = settings.minF0Hz;
  options.maxF0Hz = settings.maxF0Hz;
  options.head.smoothing = settings.headSmoothing;
  options.head.variation = settings.headVariation;
  options.head.seed = settings.seed;
  return options;
}

void applyPreset(LiveSettings& settings, const std::string& preset) {
  const pipeline::LivePreset* found = pipeline::findLivePreset(preset);
  if (found == nullptr) {
    std::string names;
    for (const pipeline::LivePreset& p : pipeline::kLivePresets) names += (names.empty() ? "" : ", ") + std::string(p.name);
    throw Error("live: no preset \"" + preset + "\" (there are " + names + ")");
  }
  settings.preset = preset;
  settings.windowFrames = found->windowFrames;
  settings.interpolate = found->interpolate;
}

std::string headModelOf(const LiveSettings& settings) {
  return settings.headModel.empty() ? defaultHeadModel() : settings.headModel;
}

std::string mouthModelOf(const LiveSettings& settings) {
  if (!settings.mouthModel.empty()) return settings.mouthModel;
  const pipeline::LivePreset* preset = pipeline::findLivePreset(settings.preset);
  std::string file(preset != nullptr ? preset->mouthModelFile : pipeline::kLivePresets[0].mouthModelFile);
  if (settings.covariance == "diagonal") file.insert(file.size() - std::string(".json").size(), "_diagonal");
  return std::string(TALKINGHEAD_SOURCE_DIR) + "/models/" + file;
}

std::filesystem::path defaultLiveSettingsPath() {
  if (const char* config = std::getenv("XDG_CONFIG_HOME"); config != nullptr && *config != '\0')
    return std::filesystem::path(config) / "talkinghead" / "live.json";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".config" / "talkinghead" / "live.json";
  return {};
}

namespace {

// One field: taken if present, checked against its range; a wrong type or value names the file and the key.
template <typename T>
void take(const nlohmann::json& document, const char* key, T& value, const std::filesystem::path& path) {
  if (!document.contains(key)) return;
  try {
    value = document.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw fileError(path, std::string("\"") + key + "\" has the wrong type");
  }
}

void requireThat(bool ok, const std::filesystem::path& path, const std::string& what) {
  if (!ok) throw fileError(path, what);
}

}  // namespace

LiveSettings loadLiveSettings(const std::filesystem::path& path) {
  LiveSettings settings;
  if (path.empty() || !std::filesystem::exists(path)) return settings;
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot be read");
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    throw fileError(path, "is not valid JSON (delete it to start from the defaults)");
  }
  requireThat(document.is_object(), path, "is not a JSON object of settings");
  take(document, "preset", settings.preset, path);
  take(document, "device", settings.device, path);
  take(document, "head", settings.headVariant, path);
  take(document, "mouth", settings.mouthMethod, path);
  take(document, "covariance", settings.covariance, path);
  take(document, "head_model", settings.headModel, path);
  take(document, "mouth_model", settings.mouthModel, path);
  take(document, "lag_frames", settings.lagFrames, path);
  take(document, "window_frames", settings.windowFrames, path);
  take(document, "iterations", settings.iterations, path);
  take(document, "wait_for_head", settings.waitForHead, path);
  take(document, "min_f0_hz", settings.minF0Hz, path);
  take(document, "max_f0_hz", settings.maxF0Hz, path);
  take(document, "head_amplitude", settings.headAmplitude, path);
  take(document, "interpolate", settings.interpolate, path);
  take(document, "blinks", settings.blinks, path);
  take(document, "gaze", settings.gaze, path);
  take(document, "idle", settings.idle, path);
  take(document, "head_smoothing", settings.headSmoothing, path);
  take(document, "head_variation", settings.headVariation, path);
  take(document, "blinks_per_minute", settings.blinksPerMinute, path);
  take(document, "seed", settings.seed, path);
  requireThat(pipeline::findLivePreset(settings.preset) != nullptr, path, "\"preset\" names no preset");
  requireThat(settings.headVariant == "trajectory" || settings.headVariant == "paper" || settings.headVariant == "none",
              path, "\"head\" must be trajectory, paper or none");
  requireThat(settings.mouthMethod == "inversion" || settings.mouthMethod == "mmse" || settings.mouthMethod == "none",
              path, "\"mouth\" must be inversion, mmse or none");
  requireThat(settings.covariance == "full" || settings.covariance == "diagonal", path,
              "\"covariance\" must be full or diagonal");
  requireThat(settings.lagFrames >= 0 && settings.lagFrames <= 300, path, "\"lag_frames\" must be 0..300");
  requireThat(settings.windowFrames >= 1 && settings.windowFrames <= 300, path, "\"window_frames\" must be 1..300");
  requireThat(settings.iterations >= 1 && settings.iterations <= 1000, path, "\"iterations\" must be 1..1000");
  requireThat(settings.minF0Hz >= 20.0 && settings.maxF0Hz <= 2000.0 && settings.minF0Hz < settings.maxF0Hz, path,
              "\"min_f0_hz\" and \"max_f0_hz\" must satisfy 20 <= min < max <= 2000");
  requireThat(settings.headAmplitude >= 0.0 && settings.headAmplitude <= 5.0, path, "\"head_amplitude\" must be 0..5");
  requireThat(settings.headSmoothing >= 0.1 && settings.headSmoothing <= 10.0, path, "\"head_smoothing\" must be 0.1..10");
  requireThat(settings.headVariation >= 0.0 && settings.headVariation <= 3.0, path, "\"head_variation\" must be 0..3");
  requireThat(settings.blinksPerMinute >= 1.0 && settings.blinksPerMinute <= 60.0, path,
              "\"blinks_per_minute\" must be 1..60");
  return settings;
}

void saveLiveSettings(const std::filesystem::path& path, const LiveSettings& settings) {
  if (path.empty()) return;
  std::filesystem::create_directories(path.parent_path());
  const nlohmann::json document = {
      {"preset", settings.preset},           {"device", settings.device},
      {"head", settings.headVariant},
      {"mouth", settings.mouthMethod},       {"covariance", settings.covariance},
      {"head_model", settings.headModel},
      {"mouth_model", settings.mouthModel},  {"lag_frames", settings.lagFrames},
      {"window_frames", settings.windowFrames}, {"iterations", settings.iterations},
      {"wait_for_head", settings.waitForHead}, {"min_f0_hz", settings.minF0Hz},
      {"max_f0_hz", settings.maxF0Hz},       {"head_amplitude", settings.headAmplitude},
      {"interpolate", settings.interpolate}, {"blinks", settings.blinks},
      {"gaze", settings.gaze},               {"idle", settings.idle},
      {"head_smoothing", settings.headSmoothing}, {"head_variation", settings.headVariation},
      {"blinks_per_minute", settings.blinksPerMinute}, {"seed", settings.seed}};
  AtomicFile out(path);
  out.stream() << document.dump(2) << '\n';
  out.commit();
}

}  // namespace th::app
