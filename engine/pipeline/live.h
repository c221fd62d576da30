// The live path, once: a sound source ─► the session's ring ─► the worker's decoder ─► animation frames for the
// display. `live --headless` and the live window both run it; they differ only in what they do with the frames.
//
//   th::pipeline::LivePipeline live(models, {.recording = clip.samples, .name = "speech.wav"}, {});
//   th::pipeline::AnimationFrame frame;
//   while (!live.done()) {
//     live.supervise();                        // starts, loops, retries; notices a lost input or a failed decoder
//     while (live.nextFrame(frame)) show(frame);
//     waitForTheNextDisplayFrame();
//   }
//
// The source is a recording (fed at real-time pace, or faster, from a thread of its own: FileFeeder) or a sound
// input (PortAudio's callback writes into the ring: audio/capture.h). A device that will not run at 16 kHz is
// converted on the way in (ResamplingDecoder). A sound input that is missing or goes away is tried again every
// retrySeconds; after giveUpSeconds without one the pipeline fails (done() and failure()). A recording can be
// played aloud, scheduled late enough that its sound meets the lips (the decoder's look-ahead and the worker's
// cadence), and looped. Other models or decoder settings are handed to the worker as a new decoder, warmed
// up on the last seconds of speech, so the face does not stop (LiveSession::replaceDecoder).
//
// What it reports (sourceName, sourceError, counters) is state the caller shows; events() lists what happened
// since the caller last asked, for its log.
// Thread contract: one thread (the display's) calls everything; the session's worker, the feeder and
// PortAudio's callbacks run behind it. The models are shared read-only and kept alive by the decoders.
#pragma once

#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "audio/capture.h"
#include "core/audio_ring.h"
#include "pipeline/animation_models.h"
#include "pipeline/live_decoder.h"
#include "pipeline/live_session.h"

namespace th::pipeline {

// A recording (16 kHz mono) or, if it is empty, a sound input.
struct LiveSource {
  std::vector<float> recording;
  std::string name;           // the recording's, for messages
  std::optional<int> device;  // the sound input: a PortAudio device number, or the default
};

struct LivePipelineOptions {
  LiveDecoderOptions decoder;
  // A recording:
  bool loop = false;                // again from the start each time it ends
  double speed = 1.0;               // times real time; 0: as fast as the worker takes it
  std::size_t blockSamples = 160;   // fed in blocks of this many (10 ms, a sound device's period)
  std::size_t repeatToSamples = 0;  // over and over to this many samples in all (a soak test), then ended
  bool playAloud = false;           // on the default output, scheduled to meet the lips
  // A sound input:
  double retrySeconds = 2.0;                                       // a missing or lost one is tried again
  double giveUpSeconds = std::numeric_limits<double>::infinity();  // ... until it has been gone this long
};

enum class LiveEventKind {
  kStarted,          // the source started (a recording's first pass, or a sound input opened)
  kSourceLost,       // the sound input went away
  kSourceFailed,     // the source would not start (no device, it will not open) or the decoder stopped
  kGaveUp,           // the sound input has been gone for giveUpSeconds
  kPlaybackStarted,  // the recording is played aloud
  kPlaybackFailed,   // ... could not be, or its output went away
  kCloseStuck,       // PortAudio did not close a stream in 2 s (left closing)
};

struct LiveEvent {
  LiveEventKind kind;
  std::string text;  // one line
};

class LivePipeline {
 public:
  LivePipeline(std::shared_ptr<const AnimationModels> models, LiveSource source, const LivePipelineOptions& options);
  ~LivePipeline();
  LivePipeline(const LivePipeline&) = delete;
  LivePipeline& operator=(const LivePipeline&) = delete;

  void supervise();
  bool nextFrame(AnimationFrame& frame);
  // The samples the worker has read, for a waveform plot (what is not taken is dropped).
  std::size_t readMonitor(float* samples, std::size_t count);
  // No more sound (a duration reached, an interrupt): what was decoded still comes out, then done().
  void endInput();
  bool done() const;
  // Why the pipeline ended early: a sound input gone for giveUpSeconds, or the decoder stopped on a recording
  // played once; empty otherwise.
  const std::string& failure() const { return failure_; }

