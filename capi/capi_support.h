// What the C API's calls share (capi/talkinghead.cpp, capi/deprecated_calls.cpp): the thread's last error, the
// caller's structs read and initialised as far as their struct_size reaches, their defaults, and the models
// handle's loading. Internal to libtalkinghead: not installed, not exported.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <optional>
#include <string>

#include "talkinghead/talkinghead.h"

namespace th::capi {

// The thread's message (th_last_error) set; returns `status`.
th_status fail(th_status status, std::string message);

// The sizes of the structs' first versions: th_frame's and th_stream_options' of 0.2 (the fields before those
// appended since), th_export_options' of 0.2, and the options per verb of 0.3, whole.
inline constexpr std::size_t kFirstFrameSize = offsetof(th_frame, head_rotation_unity);
inline constexpr std::size_t kFirstStreamOptionsSize = offsetof(th_stream_options, progress);
inline constexpr std::size_t kFirstExportOptionsSize = sizeof(th_export_options);
inline constexpr std::size_t kFirstModelsOptionsSize = sizeof(th_models_options);
inline constexpr std::size_t kFirstStreamSettingsSize = sizeof(th_stream_settings);
inline constexpr std::size_t kFirstAnimateOptionsSize = sizeof(th_animate_options);

inline constexpr double kDefaultSampleRateHz = 16000.0;

inline th_models_options defaultModelsOptions() {
  th_models_options options{};
  options.struct_size = sizeof(th_models_options);
  return options;
}

inline th_stream_settings defaultStreamSettings() {
  th_stream_settings settings{};
  settings.struct_size = sizeof(th_stream_settings);
  settings.sample_rate_hz = kDefaultSampleRateHz;
  return settings;
}

inline th_animate_options defaultAnimateOptions() {
  th_animate_options options{};
  options.struct_size = sizeof(th_animate_options);
  return options;
}

inline th_stream_options defaultStreamOptions() {
  th_stream_options options{};
  options.struct_size = sizeof(th_stream_options);
  options.sample_rate_hz = kDefaultSampleRateHz;
  return options;
}

// The caller's struct as this library knows it: the bytes its struct_size covers (a program built against an
// older header has a shorter one), the fields past them as `defaults` has them. nullopt (and the thread's
// message) for a struct_size below the struct's first version, `firstSize`.
template <typename Struct>
std::optional<Struct> readSized(const Struct* given, const Struct& defaults, std::size_t firstSize,
                                const char* function) {
  if (given == nullptr) return defaults;
  if (given->struct_size < firstSize) {
    fail(TH_ERROR_ARGUMENT, std::string(function) + ": struct_size " + std::to_string(given->struct_size) +
                                " is smaller than the struct's first version (" + std::to_string(firstSize) +
                                "): set it with the struct's _init function");
    return std::nullopt;
  }
  Struct known = defaults;
  std::memcpy(static_cast<void*>(&known), given, std::min(given->struct_size, sizeof(Struct)));
  known.struct_size = sizeof(Struct);
  return known;
}

// The defaults written into the caller's struct as far as its size (fields this library does not know zero).
template <typename Struct>
th_status initSized(Struct* given, std::size_t size, const Struct& defaults, std::size_t firstSize,
                    const char* function) {
  if (given == nullptr) return fail(TH_ERROR_ARGUMENT, std::string(function) + ": a NULL struct");
  if (size < firstSize)
    return fail(TH_ERROR_ARGUMENT, std::string(function) + ": struct_size " + std::to_string(size) +
                                       " is smaller than the struct's first version (" + std::to_string(firstSize) +
                                       ")");
  std::memset(static_cast<void*>(given), 0, size);
  std::memcpy(static_cast<void*>(given), &defaults, std::min(size, sizeof(Struct)));
  given->struct_size = size;
  return TH_OK;
}

// TH_OK for a rate of 8000..192000 Hz; else the thread's message names `function`.
th_status checkRate(double rate, const char* function);

// Which of a handle's models are read when it is made: live's, for streams (th_models_load), or the offline
// path's alone, for the one recording th_animate (models NULL) or th_animate_file animates on a handle of its own.
enum class ReadNow { streamModels, fileModels };

th_status loadModelsHandle(const th_models_options* options, ReadNow readNow, const char* function, th_models** models);

}  // namespace th::capi
