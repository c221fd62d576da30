// Sound devices through PortAudio: listing them, capturing one input into the live pipeline's ring, and playing
// a recording on an output, delayed to meet the face.
//
//   th::audio::PortAudioSystem system;                        // Pa_Initialize ... Pa_Terminate
//   for (const auto& d : system.inputDevices()) std::cout << d.index << ' ' << d.name << '\n';
//   th::pipeline::AudioRing ring(64000);
//   th::audio::Capture mic(system, std::nullopt, 16000.0, ring);   // the default input, mono 16 kHz
//   ... the worker reads ring ...; mic.active() turns false if the device goes away
//
// The callback only averages the device's channels into a buffer made when the stream opened and writes it
// into the ring: no allocation, lock, I/O or exception (PortAudio's rule, and ours). A device that cannot run
// at the asked rate is opened at its own default rate (rateHz() says which); the worker then resamples.
// Errors (no device, a busy or vanished one) are th::Error naming the device.
//
// Thread contract: PortAudioSystem and Capture belong to one thread (the owner's); the callback runs on
// PortAudio's thread and touches only the ring's producer side and its own buffer.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/audio_ring.h"

struct PaStreamCallbackTimeInfo;

namespace th::audio {

struct AudioDevice {
  int index = -1;  // PortAudio's device index
  std::string name;
  std::string hostApi;  // ALSA, OSS, JACK ...
  int inputChannels = 0;
  int outputChannels = 0;
  double defaultRateHz = 0.0;
  bool isDefaultInput = false;
  bool isDefaultOutput = false;
};

class PortAudioSystem {
 public:
  PortAudioSystem();  // throws th::Error if PortAudio cannot start
  ~PortAudioSystem();
  PortAudioSystem(const PortAudioSystem&) = delete;
  PortAudioSystem& operator=(const PortAudioSystem&) = delete;

  std::vector<AudioDevice> devices() const;
  std::vector<AudioDevice> inputDevices() const;  // those with input channels
  std::optional<AudioDevice> defaultInput() const;
};

// The rate Capture would run `device` (or the default input) at: `wantedHz` if the device takes it, else its
// own default. Throws th::Error as Capture does for a missing device.
double captureRateFor(const PortAudioSystem& system, std::optional<int> device, double wantedHz);

class Capture {
 public:
  // `device`: an index from devices(), or the default input. Throws th::Error if there is none, or it will
  // not open.
  Capture(const PortAudioSystem& system, std::optional<int> device, double rateHz, pipeline::AudioRing& ring);
  ~Capture();
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;

  const AudioDevice& device() const { return device_; }
  double rateHz() const { return rateHz_; }
  // false once the stream has stopped (the device went away, or an error), or once blocks that were coming
  // have stopped for a second: when its sound server dies, PortAudio's ALSA host can keep the stream "active"
  // while its thread only reports errors.
  bool active() const;
  std::uint64_t callbacks() const { return callbacks_.load(std::memory_order_relaxed); }
  std::uint64_t inputOverflows() const { return overflows_.load(std::memory_order_relaxed); }  // PortAudio's own

 private:
  // PortAudio's PaStreamCallback exactly (PaStreamCallbackFlags is an unsigned long).
  static int callback(const void* input, void* output, unsigned long frames, const PaStreamCallbackTimeInfo* timeInfo,
                      unsigned long statusFlags, void* self);

  AudioDevice device_;
  double rateHz_ = 0.0;
  int channels_ = 1;
  pipeline::AudioRing& ring_;
  std::vector<float> mono_;  // sized when the stream opens; the callback never grows it
  void* stream_ = nullptr;   // PaStream
  std::atomic<std::uint64_t> callbacks_{0};
  std::atomic<std::uint64_t> overflows_{0};
  std::atomic<std::int64_t> lastCallbackNs_{0};  // steady clock; 0 until the first block
};

// Plays mono samples from a ring on an output device (the default, or a chosen one), starting setDelay()
// seconds after the first samples arrive: a recording heard in step with the face, whose frames come the
// pipeline's latency after the samples go in (set the delay once the stream is open, when its own latency is
// known). The callback reads the ring into a buffer made at start-up and copies it to the device's channels; a
// short ring plays silence and counts an underrun. Throws th::Error if there is no output device or it will not
// play at `rateHz`.
class Playback {
 public:
  Playback(const PortAudioSystem& system, std::optional<int> device, double rateHz, pipeline::AudioRing& ring);
  void setDelay(double seconds);  // before the ring's first samples; later calls are ignored
  ~Playback();
  Playback(const Playback&) = delete;
  Playback& operator=(const Playback&) = delete;

  const AudioDevice& device() const { return device_; }
  bool active() const;  // false once the stream has stopped
  double outputLatencySeconds() const;  // PortAudio's estimate: from the callback to the speaker
  std::uint64_t underruns() const { return underruns_.load(std::memory_order_relaxed); }

 private:
  static int callback(const void* input, void* output, unsigned long frames, const PaStreamCallbackTimeInfo* timeInfo,
                      unsigned long statusFlags, void* self);

  AudioDevice device_;
  int channels_ = 1;
  pipeline::AudioRing& ring_;
  std::vector<float> mono_;
  double rateHz_ = 0.0;
  std::atomic<std::uint64_t> delaySamples_{0};
  std::uint64_t silenceLeft_ = 0;  // the callback's own: what is left of the delay
  bool started_ = false;           // the callback's own: samples have arrived
  void* stream_ = nullptr;
  std::atomic<std::uint64_t> underruns_{0};
};

}  // namespace th::audio
