// Sound devices through PortAudio: listing them, capturing one input into the live pipeline's ring, and playing
// a recording on an output, delayed to meet the face.
//
//   th::audio::PortAudioSystem system;                        // Pa_Initialize ... Pa_Terminate
//   for (const auto& d : system.inputDevices()) std::cout << d.index << ' ' << d.name << '\n';
//   th::AudioRing ring(64000);
//   th::audio::Capture mic(system, std::nullopt, 16000.0, ring);   // the default input, mono 16 kHz
//   ... the worker reads ring ...; mic.active() turns false if the device goes away
//
// The callback only averages the device's channels into a buffer made when the stream opened and writes it
// into the ring: no allocation, lock, I/O or exception (PortAudio's rule, and ours). A device that cannot run
// at the asked rate is opened at its own default rate (rateHz() says which); the worker then resamples.
// Errors (no device, a busy or vanished one) are th::Error naming the device.
//
// Thread contract: a Capture or Playback belongs to one thread (the owner's); the callback runs on PortAudio's
// thread and touches only the ring's side it owns and its own buffer. PortAudio's start-up, shut-down and the
// opening and closing of streams are serialised process-wide, so that a stream can be closed on a thread of
// its own (closeInBackground).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/audio_ring.h"

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

// Lets the owner stop a callback from touching anything outside its stream (the ring) before the stream
// is closed, without a lock: the callback enters and leaves; detach() marks it detached and waits for a
// callback under way to leave (microseconds). A detached callback does nothing.
class CallbackGate {
 public:
  bool enter() {
    inside_.store(true, std::memory_order_seq_cst);
    if (!detached_.load(std::memory_order_seq_cst)) return true;
    inside_.store(false, std::memory_order_seq_cst);
    return false;
  }
  void leave() { inside_.store(false, std::memory_order_seq_cst); }
  void detach();

 private:
  std::atomic<bool> detached_{false};
  std::atomic<bool> inside_{false};
};

// A pair of numbers one thread writes and another reads without waiting (a sequence lock): read() fails, rather
// than wait, if it caught a write half done, or nothing was written yet.
class SequencedPair {
 public:
  void write(std::uint64_t first, std::int64_t second);
  bool read(std::uint64_t& first, std::int64_t& second) const;

 private:
  std::atomic<std::uint32_t> version_{0};  // odd while write() runs
  std::atomic<std::uint64_t> first_{0};
  std::atomic<std::int64_t> second_{0};
};

class Capture {
 public:
  // `device`: an index from devices(), or the default input. Throws th::Error if there is none, or it will
  // not open.
  Capture(const PortAudioSystem& system, std::optional<int> device, double rateHz, AudioRing& ring);
  ~Capture();
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;

  const AudioDevice& device() const { return device_; }
  double rateHz() const { return rateHz_; }
  // false once the stream has stopped (the device went away, or an error), once blocks that were coming have
  // stopped for a second, or when none has come in the first 4 s: when its sound server dies, PortAudio's
  // ALSA host can keep the stream "active" while its thread only reports errors.
  bool active() const;
  std::uint64_t callbacks() const { return callbacks_.load(std::memory_order_relaxed); }
  std::uint64_t inputOverflows() const { return overflows_.load(std::memory_order_relaxed); }  // PortAudio's own
  // From now on the callback leaves the ring alone (it may then be destroyed before the stream is closed).
  void detachFromRing() { gate_.detach(); }

 private:
  // PortAudio's PaStreamCallback exactly (PaStreamCallbackFlags is an unsigned long).
  static int callback(const void* input, void* output, unsigned long frames, const PaStreamCallbackTimeInfo* timeInfo,
                      unsigned long statusFlags, void* self);

  AudioDevice device_;
  double rateHz_ = 0.0;
  int channels_ = 1;
  AudioRing& ring_;
  std::vector<float> mono_;  // sized when the stream opens; the callback never grows it
  void* stream_ = nullptr;   // PaStream
  std::atomic<std::uint64_t> callbacks_{0};
  std::atomic<std::uint64_t> overflows_{0};
  std::int64_t openedNs_ = 0;                    // steady clock
  std::atomic<std::int64_t> lastCallbackNs_{0};  // steady clock; 0 until the first block
  CallbackGate gate_;
};

