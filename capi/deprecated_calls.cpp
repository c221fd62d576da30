// The calls deprecated in the header, kept for programs built against 0.2: each checks its arguments as it always
// did, then hands the options it was given, split by verb, to the call that does the work (capi/talkinghead.cpp).
#include <optional>

#include "capi_support.h"
#include "talkinghead/talkinghead.h"

using namespace th::capi;

namespace {

// The all-purpose options split by verb.
struct OptionsPerVerb {
  th_models_options models = defaultModelsOptions();
  th_stream_settings stream = defaultStreamSettings();
  th_animate_options animate = defaultAnimateOptions();
};

OptionsPerVerb split(const th_stream_options& options) {
  OptionsPerVerb split;
  split.models.head_model = options.head_model;
  split.models.mouth_model = options.mouth_model;
  split.models.viseme_model = options.viseme_model;
  split.models.head_style = options.head_style;
  split.stream.sample_rate_hz = options.sample_rate_hz;
  split.stream.wait_for_head = options.wait_for_head;
  split.animate.progress = options.progress;
  split.animate.user_data = options.user_data;
  return split;
}

}  // namespace

extern "C" {

th_status th_stream_options_init_sized(th_stream_options* options, size_t struct_size) {
  return initSized(options, struct_size, defaultStreamOptions(), kFirstStreamOptionsSize, "th_stream_options_init");
}

th_status th_models_open(const th_stream_options* options, th_models** models) {
  if (models == nullptr) return fail(TH_ERROR_ARGUMENT, "th_models_open: models is NULL");
  *models = nullptr;
  const std::optional<th_stream_options> known =
      readSized(options, defaultStreamOptions(), kFirstStreamOptionsSize, "th_models_open");
  if (!known) return TH_ERROR_ARGUMENT;
  const OptionsPerVerb given = split(*known);
  return th_models_load(&given.models, models);
}

th_status th_stream_open(const th_stream_options* options, th_stream** stream) {
  if (stream == nullptr) return fail(TH_ERROR_ARGUMENT, "th_stream_open: stream is NULL");
  *stream = nullptr;
  const std::optional<th_stream_options> known =
      readSized(options, defaultStreamOptions(), kFirstStreamOptionsSize, "th_stream_open");
  if (!known) return TH_ERROR_ARGUMENT;
  if (checkRate(known->sample_rate_hz, "th_stream_open") != TH_OK) return TH_ERROR_ARGUMENT;  // before any model
  const OptionsPerVerb given = split(*known);
  // A models handle of its own, which the stream outlives.
  th_models* models = nullptr;
  if (const th_status loaded = th_models_load(&given.models, &models); loaded != TH_OK) return loaded;
  const th_status started = th_stream_start(models, &given.stream, stream);
  th_models_free(models);
  return started;
}

th_status th_stream_open_models(const th_models* models, const th_stream_options* options, th_stream** stream) {
  if (models == nullptr || stream == nullptr)
    return fail(TH_ERROR_ARGUMENT, "th_stream_open_models: models or stream is NULL");
  *stream = nullptr;
  const std::optional<th_stream_options> known =
      readSized(options, defaultStreamOptions(), kFirstStreamOptionsSize, "th_stream_open_models");
  if (!known) return TH_ERROR_ARGUMENT;
  if (checkRate(known->sample_rate_hz, "th_stream_open_models") != TH_OK) return TH_ERROR_ARGUMENT;  // the call made
  const OptionsPerVerb given = split(*known);
  return th_stream_start(models, &given.stream, stream);
}

th_status th_animate_file(const char* recording, const th_stream_options* options, th_animation** animation) {
  if (recording == nullptr || animation == nullptr)
    return fail(TH_ERROR_ARGUMENT, "th_animate_file: recording or animation is NULL");
  *animation = nullptr;
  const std::optional<th_stream_options> known =
      readSized(options, defaultStreamOptions(), kFirstStreamOptionsSize, "th_animate_file");
  if (!known) return TH_ERROR_ARGUMENT;
  const OptionsPerVerb given = split(*known);
  th_models* models = nullptr;
  if (const th_status loaded = loadModelsHandle(&given.models, ReadNow::fileModels, "th_animate_file", &models);
      loaded != TH_OK)
    return loaded;
  const th_status animated = th_animate(models, recording, &given.animate, animation);
  th_models_free(models);
  return animated;
}

th_status th_animate_file_models(const th_models* models, const char* recording, const th_stream_options* options,
                                 th_animation** animation) {
  if (models == nullptr || recording == nullptr || animation == nullptr)
    return fail(TH_ERROR_ARGUMENT, "th_animate_file_models: models, recording or animation is NULL");
  *animation = nullptr;
  const std::optional<th_stream_options> known =
      readSized(options, defaultStreamOptions(), kFirstStreamOptionsSize, "th_animate_file_models");
  if (!known) return TH_ERROR_ARGUMENT;
  const OptionsPerVerb given = split(*known);
  return th_animate(models, recording, &given.animate, animation);
}

}  // extern "C"

namespace {

th_status exportSized(const char* recording, const char* mp4, int width, int height, const char* avatar) {
  th_export_options options;
  th_export_options_init(&options);
  options.width = width;
  options.height = height;
  options.avatar = avatar;
  return th_export(recording, mp4, &options);
}

}  // namespace

extern "C" {

th_status th_export_file(const char* recording, const char* mp4, int width, int height) {
  return exportSized(recording, mp4, width, height, nullptr);
}

th_status th_export_file_avatar(const char* recording, const char* mp4, int width, int height, const char* avatar) {
  return exportSized(recording, mp4, width, height, avatar);
}

}  // extern "C"
