// libtalkinghead's C API (include/talkinghead/talkinghead.h) over the engine: a stream is live's stream decoder
// (pipeline/live_decoder.h: makeStreamDecoder); an animation is the offline path (pipeline/offline.h); an export
// is pipeline/recording_export.h's; frames are the live outputs' AvatarFrame (outputs/avatar_frame.h) in C's
// shape; an animation on a character is avatar/avatar_animation.h's tracks written by formats/gltf_animation.h.
// No C++ exception crosses the API. The caller's structs are read and written only as far as their struct_size.
#include "talkinghead/talkinghead.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <string>

#include "audio/media_audio.h"
#include "avatar/avatar_animation.h"
#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "capi_support.h"
#include "core/error.h"
#include "face/face_model.h"
#include "formats/animation_format.h"
#include "formats/arkit_format.h"
#include "formats/gltf_animation.h"
#include "outputs/avatar_frame.h"
#include "outputs/live_display.h"
#include "pipeline/head_style_source.h"
#include "pipeline/live_decoder.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"
#include "pipeline/recording_export.h"

namespace {

thread_local std::string lastError;

}  // namespace

th_status th::capi::fail(th_status status, std::string message) {
  lastError = std::move(message);
  return status;
}

using namespace th::capi;

namespace {

// Runs `body`, turning what it throws into a status and the thread's message.
template <typename Body>
th_status guarded(th_status onError, Body&& body) {
  try {
    body();
    return TH_OK;
  } catch (const th::Cancelled& cancelled) {
    return fail(TH_ERROR_CANCELLED, cancelled.what());
  } catch (const th::Error& error) {
    return fail(onError, error.what());
  } catch (const std::bad_alloc&) {
    return fail(TH_ERROR_INTERNAL, "out of memory");
  } catch (const std::exception& error) {
    return fail(TH_ERROR_INTERNAL, error.what());
  }
}

th_export_options defaultExportOptions() {
  const th::pipeline::VideoExportOptions video;
  th_export_options options{};
  options.struct_size = sizeof(th_export_options);
  options.width = video.width;
  options.height = video.height;
  options.frames_per_second = video.framesPerSecond;
  options.crf = video.crf;
  return options;
}

// A frame written into the caller's, as far as its struct_size reaches.
bool writeSized(const th_frame& frame, th_frame* into, const char* function) {
  if (into->struct_size < kFirstFrameSize) {
    fail(TH_ERROR_ARGUMENT, std::string(function) + ": frame->struct_size " + std::to_string(into->struct_size) +
                                " is smaller than th_frame's first version (" + std::to_string(kFirstFrameSize) +
                                "): set it with th_frame_init");
    return false;
  }
  const std::size_t size = std::min(into->struct_size, sizeof(th_frame));
  std::memcpy(reinterpret_cast<char*>(into) + sizeof(std::size_t),
              reinterpret_cast<const char*>(&frame) + sizeof(std::size_t), size - sizeof(std::size_t));
  return true;
}

// The cancel check the engine takes from a C progress callback: fraction done in, true to stop.
std::function<bool(double)> progressOf(th_progress_fn progress, void* userData) {
  if (progress == nullptr) return {};
  return [progress, userData](double fraction) { return progress(fraction, userData) != 0; };
}

// The models the options name (NULL: the installed ones; "": that part off).
th::pipeline::LiveSettings settingsOf(const th_models_options& options) {
  th::pipeline::LiveSettings settings;
  const auto choose = [](const char* given, std::string& path, std::string& variant, const char* off) {
    if (given == nullptr) return;
    if (*given == '\0')
      variant = off;
    else
      path = given;
  };
  choose(options.head_model, settings.models.headModel, settings.models.head, "none");
  choose(options.mouth_model, settings.models.mouthModel, settings.models.mouth, "none");
  if (options.viseme_model != nullptr) {
    settings.models.visemeModel = *options.viseme_model ? options.viseme_model : "none";
    // The visemes come from the articulation unless it is off: a viseme model named, or none, turns it off.
    settings.models.articulationModel = "none";
  }
  if (options.head_style != nullptr) settings.head.style = options.head_style;
  return settings;
}

// The head style the settings name, read or fitted for the loaded head model (none without one).
void resolveStyle(th::pipeline::LiveSettings& settings, const th::pipeline::AnimationModels& models) {
  if (models.head) th::pipeline::resolveHeadStyle(settings.head, settings.idle, *models.head);
}

th_frame frameOf(const th::outputs::AvatarFrame& avatar) {
  th_frame frame{};
  frame.struct_size = sizeof(th_frame);
  frame.index = avatar.index;
  frame.time_seconds = avatar.timeSeconds;
  for (int fap = 1; fap <= TH_NUM_FAPS; ++fap)
    frame.faps[fap] = static_cast<float>(avatar.faps[static_cast<std::size_t>(fap)]);
  for (int k = 0; k < TH_NUM_ARKIT; ++k) frame.arkit[k] = avatar.arkit[static_cast<std::size_t>(k)];
  for (int k = 0; k < TH_NUM_VISEMES; ++k) frame.visemes[k] = avatar.oculus[static_cast<std::size_t>(k)];
  for (int k = 0; k < TH_NUM_VRM; ++k) frame.vrm[k] = avatar.vrm[static_cast<std::size_t>(k)];
  frame.viseme = avatar.hasVisemes ? th::face::oculusVisemeOf(avatar.mouthClass) : -1;
  frame.rhubarb_shape = avatar.hasVisemes ? th::face::rhubarbShapeOf(avatar.mouthClass) : 'X';
  frame.head_pitch_deg = static_cast<float>(avatar.headDegrees[0]);
  frame.head_yaw_deg = static_cast<float>(avatar.headDegrees[1]);
  frame.head_roll_deg = static_cast<float>(avatar.headDegrees[2]);
  const Eigen::Quaternionf unity = avatar.unityHeadRotation();
  frame.head_rotation_unity[0] = unity.x();
  frame.head_rotation_unity[1] = unity.y();
  frame.head_rotation_unity[2] = unity.z();
  frame.head_rotation_unity[3] = unity.w();
  return frame;
}

// A recording animated offline, reporting its start and end: the offline animation is one step.
th::face::FapTrack animateWithProgress(const char* recording, const th::pipeline::AnimationModels& models,
                                       const th::pipeline::LiveSettings& settings,
                                       const std::function<bool(double)>& cancelled) {
  if (cancelled && cancelled(0.0)) throw th::Cancelled();
  th::face::FapTrack track = th::pipeline::animateRecording(
      recording, models, th::pipeline::animateOptionsOf(settings.models, settings.head, settings.idle));
  if (cancelled && cancelled(1.0)) throw th::Cancelled();
  return track;
}

}  // namespace