// Plays mono samples from a ring on an output device (the default, or a chosen one), on a schedule: ring
// sample k is heard when schedule() says (a recording heard in step with the face, whose frames come the
// pipeline's latency after the samples go in). Whenever samples come after none (the first, or after the ring
// was empty for 100 ms), the callback puts the next one on time, by silence if it is early or by skipping
// samples if it is late: a device that wakes slowly (a suspended PulseAudio sink takes a second or more) costs the
// start of the sound, not the sync. When a sample is heard is the callback's time plus the delay PortAudio reports for
// its buffer. The callback reads the ring into a buffer made at start-up and copies it to the device's channels; a
// short ring plays silence and counts an underrun. Throws th::Error if there is no output device or it will not play at
// `rateHz`.
class Playback {
 public:
  Playback(const PortAudioSystem& system, std::optional<int> device, double rateHz, AudioRing& ring);
  // Ring sample `ringSample` (counting every sample the ring has taken) is to be heard at `dueNs` (steady
  // clock), and those after it at the sample rate. Used when samples next come after none; may be called again
  // (a recording's next pass).
  void schedule(std::uint64_t ringSample, std::int64_t dueNs);
  ~Playback();
  Playback(const Playback&) = delete;
  Playback& operator=(const Playback&) = delete;

  const AudioDevice& device() const { return device_; }
  bool active() const;                  // false once the stream has stopped
  double outputLatencySeconds() const;  // PortAudio's estimate: from the callback to the speaker
  std::uint64_t underruns() const { return underruns_.load(std::memory_order_relaxed); }
  // Blocks the device has asked for: a sound server wakes a suspended output before it asks (a second or
  // more), and sound written meanwhile would be late.
  std::uint64_t callbacks() const { return callbacks_.load(std::memory_order_relaxed); }
  // The ring sample heard at `nowNs` (steady clock), fractional: the sound's clock, for a picture to follow
  // (by the latest block played, its time and the device's reported delay). False until samples have played.
  bool heardSample(std::int64_t nowNs, double& ringSample) const;
  // When ring sample 0 is heard (steady clock, ns; 0 until samples have been played), as reckoned by the
  // callback that first played some: its time plus the delay PortAudio reports for its buffer
  // (outputBufferDacTime - currentTime), less the samples skipped. With no underrun since, sample k is heard
  // at firstSoundNs() + k / rate.
  std::int64_t firstSoundNs() const { return firstSoundNs_.load(std::memory_order_acquire); }
  double firstDeviceDelaySeconds() const { return firstDeviceDelay_.load(std::memory_order_acquire); }
  void detachFromRing() { gate_.detach(); }  // as Capture's

 private:
  static int callback(const void* input, void* output, unsigned long frames, const PaStreamCallbackTimeInfo* timeInfo,
                      unsigned long statusFlags, void* self);

  AudioDevice device_;
  int channels_ = 1;
  AudioRing& ring_;
  std::vector<float> mono_;
  double rateHz_ = 0.0;
  SequencedPair schedule_;  // ring sample, when it is due (steady ns)
  SequencedPair played_;    // the latest block's first ring sample, when it is heard (steady ns)
  // The callback's own:
  std::uint64_t read_ = 0;         // ring samples taken (played or skipped)
  bool flowing_ = false;           // samples are coming; false at first and after the ring was empty 100 ms
  std::int64_t dryFromNs_ = 0;     // when the ring last ran short (0: it has not since samples came)
  std::uint64_t silenceLeft_ = 0;  // to play before the next sample, which is early
  std::uint64_t skipLeft_ = 0;     // to drop, which are late
  void* stream_ = nullptr;
  std::atomic<std::uint64_t> underruns_{0};
  std::atomic<std::uint64_t> callbacks_{0};
  std::atomic<std::int64_t> firstSoundNs_{0};
  std::atomic<double> firstDeviceDelay_{0.0};
  CallbackGate gate_;
};

// Closes a stream, then lets go of its PortAudio, on a thread of their own, and waits at most `patience` for
// that: true if it finished in time. PortAudio's ALSA host can block for good closing a stream whose sound
// server died (its thread spins on the errors and never reaches the point where it can be stopped); the
// caller then goes on, and may open another stream meanwhile. The stream is detached from its ring first, so
// the ring may go at once. A thread that never finishes keeps only what it was given.
bool closeInBackground(std::unique_ptr<Capture> capture, std::unique_ptr<PortAudioSystem> system,
                       std::chrono::milliseconds patience);
bool closeInBackground(std::unique_ptr<Playback> playback, std::unique_ptr<PortAudioSystem> system,
                       std::chrono::milliseconds patience);
int closesUnfinished();  // closes begun by closeInBackground that have not returned

}  // namespace th::audio
