// libtalkinghead's C API (include/talkinghead/talkinghead.h) over the engine: a stream is the live decoder
// (pipeline/live_decoder.h) behind a resampler; an animation is the offline path (pipeline/offline.h); frames
// are the live outputs' AvatarFrame (outputs/avatar_frame.h) in C's shape; an animation on a character is
// avatar/avatar_animation.h's tracks written by formats/gltf_animation.h. No C++ exception crosses the API.
#include "talkinghead/talkinghead.h"

#include <cmath>
#include <memory>
#include <new>
#include <optional>
#include <string>

#include "audio/media_audio.h"
#include "avatar/avatar_animation.h"
#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "core/error.h"
#include "face/face_model.h"
#include "formats/animation_format.h"
#include "formats/arkit_format.h"
#include "formats/gltf_animation.h"
#include "outputs/avatar_frame.h"
#include "outputs/live_display.h"
#include "pipeline/live_decoder.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"
#include "pipeline/video_export.h"

namespace {

thread_local std::string lastError;

th_status fail(th_status status, std::string message) {
  lastError = std::move(message);
  return status;
}

// Runs `body`, turning what it throws into a status and the thread's message.
template <typename Body>
th_status guarded(th_status onError, Body&& body) {
  try {
    body();
    return TH_OK;
  } catch (const th::Error& error) {
    return fail(onError, error.what());
  } catch (const std::bad_alloc&) {
    return fail(TH_ERROR_INTERNAL, "out of memory");
  } catch (const std::exception& error) {
    return fail(TH_ERROR_INTERNAL, error.what());
  }
}

// The models the options name (NULL: the installed ones; "": that part off).
th::pipeline::LiveSettings settingsOf(const th_stream_options* options) {
  th::pipeline::LiveSettings settings;
  if (options == nullptr) return settings;
  const auto choose = [](const char* given, std::string& path, std::string& variant, const char* off) {
    if (given == nullptr) return;
    if (*given == '\0')
      variant = off;
    else
      path = given;
  };
  choose(options->head_model, settings.models.headModel, settings.models.head, "none");
  choose(options->mouth_model, settings.models.mouthModel, settings.models.mouth, "none");
  if (options->viseme_model != nullptr) {
    settings.models.visemeModel = *options->viseme_model ? options->viseme_model : "none";
    // The visemes come from the articulation unless it is off: a viseme model named, or none, turns it off.
    settings.models.articulationModel = "none";
  }
  return settings;
}

void copyFrame(const th::outputs::AvatarFrame& avatar, th_frame* frame) {
  *frame = th_frame{};
  frame->index = avatar.index;
  frame->time_seconds = avatar.timeSeconds;
  for (int fap = 1; fap <= TH_NUM_FAPS; ++fap)
    frame->faps[fap] = static_cast<float>(avatar.faps[static_cast<std::size_t>(fap)]);
  for (int k = 0; k < TH_NUM_ARKIT; ++k) frame->arkit[k] = avatar.arkit[static_cast<std::size_t>(k)];
  for (int k = 0; k < TH_NUM_VISEMES; ++k) frame->visemes[k] = avatar.oculus[static_cast<std::size_t>(k)];
  for (int k = 0; k < TH_NUM_VRM; ++k) frame->vrm[k] = avatar.vrm[static_cast<std::size_t>(k)];
  frame->viseme = avatar.hasVisemes ? th::face::oculusVisemeOf(avatar.mouthClass) : -1;
  frame->rhubarb_shape = avatar.hasVisemes ? th::face::rhubarbShapeOf(avatar.mouthClass) : 'X';
  frame->head_pitch_deg = static_cast<float>(avatar.headDegrees[0]);
  frame->head_yaw_deg = static_cast<float>(avatar.headDegrees[1]);
  frame->head_roll_deg = static_cast<float>(avatar.headDegrees[2]);
}

}  // namespace

struct th_stream {
  std::shared_ptr<const th::pipeline::AnimationModels> models;
  std::unique_ptr<th::pipeline::FrameDecoder> decoder;
  // Blinks, gaze and the head at rest in pauses, as live's window and headless lay them over their frames.
  std::unique_ptr<th::outputs::LiveDisplay> display;
  th::pipeline::DecoderLookahead lookahead;
  bool finished = false;
};

struct th_animation {
  th::face::FapTrack track;
};

