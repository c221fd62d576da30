#include "audio/capture.h"

#include <fcntl.h>
#include <portaudio.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "core/error.h"

namespace th::audio {
namespace {

constexpr unsigned long kFramesPerBuffer = 256;  // 16 ms at 16 kHz: the callback's block

Error portAudioError(const std::string& what, PaError code) {
  return Error(what + ": " + Pa_GetErrorText(code));
}

// PortAudio is not thread-safe: its start-up and shut-down (reference-counted) and its list of open streams
// are shared. Those calls take this lock, so that a stream can be closed on another thread while the owner
// opens a new one. Aborting a stream does not take it: that is the call that can block for good.
std::mutex& portAudioLock() {
  static std::mutex lock;
  return lock;
}

// Opens and starts a stream (input, output or both), or throws naming it.
void* openStream(const PaStreamParameters* input, const PaStreamParameters* output, double rateHz,
                 PaStreamCallback* callback, void* self, const std::string& named) {
  const std::lock_guard<std::mutex> hold(portAudioLock());
  PaStream* stream = nullptr;
  PaError code = Pa_OpenStream(&stream, input, output, rateHz, kFramesPerBuffer, paNoFlag, callback, self);
  if (code != paNoError) throw portAudioError(named + ": cannot open", code);
  code = Pa_StartStream(stream);
  if (code != paNoError) {
    Pa_CloseStream(stream);
    throw portAudioError(named + ": cannot start", code);
  }
  return stream;
}

// Aborted, not stopped: stopping waits for the buffers to play out, which on a device that went away may
// never happen.
void closeStream(void* stream) {
  if (stream == nullptr) return;
  Pa_AbortStream(static_cast<PaStream*>(stream));
  const std::lock_guard<std::mutex> hold(portAudioLock());
  Pa_CloseStream(static_cast<PaStream*>(stream));
}

std::atomic<int> unfinishedCloses{0};

// Runs `close` on a detached thread; waits for it at most `patience`.
bool runWithin(std::function<void()> close, std::chrono::milliseconds patience) {
  struct Done {
    std::mutex lock;
    std::condition_variable changed;
    bool done = false;
  };
  auto done = std::make_shared<Done>();
  unfinishedCloses.fetch_add(1);
  std::thread([close = std::move(close), done] {
    close();
    unfinishedCloses.fetch_sub(1);
    const std::lock_guard<std::mutex> hold(done->lock);
    done->done = true;
    done->changed.notify_all();
  }).detach();
  std::unique_lock<std::mutex> wait(done->lock);
  return done->changed.wait_for(wait, patience, [&] { return done->done; });
}

std::int64_t steadyNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Blocks that were coming have stopped for a second, or the first has not come in 4 s (a PulseAudio monitor can
// take 2 s for its first block; a server that dies before it sends one leaves the stream waiting for good).
bool stalled(std::int64_t openedNs, std::int64_t lastCallbackNs) {
  const std::int64_t now = steadyNs();
  return lastCallbackNs == 0 ? now - openedNs > 4'000'000'000 : now - lastCallbackNs > 1'000'000'000;
}

bool streamActive(void* stream) {
  return stream != nullptr && Pa_IsStreamActive(static_cast<PaStream*>(stream)) == 1;
}

AudioDevice describe(PaDeviceIndex index) {
  const PaDeviceInfo* info = Pa_GetDeviceInfo(index);
  AudioDevice device;
  device.index = index;
  if (info == nullptr) return device;
  device.name = info->name != nullptr ? info->name : "";
  const PaHostApiInfo* host = Pa_GetHostApiInfo(info->hostApi);
  device.hostApi = host != nullptr && host->name != nullptr ? host->name : "";
  device.inputChannels = info->maxInputChannels;
  device.outputChannels = info->maxOutputChannels;
  device.defaultRateHz = info->defaultSampleRate;
  device.isDefaultInput = index == Pa_GetDefaultInputDevice();
  device.isDefaultOutput = index == Pa_GetDefaultOutputDevice();
  return device;
}

}  // namespace

PortAudioSystem::PortAudioSystem() {
  // PortAudio's host APIs print their probing on stderr as they start (ALSA's unknown PCMs, JACK's missing
  // server): noise to a user, not errors. stderr is pointed at /dev/null meanwhile; PortAudio's own errors
  // come back as codes.
  std::fflush(stderr);
  const int savedStderr = ::dup(STDERR_FILENO);
  const int devNull = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (savedStderr >= 0 && devNull >= 0) ::dup2(devNull, STDERR_FILENO);
  PaError code = paNoError;
  {
    const std::lock_guard<std::mutex> hold(portAudioLock());
    code = Pa_Initialize();
  }
  if (savedStderr >= 0 && devNull >= 0) ::dup2(savedStderr, STDERR_FILENO);
  if (devNull >= 0) ::close(devNull);
  if (savedStderr >= 0) ::close(savedStderr);
  if (code != paNoError) throw portAudioError("PortAudio cannot start", code);
}

PortAudioSystem::~PortAudioSystem() {
  const std::lock_guard<std::mutex> hold(portAudioLock());
  Pa_Terminate();
}

void CallbackGate::detach() {
  detached_.store(true, std::memory_order_seq_cst);
  while (inside_.load(std::memory_order_seq_cst)) std::this_thread::yield();
}

namespace {

template <typename Stream>
bool closeStreamInBackground(std::unique_ptr<Stream> owned, std::unique_ptr<PortAudioSystem> system,
                             std::chrono::milliseconds patience) {
  if (owned) owned->detachFromRing();
  std::shared_ptr<Stream> stream = std::move(owned);
  std::shared_ptr<PortAudioSystem> owner = std::move(system);
  return runWithin(
      [stream = std::move(stream), owner = std::move(owner)]() mutable {
        stream.reset();  // the stream before its PortAudio
        owner.reset();
      },
      patience);
}

}  // namespace

bool closeInBackground(std::unique_ptr<Capture> capture, std::unique_ptr<PortAudioSystem> system,
                       std::chrono::milliseconds patience) {
  return closeStreamInBackground(std::move(capture), std::move(system), patience);
}

bool closeInBackground(std::unique_ptr<Playback> playback, std::unique_ptr<PortAudioSystem> system,
                       std::chrono::milliseconds patience) {
  return closeStreamInBackground(std::move(playback), std::move(system), patience);
}

int closesUnfinished() {
  return unfinishedCloses.load();
}

std::vector<AudioDevice> PortAudioSystem::devices() const {
  std::vector<AudioDevice> all;
  const PaDeviceIndex count = Pa_GetDeviceCount();
  for (PaDeviceIndex i = 0; i < count; ++i) all.push_back(describe(i));
  return all;
}

std::vector<AudioDevice> PortAudioSystem::inputDevices() const {
  std::vector<AudioDevice> inputs;
  for (AudioDevice& d : devices())
    if (d.inputChannels > 0) inputs.push_back(std::move(d));
  return inputs;
}

std::optional<AudioDevice> PortAudioSystem::defaultInput() const {
  const PaDeviceIndex index = Pa_GetDefaultInputDevice();
  if (index == paNoDevice) return std::nullopt;
  return describe(index);
}

namespace {

AudioDevice inputDevice(const PortAudioSystem& system, std::optional<int> device) {
  AudioDevice chosen;
  if (device) {
    if (*device < 0 || *device >= Pa_GetDeviceCount())
      throw Error("sound input " + std::to_string(*device) + ": no such device (" +
                  std::to_string(Pa_GetDeviceCount()) + " devices; `talkinghead live --list-devices`)");
    chosen = describe(*device);
  } else {
    const std::optional<AudioDevice> fallback = system.defaultInput();
    if (!fallback) throw Error("no sound input device (no microphone, and no default input)");
    chosen = *fallback;
  }
  if (chosen.inputChannels < 1)
    throw Error("sound input " + std::to_string(chosen.index) + " (" + chosen.name + "): has no input channels");
  return chosen;
}

PaStreamParameters inputParameters(const AudioDevice& device) {
  PaStreamParameters input{};
  input.device = device.index;
  input.channelCount = std::min(device.inputChannels, 2);
  input.sampleFormat = paFloat32;
  // At least 20 ms: through PulseAudio's ALSA plugin a stream asked for its 9 ms default took seconds to deliver
  // its first block, at 20 ms a few tens of milliseconds (docs/results.md, "Figures behind choices in the code").
  input.suggestedLatency = std::max(Pa_GetDeviceInfo(device.index)->defaultLowInputLatency, 0.020);
  return input;
}

}  // namespace

double captureRateFor(const PortAudioSystem& system, std::optional<int> device, double wantedHz) {
  const AudioDevice chosen = inputDevice(system, device);
  const PaStreamParameters input = inputParameters(chosen);
  return Pa_IsFormatSupported(&input, nullptr, wantedHz) == paFormatIsSupported ? wantedHz : chosen.defaultRateHz;
}

Capture::Capture(const PortAudioSystem& system, std::optional<int> device, double rateHz, AudioRing& ring)
    : ring_(ring) {
  device_ = inputDevice(system, device);
  const std::string named = "sound input " + std::to_string(device_.index) + " (" + device_.name + ")";
  const PaStreamParameters input = inputParameters(device_);
  channels_ = input.channelCount;
  // The asked rate if the device takes it, else its own (the worker resamples).
  rateHz_ = Pa_IsFormatSupported(&input, nullptr, rateHz) == paFormatIsSupported ? rateHz : device_.defaultRateHz;
  mono_.resize(kFramesPerBuffer);
  stream_ = openStream(&input, nullptr, rateHz_, &Capture::callback, this, named);
  openedNs_ = steadyNs();
}

Capture::~Capture() {
  closeStream(stream_);
}

bool Capture::active() const {
  return streamActive(stream_) && !stalled(openedNs_, lastCallbackNs_.load(std::memory_order_relaxed));
}

int Capture::callback(const void* input, void*, unsigned long frames, const PaStreamCallbackTimeInfo*,
                      unsigned long statusFlags, void* self) {
  auto& capture = *static_cast<Capture*>(self);
  if (!capture.gate_.enter()) return paContinue;  // being closed: the ring may be gone
  capture.callbacks_.fetch_add(1, std::memory_order_relaxed);
  // A clock read (vDSO: no lock, no allocation) for the stall watchdog in active().
  capture.lastCallbackNs_.store(steadyNs(), std::memory_order_relaxed);
  if ((statusFlags & paInputOverflow) != 0) capture.overflows_.fetch_add(1, std::memory_order_relaxed);
  if (input == nullptr) {
    capture.gate_.leave();
    return paContinue;
  }
  const auto* samples = static_cast<const float*>(input);
  const int channels = capture.channels_;
  // Blocks are kFramesPerBuffer long (PortAudio keeps the asked size); a longer one is taken in parts.
  for (unsigned long done = 0; done < frames;) {
    const unsigned long n = std::min<unsigned long>(frames - done, capture.mono_.size());
    for (unsigned long i = 0; i < n; ++i) {
      float sum = 0.0f;
      for (int c = 0; c < channels; ++c)
        sum += samples[(done + i) * static_cast<unsigned long>(channels) + static_cast<unsigned long>(c)];
      capture.mono_[i] = sum / static_cast<float>(channels);
    }
    capture.ring_.write(capture.mono_.data(), n);
    done += n;
  }
  capture.gate_.leave();
  return paContinue;
}

Playback::Playback(const PortAudioSystem&, std::optional<int> device, double rateHz, AudioRing& ring) : ring_(ring) {
  PaDeviceIndex index = paNoDevice;
  if (device) {
    if (*device < 0 || *device >= Pa_GetDeviceCount())
      throw Error("sound output " + std::to_string(*device) + ": no such device");
    index = *device;
  } else {
    index = Pa_GetDefaultOutputDevice();
    if (index == paNoDevice) throw Error("no sound output device (nothing to play the recording on)");
  }
  device_ = describe(index);
  const std::string named = "sound output " + std::to_string(device_.index) + " (" + device_.name + ")";
  if (device_.outputChannels < 1) throw Error(named + ": has no output channels");
  PaStreamParameters output{};
  output.device = index;
  output.channelCount = std::min(device_.outputChannels, 2);
  output.sampleFormat = paFloat32;
  output.suggestedLatency = std::max(Pa_GetDeviceInfo(index)->defaultLowOutputLatency, 0.020);
  channels_ = output.channelCount;
  if (Pa_IsFormatSupported(nullptr, &output, rateHz) != paFormatIsSupported)
    throw Error(named + ": will not play at " + std::to_string(static_cast<int>(rateHz)) + " Hz");
  mono_.resize(kFramesPerBuffer);
  rateHz_ = rateHz;
  stream_ = openStream(nullptr, &output, rateHz, &Playback::callback, this, named);
}

Playback::~Playback() {
  closeStream(stream_);
}

// Sequentially consistent throughout: no fences (ThreadSanitizer does not model them), and two values a
// block are no cost worth saving.
void SequencedPair::write(std::uint64_t first, std::int64_t second) {
  const std::uint32_t version = version_.load();
  version_.store(version + 1);
  first_.store(first);
  second_.store(second);
  version_.store(version + 2);
}

bool SequencedPair::read(std::uint64_t& first, std::int64_t& second) const {
  const std::uint32_t version = version_.load();
  if (version == 0 || (version & 1U) != 0) return false;
  first = first_.load();
  second = second_.load();
  return version_.load() == version;
}

void Playback::schedule(std::uint64_t ringSample, std::int64_t dueNs) {
  schedule_.write(ringSample, dueNs);
}

bool Playback::heardSample(std::int64_t nowNs, double& ringSample) const {
  std::uint64_t sample = 0;
  std::int64_t heardNs = 0;
  if (!played_.read(sample, heardNs)) return false;
  ringSample = static_cast<double>(sample) + static_cast<double>(nowNs - heardNs) * 1e-9 * rateHz_;
  return true;
}

// Not the capture's stall watchdog: PulseAudio's ALSA plugin asks an output stream for blocks in bursts, with
// gaps of over a second while its own buffer plays (seen in the playback test).
bool Playback::active() const {
  return streamActive(stream_);
}

double Playback::outputLatencySeconds() const {
  const PaStreamInfo* info = stream_ != nullptr ? Pa_GetStreamInfo(static_cast<PaStream*>(stream_)) : nullptr;
  return info != nullptr ? info->outputLatency : 0.0;
}

int Playback::callback(const void*, void* output, unsigned long frames, const PaStreamCallbackTimeInfo* timeInfo,
                       unsigned long, void* self) {
  auto& playback = *static_cast<Playback*>(self);
  auto* out = static_cast<float*>(output);
  const auto channels = static_cast<unsigned long>(playback.channels_);
  if (!playback.gate_.enter()) {  // being closed: the ring may be gone
    std::fill_n(out, frames * channels, 0.0f);
    return paContinue;
  }
  playback.callbacks_.fetch_add(1, std::memory_order_relaxed);
  // When this buffer's first sample will be heard: now, plus the delay PortAudio reports for it. A clock read
  // (vDSO: no lock, no allocation).
  const double deviceDelay = timeInfo != nullptr && timeInfo->outputBufferDacTime > timeInfo->currentTime
                                 ? timeInfo->outputBufferDacTime - timeInfo->currentTime
                                 : 0.0;
  const std::int64_t nowNs = steadyNs();
  const double bufferHeardNs = static_cast<double>(nowNs) + deviceDelay * 1e9;
  // A ring empty for 100 ms is a pause in the sound (a recording's next pass, a stall): the next samples go
  // on schedule again. Shorter gaps (the ring short of a block by a few ms) play as silence and the sound
  // goes on where it was, a little later: skipping samples to catch up would chop it.
  if (playback.flowing_ && playback.dryFromNs_ != 0 && nowNs - playback.dryFromNs_ > 100'000'000 &&
      playback.ring_.available() == 0)
    playback.flowing_ = false;
  const double nsPerSample = 1e9 / playback.rateHz_;
  for (unsigned long done = 0; done < frames;) {
    const unsigned long n = std::min<unsigned long>(frames - done, playback.mono_.size());
    const double blockHeardNs = bufferHeardNs + static_cast<double>(done) * nsPerSample;
    std::fill(playback.mono_.begin(), playback.mono_.begin() + static_cast<long>(n), 0.0f);
    if (!playback.flowing_ && playback.ring_.available() > 0) {
      // Samples again (the first, or after the ring ran dry): put the next one where the schedule wants it,
      // with silence if it is early, by skipping samples if it is late (a device that woke up slowly).
      playback.flowing_ = true;
      playback.dryFromNs_ = 0;
      playback.silenceLeft_ = playback.skipLeft_ = 0;
      std::uint64_t sample = 0;
      std::int64_t dueNs = 0;
      if (playback.schedule_.read(sample, dueNs)) {
        const double nextDueNs = static_cast<double>(dueNs) +
                                 (static_cast<double>(playback.read_) - static_cast<double>(sample)) * nsPerSample;
        const double early = (nextDueNs - blockHeardNs) / nsPerSample;  // in samples
        if (early > 0.0)
          playback.silenceLeft_ = static_cast<std::uint64_t>(early);
        else
          playback.skipLeft_ = static_cast<std::uint64_t>(-early);
      }
    }
    if (playback.flowing_) {
      while (playback.skipLeft_ > 0) {
        const std::size_t got = playback.ring_.read(
            playback.mono_.data(), static_cast<std::size_t>(std::min<std::uint64_t>(playback.skipLeft_, n)));
        if (got == 0) break;
        playback.skipLeft_ -= got;
        playback.read_ += got;
      }
      std::fill(playback.mono_.begin(), playback.mono_.begin() + static_cast<long>(n), 0.0f);
      const auto silent = static_cast<unsigned long>(std::min<std::uint64_t>(playback.silenceLeft_, n));
      playback.silenceLeft_ -= silent;
      if (playback.skipLeft_ == 0 && silent < n) {
        const std::size_t got = playback.ring_.read(playback.mono_.data() + silent, n - silent);
        if (got > 0 && playback.firstSoundNs_.load(std::memory_order_relaxed) == 0) {
          playback.firstDeviceDelay_.store(deviceDelay, std::memory_order_release);
          playback.firstSoundNs_.store(
              static_cast<std::int64_t>(
                  blockHeardNs + (static_cast<double>(silent) - static_cast<double>(playback.read_)) * nsPerSample),
              std::memory_order_release);
        }
        if (got > 0)
          playback.played_.write(playback.read_,
                                 static_cast<std::int64_t>(blockHeardNs + static_cast<double>(silent) * nsPerSample));
        playback.read_ += got;
        if (got < n - silent) {  // ran dry: the rest is silence
          playback.underruns_.fetch_add(1, std::memory_order_relaxed);
          if (playback.dryFromNs_ == 0) playback.dryFromNs_ = nowNs;
        } else {
          playback.dryFromNs_ = 0;
        }
      }
    }
    for (unsigned long i = 0; i < n; ++i)
      for (unsigned long c = 0; c < channels; ++c) out[(done + i) * channels + c] = playback.mono_[i];
    done += n;
  }
  playback.gate_.leave();
  return paContinue;
}

}  // namespace th::audio