  // A new decoder with these models and options, warmed up on the recent speech: no gap in the frames.
  void reconfigure(std::shared_ptr<const AnimationModels> models, const LiveDecoderOptions& options);
  void setDecoderOptions(const LiveDecoderOptions& options);
  // Another sound input (or the same again: a rescan of the devices).
  void selectDevice(std::optional<int> device);

  std::vector<LiveEvent> events();  // since the last call
  const std::string& sourceName() const { return sourceName_; }
  const std::string& sourceError() const { return sourceError_; }  // empty while the source runs
  bool isRecording() const { return !source_.recording.empty(); }
  bool running() const { return session_ != nullptr; }                // a session takes sound now
  const std::vector<int>& fapNumbers() const { return fapNumbers_; }  // the FAPs the frames set
  double rateHz() const { return rateHz_; }
  const DecoderLookahead& lookahead() const { return lookahead_; }
  // The running session's and those replaced before it: frames dropped, samples overrun, ...
  SessionCounters counters() const;
  std::uint64_t sourcesOpened() const { return sourcesOpened_; }  // sound inputs opened, recordings' passes begun
  std::uint64_t sourcesLost() const { return sourcesLost_; }
  std::uint64_t deviceOverflows() const { return capture_ ? capture_->inputOverflows() : 0; }
  const std::vector<audio::AudioDevice>& devices() const { return devices_; }
  int passes() const { return passes_; }  // a recording's passes begun
  // Sessions begun (a recording's passes, a sound input opened): each starts its frames from 0 again.
  std::uint64_t sessionsStarted() const { return sessionsStarted_; }
  double deviceSeconds() const;  // how long sound inputs have been open

  // A recording played aloud (null otherwise): its device, and how long after going in a sample is heard.
  const audio::Playback* playback() const { return playback_.get(); }
  double playbackLatencyMs() const { return playbackLatencyMs_; }
  // The instant of the current pass heard at `atNs` (steady clock); false before it is heard, or with no
  // playback.
  bool heardInstant(std::int64_t atNs, double& seconds) const;

 private:
  void startPlayback();
  void stopPlayback();
  void startSource();
  void stopSource();
  std::unique_ptr<FrameDecoder> makeDecoder();
  void note(LiveEventKind kind, std::string text);

  std::shared_ptr<const AnimationModels> models_;
  LiveSource source_;
  LivePipelineOptions options_;
  std::vector<LiveEvent> events_;

  // Playing a recording aloud (declared before the source: destroyed after its feeder).
  std::unique_ptr<audio::PortAudioSystem> outputSystem_;
  std::unique_ptr<AudioRing> playbackRing_;
  std::unique_ptr<audio::Playback> playback_;
  std::chrono::steady_clock::time_point playbackOpened_;
  double playbackLatencyMs_ = 0.0;
  std::uint64_t passStartSample_ = 0;  // the playback ring's sample count when this pass began

  std::unique_ptr<audio::PortAudioSystem> system_;
  std::unique_ptr<LiveSession> session_;
  std::unique_ptr<audio::Capture> capture_;
  std::unique_ptr<FileFeeder> feeder_;
  std::vector<audio::AudioDevice> devices_;
  double rateHz_ = 16000.0;
  DecoderLookahead lookahead_;
  std::vector<int> fapNumbers_;
  std::string sourceName_;
  std::string sourceError_;
  std::string reportedError_;
  std::chrono::steady_clock::time_point lastAttempt_;
  std::chrono::steady_clock::time_point sourceOpened_;
  std::chrono::steady_clock::time_point goneSince_;  // no sound input since (when none runs)
  bool inputEnded_ = false;
  std::string failure_;
  int passes_ = 0;
  double deviceSeconds_ = 0.0;  // of the sound inputs closed so far
  std::uint64_t sourcesOpened_ = 0;
  std::uint64_t sourcesLost_ = 0;
  std::uint64_t sessionsStarted_ = 0;
  SessionCounters totals_;  // of sessions since replaced
};

}  // namespace th::pipeline
