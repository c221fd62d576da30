#include "head_style_clip.h"

#include <algorithm>
#include <cstdio>
#include <system_error>

#include "audio/audio_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "face/face_model.h"
#include "live/settings_file.h"
#include "tracking/track.h"
#include "tracking/video_training.h"

namespace th::app {

animation::HeadStyle headStyleOfClip(const std::filesystem::path& clip, const animation::HeadModel& model,
                                     std::ostream& log) {
  if (!tracking::isVideoName(clip)) return animation::headStyleFromFile(model, clip);
  // The sound first: a video without it is refused before the (longer) tracking.
  const audio::AudioClip sound = tracking::readClipSound(clip);
  const double seconds = sound.durationSeconds();
  const animation::HeadStyleFitOptions fit;
  if (seconds < fit.minSeconds) {
    throw fileError(clip, std::to_string(static_cast<int>(seconds + 0.5)) + " s long; a head style needs " +
                              std::to_string(static_cast<int>(fit.minSeconds)) + " s at least (20-60 s is best)");
  }
  ProgressBar bar(seconds, "head style: track", log);
  tracking::Track track = tracking::trackVideo(clip, {}, [&](double done) { bar.update(done); });
  bar.finish();
  tracking::fitTrack(track, face::FaceModel::buildDefault());
  animation::HeadRecording recording = tracking::headRecordingOf(track, sound.samples);
  recording.name = clip.string();  // the fit's errors name the file
  animation::HeadStyle style = animation::fitHeadStyle(model, recording, fit);
  style.source = clip.filename().string();
  return style;
}

void resolveHeadStyleClip(pipeline::HeadMotionOptions& head, pipeline::IdleOptions& idle,
                          const pipeline::ModelOptions& models, std::ostream& log) {
  if (head.style.empty() || head.fittedStyle || models.head == "none") return;
  const animation::HeadModel model = animation::loadHeadModel(models.headModelPath());
  pipeline::useHeadStyle(headStyleOfClip(head.style, model, log), head, idle);
  log << "head style " << describeHeadStyle(*head.fittedStyle) << '\n';
}

std::string describeHeadStyle(const animation::HeadStyle& style) {
  const animation::HeadStyleMeasures& person = style.person;
  const animation::HeadStyleMeasures& fitted = style.fitted;
  char text[512];
  std::snprintf(text, sizeof text,
                "%s, %.1f s: spread %.1f / %.1f / %.1f deg (pitch / yaw / roll), p95 speed %.0f deg/s, %.2f beats/s, "
                "pause/speech %.2f; the model styled: gain %.2f / %.2f / %.2f, smoothing %.2f, variation %.2f, "
                "pause gain %.2f, p95 speed %.0f deg/s, %.2f beats/s, pause/speech %.2f, limited to %.0f deg/s",
                style.source.c_str(), person.seconds, person.spread[0], person.spread[1], person.spread[2],
                person.speedP95, person.beatsPerSecond, person.pauseSpeechRatio, style.axisGain[0], style.axisGain[1],
                style.axisGain[2], style.smoothing, style.variation, style.pauseVariation, fitted.speedP95,
                fitted.beatsPerSecond, fitted.pauseSpeechRatio, person.speedP99);
  return text;
}

std::filesystem::path headStyleFolder() {
  const std::filesystem::path folder = configFolder();
  return folder.empty() ? folder : folder / "head-styles";
}

std::vector<std::filesystem::path> listHeadStyles() {
  std::vector<std::filesystem::path> styles;
  const std::filesystem::path folder = headStyleFolder();
  std::error_code error;
  if (folder.empty() || !std::filesystem::is_directory(folder, error)) return styles;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.path().extension() == ".json" && animation::isHeadStyleFile(entry.path())) styles.push_back(entry.path());
  }
  std::sort(styles.begin(), styles.end());
  return styles;
}

}  // namespace th::app