extern "C" {

const char* th_version(void) {
  return "0.1.0";
}

const char* th_last_error(void) {
  return lastError.c_str();
}

void th_stream_options_init(th_stream_options* options) {
  if (options == nullptr) return;
  *options = th_stream_options{};
  options->sample_rate_hz = 16000.0;
}

th_status th_stream_open(const th_stream_options* options, th_stream** stream) {
  if (stream == nullptr) return fail(TH_ERROR_ARGUMENT, "th_stream_open: stream is NULL");
  *stream = nullptr;
  const double rate = options != nullptr ? options->sample_rate_hz : 16000.0;
  if (!(rate >= 8000.0 && rate <= 192000.0))
    return fail(TH_ERROR_ARGUMENT,
                "th_stream_open: the sample rate " + std::to_string(rate) + " Hz is not 8000..192000");
  return guarded(TH_ERROR_FILE, [&] {
    const th::pipeline::LiveSettings settings = settingsOf(options);
    auto opened = std::make_unique<th_stream>();
    opened->models = std::make_shared<const th::pipeline::AnimationModels>(th::pipeline::loadModels(settings));
    th::pipeline::LiveDecoderOptions decoderOptions = settings.decoderOptions();
    decoderOptions.waitForHead = options != nullptr && options->wait_for_head != 0;
    auto decoder = std::make_unique<th::pipeline::LiveDecoder>(opened->models->head.get(), opened->models->mouth.get(),
                                                               decoderOptions, opened->models->visemes.get(),
                                                               opened->models->articulation.get());
    opened->lookahead = decoder->lookahead();
    opened->display =
        std::make_unique<th::outputs::LiveDisplay>(settings.idle, settings.live.blinks, settings.live.gaze);
    if (rate == 16000.0)
      opened->decoder = std::move(decoder);
    else
      opened->decoder = std::make_unique<th::pipeline::ResamplingDecoder>(std::move(decoder), rate);
    *stream = opened.release();
  });
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
  int got = 0;
  const th_status status = guarded(TH_ERROR_INTERNAL, [&] {
    th::pipeline::AnimationFrame decoded;
    if (!stream->decoder->next(decoded)) return;
    stream->display->present(decoded, decoded.timeSeconds);  // the stream's own time: the same at any pace
    copyFrame(th::outputs::avatarFrameOf(decoded), frame);
    got = 1;
  });
  return status == TH_OK ? got : -1;
}

double th_stream_latency_ms(const th_stream* stream) {
  return stream == nullptr ? 0.0 : stream->lookahead.totalMs;
}

void th_stream_close(th_stream* stream) {
  delete stream;
}

th_status th_animate_file(const char* recording, const th_stream_options* options, th_animation** animation) {
  if (recording == nullptr || animation == nullptr)
    return fail(TH_ERROR_ARGUMENT, "th_animate_file: recording or animation is NULL");
  *animation = nullptr;
  return guarded(TH_ERROR_FILE, [&] {
    const th::pipeline::LiveSettings settings = settingsOf(options);
    const th::pipeline::AnimationModels models = th::pipeline::loadModels(settings.models);
    auto made = std::make_unique<th_animation>();
    made->track = th::pipeline::animateRecording(
        recording, models, th::pipeline::animateOptionsOf(settings.models, settings.head, settings.idle));
    *animation = made.release();
  });
}

int th_animation_frames(const th_animation* animation) {
  return animation == nullptr ? 0 : animation->track.numFrames();
}

th_status th_animation_frame(const th_animation* animation, int index, th_frame* frame) {
  if (animation == nullptr || frame == nullptr) return fail(TH_ERROR_ARGUMENT, "th_animation_frame: a NULL argument");
  if (index < 0 || index >= animation->track.numFrames())
    return fail(TH_ERROR_ARGUMENT, "th_animation_frame: frame " + std::to_string(index) + " is not 0.." +
                                       std::to_string(animation->track.numFrames() - 1));
  return guarded(TH_ERROR_INTERNAL, [&] {
    const th::face::FapTrack& track = animation->track;
    th::pipeline::AnimationFrame decoded;
    decoded.index = index;
    decoded.timeSeconds = index / track.framesPerSecond;
    decoded.faps = track.frame(index);
    // FAPs 48-50 are the head's pitch, yaw and roll in angle units (1e-5 rad).
    for (int axis = 0; axis < 3; ++axis)
      decoded.headDegrees[axis] = decoded.faps[static_cast<std::size_t>(48 + axis)] * 1e-5 * 180.0 / M_PI;
    if (!track.visemes.empty()) {
      decoded.visemeIndex = index;
      decoded.mouthClass = track.visemes.classes[static_cast<std::size_t>(index)];
      for (int c = 0; c < th::face::kNumMouthClasses; ++c)
        decoded.visemeProbabilities[static_cast<std::size_t>(c)] =
            static_cast<float>(track.visemes.posteriors(c, index));
    }
    copyFrame(th::outputs::avatarFrameOf(decoded), frame);
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
    const th::avatar::Avatar character = th::avatar::loadAvatar(avatar);
    const th::formats::GltfAnimationTracks tracks =
        th::avatar::avatarAnimation(animation->track, character, th::avatar::rigAvatar(character));
    if (animation_only != 0)
      th::formats::writeAnimationOnly(avatar, tracks, path);
    else
      th::formats::writeAvatarAnimation(avatar, tracks, path);
  });
}

void th_animation_free(th_animation* animation) {
  delete animation;
}

th_status th_export_file(const char* recording, const char* mp4, int width, int height) {
  return th_export_file_avatar(recording, mp4, width, height, nullptr);
}

th_status th_export_file_avatar(const char* recording, const char* mp4, int width, int height, const char* avatar) {
  if (recording == nullptr || mp4 == nullptr) return fail(TH_ERROR_ARGUMENT, "th_export_file: a NULL argument");
  if (width < 16 || height < 16 || width > 7680 || height > 4320 || width % 2 != 0 || height % 2 != 0)
    return fail(TH_ERROR_ARGUMENT, "th_export_file: the size must be even, 16x16 to 7680x4320");
  return guarded(TH_ERROR_FILE, [&] {
    // The character first: a bad file fails before any work.
    std::optional<th::avatar::Avatar> character;
    if (avatar != nullptr) {
      character = th::avatar::loadAvatar(avatar);
      th::avatar::rigAvatar(*character);  // throws, naming it, when nothing in it can be driven
    }
    const th::pipeline::LiveSettings settings;
    const th::pipeline::AnimationModels models = th::pipeline::loadModels(settings.models);
    th::audio::AudioClip clip;
    const th::face::FapTrack track = th::pipeline::animateRecording(
        recording, models, th::pipeline::animateOptionsOf(settings.models, settings.head, settings.idle), &clip);
    const th::face::FaceModel face = th::face::FaceModel::buildDefault();
    th::pipeline::exportVideo(face, track, clip.samples, clip.sampleRateHz, mp4,
                              {.width = width, .height = height, .avatar = character ? &*character : nullptr});
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