// The stream models (live's: its mouth model and articulation) loaded at once, the file models (the offline
// path's) on first use; both shared, so that streams and exports keep what they use after the handle is freed.
// (A handle th_animate makes for one recording holds the file models alone.)
struct th_models {
  th::pipeline::LiveSettings settings;
  std::shared_ptr<const th::pipeline::AnimationModels> stream;
  mutable std::once_flag fileLoaded;
  mutable std::shared_ptr<const th::pipeline::AnimationModels> file;

  const std::shared_ptr<const th::pipeline::AnimationModels>& fileModels() const {
    std::call_once(fileLoaded, [this] {
      file = std::make_shared<const th::pipeline::AnimationModels>(th::pipeline::loadModels(settings.models));
    });
    return file;
  }
};

struct th_stream {
  std::unique_ptr<th::pipeline::FrameDecoder> decoder;
  // Blinks, gaze and the head at rest in pauses, as live's window and headless lay them over their frames.
  std::unique_ptr<th::outputs::LiveDisplay> display;
  th::pipeline::DecoderLookahead lookahead;
  bool finished = false;
};

struct th_animation {
  th::face::FapTrack track;
};

namespace th::capi {

th_status checkRate(double rate, const char* function) {
  if (rate >= 8000.0 && rate <= 192000.0) return TH_OK;
  return fail(TH_ERROR_ARGUMENT,
              std::string(function) + ": the sample rate " + std::to_string(rate) + " Hz is not 8000..192000");
}

th_status loadModelsHandle(const th_models_options* options, ReadNow readNow, const char* function,
                           th_models** models) {
  if (models == nullptr) return fail(TH_ERROR_ARGUMENT, std::string(function) + ": models is NULL");
  *models = nullptr;
  const std::optional<th_models_options> known =
      readSized(options, defaultModelsOptions(), kFirstModelsOptionsSize, function);
  if (!known) return TH_ERROR_ARGUMENT;
  return guarded(TH_ERROR_FILE, [&] {
    auto opened = std::make_unique<th_models>();
    opened->settings = settingsOf(*known);
    if (readNow == ReadNow::streamModels) {
      opened->stream =
          std::make_shared<const th::pipeline::AnimationModels>(th::pipeline::loadModels(opened->settings));
      resolveStyle(opened->settings, *opened->stream);
    } else {
      resolveStyle(opened->settings, *opened->fileModels());
    }
    *models = opened.release();
  });
}

}  // namespace th::capi

