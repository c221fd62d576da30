#include "pipeline/live.h"

#include <cmath>
#include <utility>

#include "core/error.h"
#include "features/online_features.h"

namespace th::pipeline {
namespace {

constexpr std::chrono::milliseconds kClosePatience{2000};  // waited for a sound stream to close
constexpr double kSampleRateHz = features::OnlineFeatureExtractor::kSampleRateHz;

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void add(SessionCounters& total, const SessionCounters& more) {
  total.samplesIn += more.samplesIn;
  total.overrunSamples += more.overrunSamples;
  total.framesDecoded += more.framesDecoded;
  total.framesDropped += more.framesDropped;
  total.decodeSeconds += more.decodeSeconds;
}

}  // namespace

LivePipeline::LivePipeline(std::shared_ptr<const AnimationModels> models, LiveSource source,
                           const LivePipelineOptions& options)
    : models_(std::move(models)), source_(std::move(source)), options_(options) {
  if (!models_) throw Error("live: no models");
  // The decoder is made once here, so that bad settings (a lag below 0, a batch head) fail before any sound.
  static_cast<void>(makeDecoder());
  const auto now = std::chrono::steady_clock::now();
  goneSince_ = now;
  lastAttempt_ = now - std::chrono::hours(1);
  if (isRecording() && options_.playAloud) startPlayback();
}

LivePipeline::~LivePipeline() {
  stopSource();
  stopPlayback();
}

std::unique_ptr<FrameDecoder> LivePipeline::makeDecoder() {
  StreamDecoder made = makeStreamDecoder(models_, options_.decoder, rateHz_);
  lookahead_ = made.lookahead;
  fapNumbers_ = std::move(made.fapNumbers);
  return std::move(made.decoder);
}

void LivePipeline::note(LiveEventKind kind, std::string text) {
  events_.push_back({kind, std::move(text)});
}

std::vector<LiveEvent> LivePipeline::events() {
  return std::exchange(events_, {});
}

// A recording has no latency to save, only its sync: its sound is scheduled late enough for each instant's
// frame to be there when it is heard. The decoder's look-ahead, plus 60 ms for the worker's cadence and
// processing (when frames arrive after their instant: docs/results.md, "Live: sound to lips"), half a frame (the
// nearest frame is shown) and drawing.
void LivePipeline::startPlayback() {
  try {
    playbackLatencyMs_ = lookahead_.totalMs + 60.0;
    outputSystem_ = std::make_unique<audio::PortAudioSystem>();
    playbackRing_ = std::make_unique<AudioRing>(2 * static_cast<std::size_t>(kSampleRateHz));
    playback_ = std::make_unique<audio::Playback>(*outputSystem_, std::nullopt, kSampleRateHz, *playbackRing_);
    playbackOpened_ = std::chrono::steady_clock::now();
    note(LiveEventKind::kPlaybackStarted,
         "playing aloud: " + playback_->device().name + ", " + std::to_string(std::lround(playbackLatencyMs_)) +
             " ms after the face's input (the device's latency " +
             std::to_string(std::lround(playback_->outputLatencySeconds() * 1000.0)) + " ms)");
  } catch (const Error& error) {
    playback_.reset();
    playbackRing_.reset();
    outputSystem_.reset();
    note(LiveEventKind::kPlaybackFailed, std::string("not played aloud: ") + error.what());
  }
}

void LivePipeline::stopPlayback() {
  if ((playback_ || outputSystem_) &&
      !audio::closeInBackground(std::move(playback_), std::move(outputSystem_), kClosePatience))
    note(LiveEventKind::kCloseStuck, "the sound output: PortAudio has not closed it in 2 s; left closing");
}

void LivePipeline::startSource() {
  // A recording played aloud waits (3 s at most) for the output to start asking for blocks: PulseAudio wakes a
  // suspended sink first, and the sound would have to skip what it missed to stay in step with the face.
  if (isRecording() && playback_ && playback_->callbacks() < 4 && secondsSince(playbackOpened_) < 3.0) {
    sourceName_ = source_.name + " (waiting for the sound output)";
    return;
  }
  stopSource();
  sourceError_.clear();
  lastAttempt_ = std::chrono::steady_clock::now();
  try {
    double rate = kSampleRateHz;
    if (!isRecording()) {
      system_ = std::make_unique<audio::PortAudioSystem>();
      devices_ = system_->inputDevices();
      rate = audio::captureRateFor(*system_, source_.device, rate);
    }
    rateHz_ = rate;
    LiveSessionOptions sessionOptions;
    sessionOptions.ringSamples = static_cast<std::size_t>(4.0 * rate);
    sessionOptions.sampleRateHz = rate;
    sessionOptions.monitorSamples = static_cast<std::size_t>(rate);
    // A new decoder's warm-up starts on whole 100 ms (3 frames); 200 ms where 100 ms is no whole number of samples.
    if (std::abs(rate * 0.1 - std::round(rate * 0.1)) > 1e-9) sessionOptions.alignSeconds = 0.2;
    session_ = std::make_unique<LiveSession>(makeDecoder(), sessionOptions);
    session_->start();
    ++sessionsStarted_;
    if (!isRecording()) {
      capture_ = std::make_unique<audio::Capture>(*system_, source_.device, rate, session_->ring());
      sourceName_ = "sound input " + std::to_string(capture_->device().index) + ": " + capture_->device().name;
      sourceOpened_ = std::chrono::steady_clock::now();
      ++sourcesOpened_;
      note(LiveEventKind::kStarted, "listening: " + sourceName_ + ", " + std::to_string(std::lround(rate)) + " Hz");
    } else {
      // This pass's first sample is heard the pipeline's latency after the feeder starts.
      if (playback_) {
        passStartSample_ = playbackRing_->samplesWritten();
        playback_->schedule(passStartSample_,
                            steadyNanoseconds() + static_cast<std::int64_t>(playbackLatencyMs_ * 1e6));
      }
      feeder_ = std::make_unique<FileFeeder>(*session_, source_.recording, options_.speed, options_.blockSamples,
                                             options_.repeatToSamples, playbackRing_.get());
      sourceName_ = source_.name + (options_.loop ? " (in a loop)" : "");
      if (passes_ == 0) note(LiveEventKind::kStarted, "playing: " + sourceName_);
      ++passes_;
      ++sourcesOpened_;
    }
  } catch (const Error& error) {
    // No device, or it will not open: the face stays at rest, the caller shows why, and it is tried again.
    stopSource();
    sourceError_ = error.what();
    if (sourceError_ != reportedError_) note(LiveEventKind::kSourceFailed, sourceError_);
    reportedError_ = sourceError_;
  }
}

void LivePipeline::stopSource() {
  feeder_.reset();
  if (capture_) deviceSeconds_ += secondsSince(sourceOpened_);
  // Closed on a thread of its own: closing a stream whose sound server died can block in PortAudio.
  if ((capture_ || system_) && !audio::closeInBackground(std::move(capture_), std::move(system_), kClosePatience))
    note(LiveEventKind::kCloseStuck, sourceName_ + ": PortAudio has not closed it in 2 s; left closing");
  if (session_) add(totals_, session_->counters());
  session_.reset();
}

void LivePipeline::supervise() {
  if (playback_ && !playback_->active()) {
    // The output went away: stop playing (PortAudio's threads with it), keep the face going.
    note(LiveEventKind::kPlaybackFailed, "not played aloud: " + playback_->device().name + " went away");
    stopPlayback();
  }
  if (session_) {
    try {
      session_->rethrowError();
    } catch (const std::exception& error) {
      sourceError_ = std::string("the decoder stopped: ") + error.what();
      note(LiveEventKind::kSourceFailed, sourceError_);
      if (isRecording() && !options_.loop) failure_ = sourceError_;
      stopSource();
      if (!isRecording()) goneSince_ = std::chrono::steady_clock::now();
      return;
    }
  }
  if (inputEnded_ || !failure_.empty()) return;
  if (!session_) {
    if (isRecording()) {
      // Not started yet (or waiting for the sound output); a looped one whose decoder failed is tried again.
      if (passes_ == 0 || (options_.loop && secondsSince(lastAttempt_) >= options_.retrySeconds)) startSource();
      return;
    }
    if (secondsSince(goneSince_) >= options_.giveUpSeconds) {
      failure_ = "no sound input for " + std::to_string(std::lround(options_.giveUpSeconds)) + " s" +
                 (sourceError_.empty() ? std::string() : " (" + sourceError_ + ")");
      note(LiveEventKind::kGaveUp, failure_);
      return;
    }
    if (secondsSince(lastAttempt_) >= options_.retrySeconds) startSource();
    return;
  }
  if (capture_ && !capture_->active()) {
    ++sourcesLost_;
    sourceError_ =
        sourceName_ + " went away; trying again every " + std::to_string(std::lround(options_.retrySeconds)) + " s";
    note(LiveEventKind::kSourceLost, sourceError_);
    reportedError_ = sourceError_;
    stopSource();
    goneSince_ = std::chrono::steady_clock::now();
    return;
  }
  if (feeder_ && options_.loop && session_->done()) startSource();  // the recording again from the start
}

bool LivePipeline::nextFrame(AnimationFrame& frame) {
  return session_ && session_->nextFrame(frame);
}

std::size_t LivePipeline::readMonitor(float* samples, std::size_t count) {
  return session_ ? session_->readMonitor(samples, count) : 0;
}

void LivePipeline::endInput() {
  if (inputEnded_) return;
  inputEnded_ = true;
  if (feeder_) feeder_->stop();  // which ends the session's input
  if (capture_) {
    deviceSeconds_ += secondsSince(sourceOpened_);
    if (!audio::closeInBackground(std::move(capture_), std::move(system_), kClosePatience))
      note(LiveEventKind::kCloseStuck, sourceName_ + ": PortAudio has not closed it in 2 s; left closing");
  }
  if (session_) session_->endOfInput();
}

bool LivePipeline::done() const {
  if (!failure_.empty()) return true;
  if (isRecording() && !options_.loop && passes_ > 0) return !session_ || session_->done();
  if (inputEnded_) return !session_ || session_->done();
  return false;
}

void LivePipeline::reconfigure(std::shared_ptr<const AnimationModels> models, const LiveDecoderOptions& options) {
  models_ = std::move(models);
  setDecoderOptions(options);
}

void LivePipeline::setDecoderOptions(const LiveDecoderOptions& options) {
  options_.decoder = options;
  if (session_) {
    session_->replaceDecoder(makeDecoder());
  } else {
    static_cast<void>(makeDecoder());  // the look-ahead shown is the new one's
  }
}

void LivePipeline::selectDevice(std::optional<int> device) {
  if (isRecording()) return;
  source_.device = device;
  startSource();
}

SessionCounters LivePipeline::counters() const {
  SessionCounters all = totals_;
  if (session_) add(all, session_->counters());
  return all;
}

double LivePipeline::deviceSeconds() const {
  return deviceSeconds_ + (capture_ ? secondsSince(sourceOpened_) : 0.0);
}

bool LivePipeline::heardInstant(std::int64_t atNs, double& seconds) const {
  double sample = 0.0;
  if (!feeder_ || !playback_ || !playback_->heardSample(atNs, sample)) return false;
  seconds = (sample - static_cast<double>(passStartSample_)) / kSampleRateHz;
  return seconds >= 0.0;
}

}  // namespace th::pipeline