namespace {

th_status openStream(const th::pipeline::LiveSettings& settings,
                     std::shared_ptr<const th::pipeline::AnimationModels> models, const th_stream_settings& given,
                     th_stream** stream) {
  const double rate = given.sample_rate_hz;
  return guarded(TH_ERROR_FILE, [&] {
    th::pipeline::LiveDecoderOptions decoderOptions = settings.decoderOptions();
    decoderOptions.waitForHead = given.wait_for_head != 0;
    th::pipeline::StreamDecoder made = th::pipeline::makeStreamDecoder(std::move(models), decoderOptions, rate);
    auto opened = std::make_unique<th_stream>();
    opened->decoder = std::move(made.decoder);
    opened->lookahead = made.lookahead;
    opened->display =
        std::make_unique<th::outputs::LiveDisplay>(settings.idle, settings.live.blinks, settings.live.gaze);
    *stream = opened.release();
  });
}

}  // namespace

extern "C" {

const char* th_version(void) {
  return TALKINGHEAD_VERSION;
}

const char* th_last_error(void) {
  return lastError.c_str();
}

th_status th_frame_init_sized(th_frame* frame, size_t struct_size) {
  th_frame defaults{};
  defaults.struct_size = sizeof(th_frame);
  return initSized(frame, struct_size, defaults, kFirstFrameSize, "th_frame_init");
}

th_status th_models_options_init_sized(th_models_options* options, size_t struct_size) {
  return initSized(options, struct_size, defaultModelsOptions(), kFirstModelsOptionsSize, "th_models_options_init");
}

th_status th_stream_settings_init_sized(th_stream_settings* settings, size_t struct_size) {
  return initSized(settings, struct_size, defaultStreamSettings(), kFirstStreamSettingsSize, "th_stream_settings_init");
}

th_status th_animate_options_init_sized(th_animate_options* options, size_t struct_size) {
  return initSized(options, struct_size, defaultAnimateOptions(), kFirstAnimateOptionsSize, "th_animate_options_init");
}

th_status th_export_options_init_sized(th_export_options* options, size_t struct_size) {
  return initSized(options, struct_size, defaultExportOptions(), kFirstExportOptionsSize, "th_export_options_init");
}

th_status th_models_load(const th_models_options* options, th_models** models) {
  return loadModelsHandle(options, ReadNow::streamModels, "th_models_load", models);
}

void th_models_free(th_models* models) {
  delete models;
}

th_status th_stream_start(const th_models* models, const th_stream_settings* settings, th_stream** stream) {
  if (stream == nullptr) return fail(TH_ERROR_ARGUMENT, "th_stream_start: stream is NULL");
  *stream = nullptr;
  const std::optional<th_stream_settings> known =
      readSized(settings, defaultStreamSettings(), kFirstStreamSettingsSize, "th_stream_start");
  if (!known) return TH_ERROR_ARGUMENT;
  if (checkRate(known->sample_rate_hz, "th_stream_start") != TH_OK) return TH_ERROR_ARGUMENT;  // before any model
  if (models != nullptr) return openStream(models->settings, models->stream, *known, stream);
  // The installed models, read for this stream, which outlives the handle.
  th_models* own = nullptr;
  if (const th_status loaded = th_models_load(nullptr, &own); loaded != TH_OK) return loaded;
  const th_status started = openStream(own->settings, own->stream, *known, stream);
  th_models_free(own);
  return started;
}

th_status th_stream_push(th_stream* stream, const float* samples, size_t count) {
  if (stream == nullptr || (samples == nullptr && count > 0))
    return fail(TH_ERROR_ARGUMENT, "th_stream_push: stream or samples is NULL");
  if (stream->finished) return fail(TH_ERROR_STATE, "th_stream_push: the stream was finished");
  return guarded(TH_ERROR_INTERNAL, [&] { stream->decoder->acceptWaveform({samples, count}); });
}

th_status th_stream_finish(th_stream* stream) {
  if (stream == nullptr) return fail(TH_ERROR_ARGUMENT, "th_stream_finish: stream is NULL");
  if (stream->finished) return TH_OK;
  stream->finished = true;
  return guarded(TH_ERROR_INTERNAL, [&] { stream->decoder->inputFinished(); });
}

int th_stream_pull(th_stream* stream, th_frame* frame) {
  if (stream == nullptr || frame == nullptr) {
    fail(TH_ERROR_ARGUMENT, "th_stream_pull: stream or frame is NULL");
    return -1;
  }
  if (frame->struct_size < kFirstFrameSize) return writeSized({}, frame, "th_stream_pull") ? 0 : -1;
  int got = 0;
  const th_status status = guarded(TH_ERROR_INTERNAL, [&] {
    th::pipeline::AnimationFrame decoded;
    if (!stream->decoder->next(decoded)) return;
    // The stream's own time: the same at any pace.
    got = writeSized(frameOf(stream->display->present(decoded, decoded.timeSeconds)), frame, "th_stream_pull") ? 1 : -1;
  });
  return status == TH_OK ? got : -1;
}

double th_stream_latency_ms(const th_stream* stream) {
  return stream == nullptr ? 0.0 : stream->lookahead.totalMs;
}

void th_stream_close(th_stream* stream) {
  delete stream;
}

th_status th_animate(const th_models* models, const char* recording, const th_animate_options* options,
                     th_animation** animation) {
  if (recording == nullptr || animation == nullptr)
    return fail(TH_ERROR_ARGUMENT, "th_animate: recording or animation is NULL");
  *animation = nullptr;
  const std::optional<th_animate_options> known =
      readSized(options, defaultAnimateOptions(), kFirstAnimateOptionsSize, "th_animate");
  if (!known) return TH_ERROR_ARGUMENT;
  if (models == nullptr) {
    // The installed file models, read for this recording alone (not the stream models it would not use).
    th_models* own = nullptr;
    if (const th_status loaded = loadModelsHandle(nullptr, ReadNow::fileModels, "th_animate", &own); loaded != TH_OK)
      return loaded;
    const th_status animated = th_animate(own, recording, &*known, animation);
    th_models_free(own);
    return animated;
  }
  return guarded(TH_ERROR_FILE, [&] {
    auto made = std::make_unique<th_animation>();
    made->track = animateWithProgress(recording, *models->fileModels(), models->settings,
                                      progressOf(known->progress, known->user_data));
    *animation = made.release();
  });
}

int th_animation_frames(const th_animation* animation) {
  return animation == nullptr ? 0 : animation->track.numFrames();
}

th_status th_animation_frame(const th_animation* animation, int index, th_frame* frame) {
  if (animation == nullptr || frame == nullptr) return fail(TH_ERROR_ARGUMENT, "th_animation_frame: a NULL argument");
  if (frame->struct_size < kFirstFrameSize)
    return writeSized({}, frame, "th_animation_frame") ? TH_OK : TH_ERROR_ARGUMENT;
  if (index < 0 || index >= animation->track.numFrames())
    return fail(TH_ERROR_ARGUMENT, "th_animation_frame: frame " + std::to_string(index) + " is not 0.." +
                                       std::to_string(animation->track.numFrames() - 1));
  return guarded(TH_ERROR_INTERNAL, [&] {
    const th::face::FapTrack& track = animation->track;
    th::pipeline::AnimationFrame decoded;
    decoded.index = index;
    decoded.timeSeconds = index / track.framesPerSecond;
    decoded.faps = track.frame(index);
    if (!track.visemes.empty()) {
      decoded.visemeIndex = index;
      decoded.mouthClass = track.visemes.classes[static_cast<std::size_t>(index)];
      for (int c = 0; c < th::face::kNumMouthClasses; ++c)
        decoded.visemeProbabilities[static_cast<std::size_t>(c)] =
            static_cast<float>(track.visemes.posteriors(c, index));
    }
    if (!writeSized(frameOf(th::outputs::avatarFrameOf(decoded)), frame, "th_animation_frame"))
      throw th::Error(th_last_error());
  });
}

th_status th_animation_write(const th_animation* animation, const char* path, const char* format) {
  if (animation == nullptr || path == nullptr) return fail(TH_ERROR_ARGUMENT, "th_animation_write: a NULL argument");
  return guarded(TH_ERROR_FILE, [&] {
    th::formats::writeAnimation(path, animation->track,
                                th::formats::formatForWriting(path, format != nullptr ? format : ""));
  });
}

th_status th_animation_write_avatar(const th_animation* animation, const char* avatar, const char* path,
                                    int animation_only) {
  if (animation == nullptr || avatar == nullptr || path == nullptr)
    return fail(TH_ERROR_ARGUMENT, "th_animation_write_avatar: a NULL argument");
  return guarded(TH_ERROR_FILE, [&] {
    th::avatar::checkAvatarAnimationOutput(avatar, path, animation_only != 0);
    th::avatar::writeSpeechOnAvatar(avatar, th::avatar::loadAvatar(avatar), animation->track, path,
                                    animation_only != 0);
  });
}

void th_animation_free(th_animation* animation) {
  delete animation;
}

th_status th_export(const char* recording, const char* mp4, const th_export_options* options) {
  if (recording == nullptr || mp4 == nullptr) return fail(TH_ERROR_ARGUMENT, "th_export: a NULL argument");
  const std::optional<th_export_options> known =
      readSized(options, defaultExportOptions(), kFirstExportOptionsSize, "th_export");
  if (!known) return TH_ERROR_ARGUMENT;
  const int width = known->width, height = known->height;
  if (width < 16 || height < 16 || width > 7680 || height > 4320 || width % 2 != 0 || height % 2 != 0)
    return fail(TH_ERROR_ARGUMENT, "th_export: the size must be even, 16x16 to 7680x4320");
  if (!(known->frames_per_second >= 1.0 && known->frames_per_second <= 120.0))
    return fail(TH_ERROR_ARGUMENT, "th_export: frames_per_second must be 1..120");
  if (known->crf < 0 || known->crf > 51) return fail(TH_ERROR_ARGUMENT, "th_export: crf must be 0..51");
  return guarded(TH_ERROR_FILE, [&] {
    // The character first: a bad file fails before any work.
    std::optional<th::avatar::Avatar> character;
    if (known->avatar != nullptr) {
      character = th::avatar::loadAvatar(known->avatar);
      th::avatar::rigAvatar(*character);  // throws, naming it, when nothing in it can be driven
    }
    th::pipeline::RecordingExport job;
    job.recording = recording;
    job.output = mp4;
    job.video.width = width;
    job.video.height = height;
    job.video.framesPerSecond = known->frames_per_second;
    job.video.crf = known->crf;
    job.video.avatar = character ? &*character : nullptr;
    if (known->models != nullptr) {
      job.models = known->models->settings.models;
      job.head = known->models->settings.head;  // its head style among them
      job.idle = known->models->settings.idle;
      job.loadedModels = known->models->fileModels();
    }
    const std::function<bool(double)> cancelled = progressOf(known->progress, known->user_data);
    double fraction = 0.0;
    th::pipeline::RecordingExportHooks hooks;
    if (cancelled) {
      hooks.progress = [&](int done, int total) { fraction = total > 0 ? static_cast<double>(done) / total : 1.0; };
      hooks.cancelled = [&] { return cancelled(fraction); };
    }
    th::pipeline::exportRecording(job, hooks);
    // The file is whole now; a last report, which can no longer cancel.
    if (cancelled) cancelled(1.0);
  });
}

const char* th_arkit_name(int index) {
  return index >= 0 && index < TH_NUM_ARKIT ? th::formats::kArkitNames[static_cast<std::size_t>(index)].data()
                                            : nullptr;
}

const char* th_viseme_name(int index) {
  return index >= 0 && index < TH_NUM_VISEMES ? th::face::kOculusVisemeNames[static_cast<std::size_t>(index)].data()
                                              : nullptr;
}

const char* th_vrm_name(int index) {
  return index >= 0 && index < TH_NUM_VRM ? th::face::kVrmVowelNames[static_cast<std::size_t>(index)].data() : nullptr;
}

const char* th_format_name(int index) {
  const auto& formats = th::formats::animationFormats();
  return index >= 0 && index < static_cast<int>(formats.size())
             ? formats[static_cast<std::size_t>(index)]->name().data()
             : nullptr;
}

const char* th_format_extension(int index) {
  const auto& formats = th::formats::animationFormats();
  return index >= 0 && index < static_cast<int>(formats.size())
             ? formats[static_cast<std::size_t>(index)]->extension().data()
             : nullptr;
}

}  // extern "C"
