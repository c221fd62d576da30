// glad before GLFW: glad's header stands in for the system GL header that GLFW would otherwise pull in.
#include <glad/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "live_window.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/offline.h"
#include "animation/idle_motion.h"
#include "animation_models.h"
#include "audio/capture.h"
#include "audio/media_audio.h"
#include "core/cpu_time.h"
#include "core/error.h"
#include "core/statistics.h"
#include "face/face_model.h"
#include "face/fap.h"
#include "interrupt.h"
#include "pipeline/live_decoder.h"
#include "pipeline/live_presets.h"
#include "pipeline/live_session.h"
#include "pipeline/playout.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "render/image.h"
#include "window_capture.h"

namespace th::app {
namespace {

constexpr double kRetrySeconds = 2.0;   // a lost or missing sound input is tried again this often
constexpr std::chrono::milliseconds kClosePatience{2000};  // waited for a sound stream to close
constexpr std::size_t kPlotFrames = 300;  // 10 s of frames in the plots
constexpr double kWaveformSeconds = 2.0;
constexpr std::size_t kStatFrames = 150;  // the latency figures are medians over the last 5 s

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(const std::deque<double>& values) { return quantile(std::vector<double>(values.begin(), values.end()), 0.5); }

// A decoder that keeps its models alive: after the panel loads other models, the worker may still be running
// the old decoder until it takes the new one.
class ModelDecoder final : public pipeline::FrameDecoder {
 public:
  ModelDecoder(std::shared_ptr<const AnimationModels> models, const pipeline::LiveDecoderOptions& options)
      : models_(std::move(models)), decoder_(models_->head.get(), models_->mouth.get(), options) {}
  void acceptWaveform(std::span<const float> samples16k) override { decoder_.acceptWaveform(samples16k); }
  void inputFinished() override { decoder_.inputFinished(); }
  bool next(pipeline::AnimationFrame& frame) override { return decoder_.next(frame); }
  pipeline::DecoderLookahead lookahead() const { return decoder_.lookahead(); }

 private:
  std::shared_ptr<const AnimationModels> models_;
  pipeline::LiveDecoder decoder_;
};

std::unique_ptr<pipeline::FrameDecoder> makeDecoder(const std::shared_ptr<const AnimationModels>& models,
                                                    const pipeline::LiveDecoderOptions& options, double rateHz,
                                                    pipeline::DecoderLookahead& lookahead) {
  auto decoder = std::make_unique<ModelDecoder>(models, options);
  lookahead = decoder->lookahead();
  if (rateHz == features::OnlineFeatureExtractor::kSampleRateHz) return decoder;
  return std::make_unique<pipeline::ResamplingDecoder>(std::move(decoder), rateHz);
}

std::optional<int> deviceIndexOf(const std::string& text) {
  if (text == "default") return std::nullopt;
  try {
    std::size_t used = 0;
    const int index = std::stoi(text, &used);
    if (used == text.size() && index >= 0) return index;
  } catch (const std::exception&) {
  }
  throw Error("sound input \"" + text + "\": expected \"default\" or a device number");
}

// Rolling plots: the newest value last.
struct Curve {
  std::deque<float> values;
  void push(double value, std::size_t keep) {
    values.push_back(static_cast<float>(value));
    while (values.size() > keep) values.pop_front();
  }
};

// 4x MSAA costs llvmpipe about three times the frame's CPU time: without a GPU, the 60 frames a second matter
// more than smooth edges.
int samplesFor(render::WindowContext& window, int asked) {
  if (asked > 0) return asked;
  return window.description().find("llvmpipe") != std::string::npos ? 1 : 4;
}

// The panel is a column at the window's left and the face is drawn beside it: no part of the face hides
// behind the panel, and neither the backdrop nor the head is drawn where the panel covers them (on llvmpipe
// at 1280x720 every pixel shaded costs).
constexpr int kPanelWidth = 440;
int panelWidthFor(int windowWidth) { return std::min(kPanelWidth, windowWidth / 2); }

class LiveWindow {
 public:
  LiveWindow(const LiveWindowArguments& arguments, LiveSettings settings)
      : arguments_(arguments),
        settings_(std::move(settings)),
        face_(face::FaceModel::buildDefault()),
        window_({.width = 1280, .height = 720, .title = "talkinghead live", .visible = true, .vsync = true, .depth = true}),
        renderer_(window_, face_.mesh(),
                  {.width = 1280 - panelWidthFor(1280), .height = 720, .samples = samplesFor(window_, arguments.msaa)}),
        camera_(render::frameHead(face_.mesh().positions, (1280.0 - panelWidthFor(1280)) / 720.0)),
        playout_(pipeline::PlayoutOptions{.interpolate = settings_.interpolate}) {
    renderer_.setMouthOpening(face_.innerLipVertices());
    renderer_.setEyeOpenings(face_.eyeLidVertices(0), face_.eyeLidVertices(1));
    idle_ = animation::IdleMotion({.blinksPerMinute = settings_.blinksPerMinute, .seed = settings_.seed});
    models_ = loadModels(settings_);  // a bad model file is an error before the window is of any use
    showModelPaths();
    if (!arguments_.input.empty()) {
      recording_ = audio::readRecording(arguments_.input).samples;
      if (recording_.empty()) throw fileError(arguments_.input, "has no samples");
      startPlayback();
    }
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
    ImGui::StyleColorsDark();
    // Input marks the panel for drawing (panelNeedsDrawing). Set first: ImGui's back-end calls them on.
    glfwSetWindowUserPointer(window_.window(), this);
    glfwSetMouseButtonCallback(window_.window(), [](GLFWwindow* w, int, int, int) { noteInput(w); });
    glfwSetScrollCallback(window_.window(), [](GLFWwindow* w, double, double) { noteInput(w); });
    glfwSetKeyCallback(window_.window(), [](GLFWwindow* w, int, int, int, int) { noteInput(w); });
    glfwSetCharCallback(window_.window(), [](GLFWwindow* w, unsigned int) { noteInput(w); });
    glfwSetCursorEnterCallback(window_.window(), [](GLFWwindow* w, int) { noteInput(w); });
    ImGui_ImplGlfw_InitForOpenGL(window_.window(), true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    startSource();
    std::cout << "live: preset " << settings_.preset << ", head " << settings_.headVariant << " (lag "
              << settings_.lagFrames << "), mouth " << settings_.mouthMethod << " (" << settings_.covariance
              << " covariance, window " << settings_.windowFrames
              << ", " << settings_.iterations << " iterations), " << mouthModelOf(settings_) << "; "
              << (sourceError_.empty() ? sourceName_ : sourceError_) << std::endl;
  }

  ~LiveWindow() {
    stopSource();
    stopPlayback();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }

  LiveWindow(const LiveWindow&) = delete;
  LiveWindow& operator=(const LiveWindow&) = delete;

  void run() {
    InterruptGuard interrupts;
    const auto started = std::chrono::steady_clock::now();
    int frame = 0;
    std::pair<int, int> lastSize{0, 0};
    while (!window_.shouldClose() && !InterruptGuard::requested()) {
      if (arguments_.duration > 0.0 && secondsSince(started) >= arguments_.duration) break;
      const auto loopStart = std::chrono::steady_clock::now();
      glfwPollEvents();
      const auto size = window_.framebufferSize();
      if (size.first <= 0 || size.second <= 0) {  // minimised: keep the pipeline drained
        takeFrames();
        std::this_thread::sleep_for(std::chrono::milliseconds(16));
        continue;
      }
      const bool resized = size != lastSize;
      if (resized) {
        panelWidth_ = panelWidthFor(size.first);
        renderer_.resize(size.first - panelWidth_, size.second);
        camera_ = render::frameHead(face_.mesh().positions, static_cast<double>(size.first - panelWidth_) / size.second);
        lastSize = size;
        keptCheck_ = KeptCheck::kToMark;  // new buffers: check again
      }
      superviseSource();
      takeFrames();
      const auto drawStart = std::chrono::steady_clock::now();
      if (keptCheck_ == KeptCheck::kKept && std::chrono::steady_clock::now() - keptCheckedAt_ > std::chrono::seconds(10))
        keptCheck_ = KeptCheck::kToMark;  // and now and then again
      const bool checking = keptCheck_ == KeptCheck::kToRead;
      if (checking) readKeptMark(size);
      const bool panelNow = resized || checking || keptCheck_ != KeptCheck::kKept || panelNeedsDrawing();
      if (panelNow) {
        // The panel's background is this clear (llvmpipe clears with a memset, where ImGui's window background
        // would be a blended quad the size of the column); the face's part is then drawn over.
        const ImVec4 background = ImGui::GetStyle().Colors[ImGuiCol_WindowBg];
        glClearColor(background.x, background.y, background.z, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
      }
      drawFace();
      const auto faceDone = std::chrono::steady_clock::now();
      if (panelNow) {
        drawPanel(size);
        panelDrawn_ = std::chrono::steady_clock::now();
        panelStale_ = false;
        panelSpills_ = spillsOutOfTheColumn(*ImGui::GetDrawData());
        ++panelDraws_;
        if (keptCheck_ == KeptCheck::kToMark) markKept(size);
      }
      const auto panelDone = std::chrono::steady_clock::now();
      ++frame;
      if (!arguments_.screenshot.empty() && frame >= arguments_.frames) {
        render::writePng(arguments_.screenshot, grabWindow(size));
        std::cout << "wrote " << arguments_.screenshot << '\n';
        break;
      }
      window_.swapBuffers();
      const auto swapped = std::chrono::steady_clock::now();
      noteSoundToLips();
      const auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
      record(displayMs_, ms(drawStart, swapped));
      record(stageMs_[0], faceSetupMs_);
      record(stageMs_[1], ms(drawStart, faceDone) - faceSetupMs_);
      if (panelNow) record(stageMs_[2], ms(faceDone, panelDone));  // on the frames that draw it
      record(stageMs_[3], ms(panelDone, swapped));
      const double period = ms(lastSwap_, swapped);
      lastSwap_ = swapped;
      record(periodMs_, period);
      if (frame == 30) cpuAtFrame30_ = processCpuSeconds();
      if (frame > 30) {  // after the first half second (start-up)
        allPeriodsMs_.push_back(period);
        allBusyMs_.push_back(ms(loopStart, swapped));
      }
      // No vsync (Xvfb, some drivers): hold the loop near its cap (60 Hz) rather than spin.
      if (arguments_.maxFps > 0.0) {
        const auto tick = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(1.0 / arguments_.maxFps));
        nextTick_ = std::max(nextTick_ + tick, std::chrono::steady_clock::now() - std::chrono::milliseconds(50));
        std::this_thread::sleep_until(nextTick_);
      }
    }
    saveLiveSettings(arguments_.settingsPath, settings_);
    if (!allPeriodsMs_.empty()) {
      std::sort(allPeriodsMs_.begin(), allPeriodsMs_.end());
      const double medianPeriod = allPeriodsMs_[allPeriodsMs_.size() / 2];
      const double slow = allPeriodsMs_[allPeriodsMs_.size() * 95 / 100];
      // The frame's own work, from the loop's top (events, frames taken) to the swap's return (the loop's cap
      // and its sleep left out):
      // how much of the cap's period is spare.
      std::sort(allBusyMs_.begin(), allBusyMs_.end());
      const double busy = allBusyMs_[allBusyMs_.size() / 2];
      const double busySlow = allBusyMs_[allBusyMs_.size() * 95 / 100];
      // The process's CPU time, llvmpipe's rasterising threads and the decoders included: less at the mercy of
      // what else the machine runs than the frame rate (two cores give 33.3 ms a frame at 60 frames/s).
      const double cpuMs = (processCpuSeconds() - cpuAtFrame30_) * 1000.0 / static_cast<double>(allPeriodsMs_.size());
      std::printf("display: %zu frames, median %.1f frames/s (95th percentile frame %.1f ms), CPU %.1f ms a frame (all "
                  "threads), busy %.1f ms a frame (95th percentile %.1f), the panel drawn %.1f times a second; per frame (median ms of the last 5 s): face %.1f, GL "
                  "%.1f, panel %.1f (the frames that draw it), swap %.1f\n",
                  allPeriodsMs_.size(), 1000.0 / medianPeriod, slow, cpuMs, busy, busySlow,
                  static_cast<double>(panelDraws_) / secondsSince(started), median(stageMs_[0]), median(stageMs_[1]),
                  median(stageMs_[2]), median(stageMs_[3]));
    }
    reportSoundToLips();
  }

 private:
  // The model files in use, in the panel's text fields.
  void showModelPaths() {
    const auto fill = [](std::array<char, 512>& field, const std::string& text) {
      field.fill('\0');
      std::copy_n(text.begin(), std::min(text.size(), field.size() - 1), field.begin());
    };
    fill(headPath_, headModelOf(settings_));
    fill(mouthPath_, mouthModelOf(settings_));
  }

  static void record(std::deque<double>& values, double value) {
    values.push_back(value);
    while (values.size() > kStatFrames) values.pop_front();
  }

  std::shared_ptr<const AnimationModels> loadModels(const LiveSettings& settings) const {
    return std::make_shared<const AnimationModels>(loadAnimationModels(
        "live", settings.headVariant, headModelOf(settings), settings.mouthMethod, mouthModelOf(settings)));
  }

  // --- the sound source and its session -------------------------------------------------------------------

  // A recording is played aloud, and the sound is the face's clock: each frame shows the instant heard when
  // it is swapped in. The sound is scheduled late enough for that instant's frame to be there: the decoder's
  // look-ahead, plus 60 ms for the worker's cadence and processing (frames arrived 62 ms after their instant
  // at the median, 76-80 ms at the 99th percentile, with a 46 ms look-ahead), half a frame (the nearest frame
  // is shown) and drawing. A recording has no latency to save: only its sync matters. Without an output
  // device the face still moves, on the playout's own clock.
  void startPlayback() {
    try {
      playbackLatencyMs_ =
          pipeline::LiveDecoder(models_->head.get(), models_->mouth.get(), decoderOptionsOf(settings_)).lookahead().totalMs + 60.0;
      outputSystem_ = std::make_unique<audio::PortAudioSystem>();
      playbackRing_ = std::make_unique<AudioRing>(2 * features::OnlineFeatureExtractor::kSampleRateHz);
      playback_ = std::make_unique<audio::Playback>(*outputSystem_, std::nullopt, features::OnlineFeatureExtractor::kSampleRateHz,
                                                    *playbackRing_);
      playbackOpened_ = std::chrono::steady_clock::now();
      playbackNote_ = "played on " + playback_->device().name;
      std::cout << "playing aloud: " << playback_->device().name << ", " << std::lround(playbackLatencyMs_)
                << " ms after the face's input (the device's latency " << std::lround(playback_->outputLatencySeconds() * 1000.0)
                << " ms)" << std::endl;
    } catch (const Error& error) {
      playback_.reset();
      playbackRing_.reset();
      outputSystem_.reset();
      playbackNote_ = std::string("not played aloud: ") + error.what();
      std::cerr << "talkinghead: " << playbackNote_ << '\n';
    }
  }

  void startSource() {
    // A recording waits (3 s at most) for the sound output to start asking for blocks: PulseAudio wakes a
    // suspended sink first, and the sound would have to skip what it missed to stay in step with the face.
    if (!recording_.empty() && playback_ && playback_->callbacks() < 4 && secondsSince(playbackOpened_) < 3.0) {
      if (!session_) lastAttempt_ = std::chrono::steady_clock::now() - std::chrono::seconds(10);  // again next frame
      sourceName_ = arguments_.input + " (in a loop; waiting for the sound output)";
      return;
    }
    stopSource();
    sourceError_.clear();
    lastAttempt_ = std::chrono::steady_clock::now();
    try {
      double rate = features::OnlineFeatureExtractor::kSampleRateHz;
      std::optional<int> index;
      if (recording_.empty()) {
        system_ = std::make_unique<audio::PortAudioSystem>();
        devices_ = system_->inputDevices();
        index = deviceIndexOf(settings_.device);
        rate = audio::captureRateFor(*system_, index, rate);
      }
      pipeline::LiveSessionOptions options;
      options.ringSamples = static_cast<std::size_t>(4.0 * rate);
      options.sampleRateHz = rate;
      options.monitorSamples = static_cast<std::size_t>(rate);
      // The decoder's warm-up starts on whole 100 ms (3 frames); 200 ms where 100 ms is no whole number of samples.
      if (std::abs(rate * 0.1 - std::round(rate * 0.1)) > 1e-9) options.alignSeconds = 0.2;
      session_ = std::make_unique<pipeline::LiveSession>(makeDecoder(models_, decoderOptionsOf(settings_), rate, lookahead_), options);
      session_->start();
      rateHz_ = rate;
      if (recording_.empty()) {
        capture_ = std::make_unique<audio::Capture>(*system_, index, rate, session_->ring());
        sourceName_ = "sound input " + std::to_string(capture_->device().index) + ": " + capture_->device().name;
      } else {
        // This pass's first sample is heard the pipeline's latency after the feeder starts.
        if (playback_) {
          passStartSample_ = playbackRing_->samplesWritten();
          playback_->schedule(passStartSample_, pipeline::steadyNanoseconds() + static_cast<std::int64_t>(playbackLatencyMs_ * 1e6));
        }
        feeder_ = std::make_unique<pipeline::FileFeeder>(*session_, recording_, 1.0, 160, 0, playbackRing_.get());
        sourceName_ = arguments_.input + " (in a loop)";
      }
      playout_.reset();
      const auto waveformSize = static_cast<std::size_t>(kWaveformSeconds * rate);
      if (waveform_.size() != waveformSize) waveform_.assign(waveformSize, 0.0f);  // a recording's next pass keeps it
      if (capture_ || loops_++ == 0) std::cout << (capture_ ? "listening: " : "playing: ") << sourceName_ << std::endl;
    } catch (const Error& error) {
      // No device, or it will not open: the face stays at rest, the panel says why, and we try again.
      stopSource();
      sourceError_ = error.what();
      if (sourceError_ != reportedError_) std::cerr << "talkinghead: " << sourceError_ << '\n';
      reportedError_ = sourceError_;
    }
  }

  void stopSource() {
    feeder_.reset();
    // Closed on a thread of its own: closing a stream whose sound server died can block in PortAudio.
    if ((capture_ || system_) && !audio::closeInBackground(std::move(capture_), std::move(system_), kClosePatience))
      std::cerr << "talkinghead: " << sourceName_ << ": PortAudio has not closed it in 2 s; left closing\n";
    if (session_) {
      const pipeline::SessionCounters counters = session_->counters();
      totals_.framesDropped += counters.framesDropped;
      totals_.overrunSamples += counters.overrunSamples;
    }
    session_.reset();
  }

  void stopPlayback() {
    if ((playback_ || outputSystem_) && !audio::closeInBackground(std::move(playback_), std::move(outputSystem_), kClosePatience))
      std::cerr << "talkinghead: the sound output: PortAudio has not closed it in 2 s; left closing\n";
  }

  void superviseSource() {
    if (playback_ && !playback_->active()) {
      // The output went away: stop playing (PortAudio's threads with it), keep the face going.
      playbackNote_ = "not played aloud: " + playback_->device().name + " went away";
      std::cerr << "talkinghead: " << playbackNote_ << '\n';
      stopPlayback();
    }
    if (!session_) {
      if (secondsSince(lastAttempt_) >= kRetrySeconds) startSource();
      return;
    }
    if (capture_ && !capture_->active()) {
      sourceError_ = sourceName_ + " went away; trying again every 2 s (or pick another input)";
      std::cerr << "talkinghead: " << sourceError_ << '\n';
      std::cout << "stopped listening: " << sourceName_ << std::endl;
      playout_.reset();  // no more frames: the face eases to neutral
      reportedError_ = sourceError_;
      stopSource();
      lastAttempt_ = std::chrono::steady_clock::now();
      return;
    }
    if (feeder_ && session_->done()) startSource();  // the recording again from the start
  }

  // The decoder settings or the models changed: a new decoder, warmed up by the worker, no gap.
  void replaceDecoder() {
    if (!session_) return;
    session_->replaceDecoder(makeDecoder(models_, decoderOptionsOf(settings_), rateHz_, lookahead_));
  }

  void takeFrames() {
    if (!session_) return;
    try {
      session_->rethrowError();
    } catch (const std::exception& error) {
      sourceError_ = std::string("the decoder stopped: ") + error.what();
      std::cerr << "talkinghead: " << sourceError_ << '\n';
      stopSource();
      lastAttempt_ = std::chrono::steady_clock::now();
      return;
    }
    const std::int64_t now = pipeline::steadyNanoseconds();
    pipeline::AnimationFrame frame;
    while (session_->nextFrame(frame)) {
      panelStale_ = true;
      playout_.push(frame, now);
      f0_.push(frame.f0Hz, kPlotFrames);
      energy_.push(frame.energy, kPlotFrames);
      jaw_.push(frame.faps[3], kPlotFrames);
      chosenFap_.push(frame.faps[static_cast<std::size_t>(plottedFap_)], kPlotFrames);
      for (int axis = 0; axis < 3; ++axis) head_[static_cast<std::size_t>(axis)].push(frame.headDegrees[axis], kPlotFrames);
      headPosteriors_.push(frame.headPosterior, frame.headStates);
      mouthPosteriors_.push(frame.mouthPosterior, frame.mouthStates);
      processingMs_.push_back(static_cast<double>(frame.decodedNs - frame.inputReadNs) * 1e-6);
      queueMs_.push_back(static_cast<double>(now - frame.decodedNs) * 1e-6);
      while (processingMs_.size() > kStatFrames) processingMs_.pop_front();
      while (queueMs_.size() > kStatFrames) queueMs_.pop_front();
    }
    std::array<float, 1024> block{};
    for (std::size_t n = session_->readMonitor(block.data(), block.size()); n > 0;
         n = session_->readMonitor(block.data(), block.size())) {
      for (std::size_t i = 0; i < n; ++i) waveform_[waveformAt_++ % waveform_.size()] = block[i];
    }
  }

  // --- sound to lips ---------------------------------------------------------------------------------------
  // A recording played aloud: at each swap, the instant of speech heard then (by the playback's clock: its
  // latest block, that block's time and the device's reported delay) against the instant the face shows.
  // Over the recording's first pass; when the recording's start was heard is reported too, for a check
  // against the sound itself (the device test records the sink).

  // The instant of this pass heard at `atNs`; false before the pass is heard, or with no playback.
  bool heardInstant(std::int64_t atNs, double& seconds) const {
    double sample = 0.0;
    if (!feeder_ || !playback_ || !playback_->heardSample(atNs, sample)) return false;
    seconds = (sample - static_cast<double>(passStartSample_)) / features::OnlineFeatureExtractor::kSampleRateHz;
    return seconds >= 0.0;
  }

  void noteSoundToLips() {
    double heard = 0.0;
    if (loops_ != 1 || shownSeconds_ < 0.0 || !heardInstant(pipeline::steadyNanoseconds(), heard)) return;
    if (lateMs_.size() < 100000) lateMs_.push_back((heard - shownSeconds_) * 1000.0);
  }

  void reportSoundToLips() {
    if (!playback_ || playback_->firstSoundNs() == 0 || lateMs_.size() < 30) return;
    std::sort(lateMs_.begin(), lateMs_.end());
    const auto at = [&](double q) { return lateMs_[static_cast<std::size_t>(q * static_cast<double>(lateMs_.size() - 1))]; };
    std::printf("sound to lips: the face shows each instant %+.1f ms after it is heard (median of %zu frames; 10-90 %%: "
                "%+.1f to %+.1f ms); the recording's start heard at %.6f s on the steady clock, by the device's reported "
                "delay of %.1f ms; the sound scheduled %.1f ms after the input; %llu underruns\n",
                at(0.5), lateMs_.size(), at(0.1), at(0.9), static_cast<double>(playback_->firstSoundNs()) * 1e-9,
                playback_->firstDeviceDelaySeconds() * 1000.0, playbackLatencyMs_,
                static_cast<unsigned long long>(playback_->underruns()));
  }

  // --- the face -------------------------------------------------------------------------------------------

  void drawFace() {
    pipeline::PlayoutSample sample;
    // Until the first frame of a new stream (another input, another display mode), the last pose stays: no
    // jump to the neutral face between two streams.
    face::FapFrame faps = lastDecoded_;
    double levelDb = -140.0;  // no sound: silence
    // A recording heard aloud is the clock: the face shows the instant heard when this frame is swapped in
    // (now, plus what drawing and the swap have lately taken). Otherwise the playout's own clock.
    const std::int64_t now = pipeline::steadyNanoseconds();
    double instant = 0.0;
    const bool shown = heardInstant(now + static_cast<std::int64_t>(median(displayMs_) * 1e6), instant)
                           ? playout_.sampleAt(instant, sample)
                           : playout_.sample(now, sample);
    if (shown) {
      faps = sample.frame.faps;
      lastDecoded_ = faps;
      shownSeconds_ = sample.streamSeconds;
      levelDb = sample.frame.levelDb;
      record(behindMs_, sample.behindNewestMs);
      framesWithout_ = 0;
    } else if (++framesWithout_ > 30) {
      // Half a second with no stream (a lost input): the face eases to neutral, the mouth closes.
      for (double& value : lastDecoded_) value *= 0.9;
    }
    for (const int fap : animation::kHeadFaps) faps[static_cast<std::size_t>(fap)] *= settings_.headAmplitude;
    if (settings_.idle)
      idle_.apply(secondsSince(opened_), levelDb, {.blinks = settings_.blinks, .gaze = settings_.gaze}, faps);
    const auto setupStart = std::chrono::steady_clock::now();
    if (faps != shown_) {
      renderer_.setPositions(face_.deform(faps));
      renderer_.setPupilScale(face_.pupilScale(faps));
      shown_ = faps;
    }
    faceSetupMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - setupStart).count();
    if (renderer_.options().samples <= 1) {
      renderer_.renderToWindow(camera_, panelWidth_);  // no target of its own to copy: the fastest way on llvmpipe
    } else {
      renderer_.render(camera_);
      window_.makeCurrent();
      renderer_.present(window_.framebufferSize(), panelWidth_);
    }
  }

  // --- the panel ------------------------------------------------------------------------------------------

  // The panel's column is drawn again only when what it shows changes, if the window's back buffer keeps its
  // pixels from one frame to the next. GL leaves them undefined after a swap; Mesa's software path (llvmpipe
  // under X) keeps them, a GPU's swap chain does not. So it is checked: a frame leaves a mark in a corner of
  // the column (one pixel, for one frame), and the next reads it back before drawing anything. Found: the
  // column is kept; not found: drawn every frame from then on. Checked again after a resize, and every 10 s
  // while found (a mark one pixel wide for one frame does not show).
  enum class KeptCheck { kToMark, kToRead, kKept, kNotKept };

  static constexpr std::array<std::uint8_t, 3> kKeptMark{17, 201, 83};

  void markKept(std::pair<int, int> size) {
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, size.second - 1, 1, 1);
    glClearColor(kKeptMark[0] / 255.0f, kKeptMark[1] / 255.0f, kKeptMark[2] / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    keptCheck_ = KeptCheck::kToRead;
  }

  void readKeptMark(std::pair<int, int> size) {
    std::array<std::uint8_t, 4> pixel{};
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, size.second - 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel.data());
    const bool kept = std::equal(kKeptMark.begin(), kKeptMark.end(), pixel.begin());
    keptCheckedAt_ = std::chrono::steady_clock::now();
    const bool first = !keptReported_;
    keptReported_ = true;
    keptCheck_ = kept ? KeptCheck::kKept : KeptCheck::kNotKept;
    if (first || !kept)  // said once, and again if it stops keeping them
      std::cout << "live: the window's back buffer " << (kept ? "keeps" : "does not keep")
                << " its pixels between frames: the panel is drawn " << (kept ? "when it changes" : "every frame")
                << std::endl;
  }

  static void noteInput(GLFWwindow* window) {
    static_cast<LiveWindow*>(glfwGetWindowUserPointer(window))->lastInput_ = std::chrono::steady_clock::now();
  }

  // With the column kept: its plots and figures move on with each animation frame (30 a second), while the
  // face is drawn at the display's rate. While the user works the panel (the cursor over the window, a key, a
  // click, a field being edited), at the display's rate; otherwise at least 10 times a second (status text).
  bool panelNeedsDrawing() {
    const auto now = std::chrono::steady_clock::now();
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(window_.window(), &x, &y);
    if (x != cursor_[0] || y != cursor_[1]) lastInput_ = now;
    cursor_ = {x, y};
    return panelStale_ || panelSpills_ || now - lastInput_ < std::chrono::milliseconds(500) ||
           ImGui::GetIO().WantTextInput || ImGui::IsAnyItemActive() || now - panelDrawn_ >= std::chrono::milliseconds(100);
  }

  // Whether ImGui drew beyond the column (a combo's list, a tooltip): the face, drawn every frame, would cover
  // that part on the frames the panel is not drawn. (By the vertices: a window's first clip rectangle is the
  // whole display, whatever it draws.)
  bool spillsOutOfTheColumn(const ImDrawData& data) const {
    const float right = data.DisplayPos.x + static_cast<float>(panelWidth_) + 0.5f;
    for (int l = 0; l < data.CmdListsCount; ++l)
      for (const ImDrawVert& vertex : data.CmdLists[l]->VtxBuffer)
        if (vertex.pos.x > right) return true;
    return false;
  }

  void drawPanel(std::pair<int, int> size) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    // The whole column; its background is the frame's clear (run()), so the window draws none.
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(static_cast<float>(panelWidth_), static_cast<float>(size.second)), ImGuiCond_Always);
    ImGui::Begin("Live", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoBackground);
    // The plots near the top, where they stay in view whatever the sound section has to say.
    sourceSection();
    plotSection();
    latencySection();
    modelSection();
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }

  void sourceSection() {
    if (!ImGui::CollapsingHeader("Sound", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (!sourceError_.empty()) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.35f, 1.0f));
      ImGui::TextWrapped("%s", sourceError_.c_str());
      ImGui::PopStyleColor();
    } else {
      ImGui::TextWrapped("%s, %.0f Hz", sourceName_.c_str(), rateHz_);
    }
    if (!recording_.empty()) {
      if (playback_)
        ImGui::TextWrapped("%s, heard %.0f ms after it goes in, to meet the lips (device latency %.0f ms), %llu underruns",
                           playbackNote_.c_str(), playbackLatencyMs_, playback_->outputLatencySeconds() * 1000.0,
                           static_cast<unsigned long long>(playback_->underruns()));
      else
        ImGui::TextWrapped("%s", playbackNote_.c_str());
      return;
    }
    const std::string current = settings_.device == "default" ? "default input" : "input " + settings_.device;
    if (ImGui::BeginCombo("input", current.c_str())) {
      if (ImGui::Selectable("default input", settings_.device == "default")) chooseDevice("default");
      for (const audio::AudioDevice& device : devices_) {
        const std::string label = std::to_string(device.index) + ": " + device.name;
        if (ImGui::Selectable(label.c_str(), settings_.device == std::to_string(device.index)))
          chooseDevice(std::to_string(device.index));
      }
      ImGui::EndCombo();
    }
    ImGui::SameLine();
    if (ImGui::SmallButton("rescan")) startSource();
  }

  void chooseDevice(const std::string& device) {
    settings_.device = device;
    startSource();
  }

  void modelSection() {
    if (!ImGui::CollapsingHeader("Models", ImGuiTreeNodeFlags_DefaultOpen)) return;
    bool reload = false;
    bool redecode = false;
    if (ImGui::BeginCombo("preset", settings_.preset.c_str())) {
      for (const pipeline::LivePreset& preset : pipeline::kLivePresets) {
        if (ImGui::Selectable(std::string(preset.name).c_str(), settings_.preset == preset.name)) {
          applyPreset(settings_, std::string(preset.name));
          settings_.mouthModel.clear();
          playout_ = pipeline::Playout(pipeline::PlayoutOptions{.interpolate = settings_.interpolate});
          reload = true;
        }
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(preset.summary).c_str());
      }
      ImGui::EndCombo();
    }
    static constexpr std::array<const char*, 3> kHeads{"trajectory", "paper", "none"};
    static constexpr std::array<const char*, 3> kMouths{"inversion", "mmse", "none"};
    reload |= choice("head", kHeads, settings_.headVariant);
    reload |= choice("mouth", kMouths, settings_.mouthMethod);
    static constexpr std::array<const char*, 2> kCovariances{"full", "diagonal"};
    if (choice("covariance", kCovariances, settings_.covariance)) {
      settings_.mouthModel.clear();  // the shipped model's twin
      reload = true;
    }
    redecode |= ImGui::SliderInt("head lag (frames)", &settings_.lagFrames, 0, 30);
    redecode |= ImGui::SliderInt("mouth window (frames)", &settings_.windowFrames, 1, 10);
    redecode |= ImGui::SliderInt("EM iterations", &settings_.iterations, 1, 50);
    redecode |= ImGui::Checkbox("frames wait for the head", &settings_.waitForHead);
    float f0[2] = {static_cast<float>(settings_.minF0Hz), static_cast<float>(settings_.maxF0Hz)};
    if (ImGui::DragFloat2("F0 range (Hz)", f0, 1.0f, 20.0f, 2000.0f, "%.0f") && f0[0] + 10.0f < f0[1]) {
      settings_.minF0Hz = f0[0];
      settings_.maxF0Hz = f0[1];
      redecode = true;
    }
    float amplitude = static_cast<float>(settings_.headAmplitude);
    if (ImGui::SliderFloat("head amplitude", &amplitude, 0.0f, 3.0f, "%.2f")) settings_.headAmplitude = amplitude;
    if (ImGui::Checkbox("smooth motion (interpolate, +33 ms)", &settings_.interpolate))
      playout_ = pipeline::Playout(pipeline::PlayoutOptions{.interpolate = settings_.interpolate});
    float smoothing = static_cast<float>(settings_.headSmoothing);
    if (ImGui::SliderFloat("head smoothing", &smoothing, 0.1f, 10.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) {
      settings_.headSmoothing = smoothing;
      redecode = true;
    }
    float variation = static_cast<float>(settings_.headVariation);
    if (ImGui::SliderFloat("head variation", &variation, 0.0f, 3.0f, "%.2f")) {
      settings_.headVariation = variation;
      redecode = true;
    }
    ImGui::Checkbox("idle", &settings_.idle);
    ImGui::SameLine();
    ImGui::Checkbox("blinks", &settings_.blinks);
    ImGui::SameLine();
    ImGui::Checkbox("gaze shifts", &settings_.gaze);
    ImGui::SameLine();
    ImGui::TextUnformatted(idle_.speaking() ? "(speech)" : "(silence: head at rest)");
    ImGui::InputText("head model", headPath_.data(), headPath_.size());
    ImGui::InputText("mouth model", mouthPath_.data(), mouthPath_.size());
    if (ImGui::Button("load model files")) {
      settings_.headModel = headPath_.data();
      settings_.mouthModel = mouthPath_.data();
      reload = true;
    }
    if (!modelError_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "%s", modelError_.c_str());
    if (reload) {
      try {
        models_ = loadModels(settings_);
        modelError_.clear();
        showModelPaths();
        redecode = true;
      } catch (const Error& error) {
        modelError_ = error.what();  // the running models stay
      }
    }
    if (redecode) replaceDecoder();
  }

  template <std::size_t N>
  static bool choice(const char* label, const std::array<const char*, N>& names, std::string& value) {
    bool changed = false;
    if (ImGui::BeginCombo(label, value.c_str())) {
      for (const char* name : names)
        if (ImGui::Selectable(name, value == name) && value != name) {
          value = name;
          changed = true;
        }
      ImGui::EndCombo();
    }
    return changed;
  }

  void latencySection() {
    if (!ImGui::CollapsingHeader("Latency", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const double processing = median(processingMs_);
    const double queue = median(queueMs_);
    const double display = median(behindMs_) + median(displayMs_);
    ImGui::Text("look-ahead  %6.1f ms  (mouth %.0f, head %.0f%s)", lookahead_.totalMs, lookahead_.mouthMs,
                lookahead_.headMs, lookahead_.headDelayFrames > 0 ? ", shown late" : "");
    ImGui::Text("processing  %6.1f ms  (median, read to frame out)", processing);
    ImGui::Text("queueing    %6.1f ms  (frame out to the display)", queue);
    ImGui::Text("display     %6.1f ms  (playout %.1f + drawing %.1f)", display, median(behindMs_), median(displayMs_));
    ImGui::Text("in all      %6.1f ms  (+ the sound device's buffer)", lookahead_.totalMs + processing + queue + display);
    pipeline::SessionCounters counters;
    if (session_) counters = session_->counters();
    ImGui::Text("frames dropped %llu   samples overrun %llu   display starved %llu",
                static_cast<unsigned long long>(totals_.framesDropped + counters.framesDropped),
                static_cast<unsigned long long>(totals_.overrunSamples + counters.overrunSamples),
                static_cast<unsigned long long>(playout_.starvedSamples()));
    if (capture_) ImGui::Text("device overflows %llu", static_cast<unsigned long long>(capture_->inputOverflows()));
    const double period = median(periodMs_);
    ImGui::Text("display %.1f frames/s; per frame (median ms):", period > 0.0 ? 1000.0 / period : 0.0);
    ImGui::Text("  face %.1f, GL %.1f, panel %.1f (when drawn), swap %.1f", median(stageMs_[0]), median(stageMs_[1]),
                median(stageMs_[2]), median(stageMs_[3]));
  }

  void plotSection() {
    if (!ImGui::CollapsingHeader("Plots", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const float width = ImGui::GetContentRegionAvail().x;
    // The waveform as the peak of each of 400 stretches of the last two seconds, oldest first.
    std::array<float, 400>& peaks = peaks_;  // a member: the panel allocates nothing per frame
    peaks.fill(0.0f);
    if (!waveform_.empty()) {
      const std::size_t span = waveform_.size() / peaks.size();
      for (std::size_t p = 0; p < peaks.size(); ++p)
        for (std::size_t i = 0; i < span; ++i)
          peaks[p] = std::max(peaks[p], std::abs(waveform_[(waveformAt_ + p * span + i) % waveform_.size()]));
    }
    ImGui::PlotHistogram("##wave", peaks.data(), static_cast<int>(peaks.size()), 0, "waveform (2 s)", 0.0f, 1.0f, ImVec2(width, 50));
    plot("F0 (Hz)", f0_, 0.0f, 400.0f, width);
    plot("energy", energy_, -3.0f, 3.0f, width);
    plot("jaw, FAP 3", jaw_, -100.0f, 400.0f, width);
    ImGui::SliderInt("FAP", &plottedFap_, 3, face::kNumFaps);
    plot(("FAP " + std::to_string(plottedFap_)).c_str(), chosenFap_, -300.0f, 300.0f, width);
    static constexpr std::array<const char*, 3> kAxes{"head pitch (deg)", "head yaw (deg)", "head roll (deg)"};
    for (std::size_t axis = 0; axis < 3; ++axis) plot(kAxes[axis], head_[axis], -10.0f, 10.0f, width);
    posteriorPlot("head model: P(state | prosody so far)", headPosteriors_, width);
    posteriorPlot("mouth model: P(state | audio so far)", mouthPosteriors_, width);
  }

  // A model's state posteriors over the last 10 s.
  struct Posteriors {
    std::deque<std::array<float, 32>> frames;
    int states = 0;
    template <std::size_t N>
    void push(const std::array<float, N>& posterior, int numStates) {
      std::array<float, 32> copy{};
      std::copy(posterior.begin(), posterior.end(), copy.begin());
      frames.push_back(copy);
      states = numStates;
      while (frames.size() > kPlotFrames) frames.pop_front();
    }
  };

  // A column per frame, a row per state, brighter for more probable.
  static void posteriorPlot(const char* title, const Posteriors& posteriors, float width) {
    if (posteriors.states <= 0 || posteriors.frames.empty()) return;
    ImGui::Text("%s, %d states", title, posteriors.states);
    const float row = posteriors.states > 12 ? 3.0f : 6.0f;
    const float height = row * static_cast<float>(posteriors.states);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(origin, ImVec2(origin.x + width, origin.y + height), IM_COL32(20, 24, 36, 255));
    const float column = width / static_cast<float>(kPlotFrames);
    const float offset = static_cast<float>(kPlotFrames - posteriors.frames.size());
    for (std::size_t t = 0; t < posteriors.frames.size(); ++t)
      for (int k = 0; k < posteriors.states; ++k) {
        const float p = posteriors.frames[t][static_cast<std::size_t>(k)];
        if (p < 0.02f) continue;
        const auto level = static_cast<int>(std::lround(40.0 + 215.0 * std::min(1.0f, p)));
        const float x = origin.x + (offset + static_cast<float>(t)) * column;
        const float y = origin.y + row * static_cast<float>(k);
        draw->AddRectFilled(ImVec2(x, y), ImVec2(x + column + 0.5f, y + row), IM_COL32(level, level * 3 / 4, 40, 255));
      }
    ImGui::Dummy(ImVec2(width, height));
  }

  // Read from the curve's deque through ImGui's getter: no copy.
  static void plot(const char* label, const Curve& curve, float low, float high, float width) {
    ImGui::PushID(label);
    ImGui::PlotLines(
        "##curve", [](void* data, int i) { return static_cast<const Curve*>(data)->values[static_cast<std::size_t>(i)]; },
        const_cast<Curve*>(&curve), static_cast<int>(curve.values.size()), 0, label, low, high, ImVec2(width, 40));
    ImGui::PopID();
  }

  LiveWindowArguments arguments_;
  LiveSettings settings_;
  face::FaceModel face_;
  render::WindowContext window_;
  render::FaceRenderer renderer_;
  render::OrbitCamera camera_;
  pipeline::Playout playout_;
  animation::IdleMotion idle_;
  std::chrono::steady_clock::time_point opened_ = std::chrono::steady_clock::now();
  std::shared_ptr<const AnimationModels> models_;
  std::vector<float> recording_;
  int loops_ = 0;

  // Playing a recording aloud (declared before the source: destroyed after its feeder).
  std::unique_ptr<audio::PortAudioSystem> outputSystem_;
  std::unique_ptr<AudioRing> playbackRing_;
  std::unique_ptr<audio::Playback> playback_;
  std::string playbackNote_;
  std::chrono::steady_clock::time_point playbackOpened_;
  double playbackLatencyMs_ = 0.0;  // a sample is heard this long after it goes into the pipeline
  std::uint64_t passStartSample_ = 0;  // the playback ring's sample count when this pass began
  double shownSeconds_ = -1.0;         // the instant of speech drawn this frame (-1: none yet)
  std::vector<double> lateMs_;         // at each swap of the first pass: heard instant - shown instant
  std::unique_ptr<audio::PortAudioSystem> system_;
  std::unique_ptr<pipeline::LiveSession> session_;
  std::unique_ptr<audio::Capture> capture_;
  std::unique_ptr<pipeline::FileFeeder> feeder_;
  std::vector<audio::AudioDevice> devices_;
  double rateHz_ = 16000.0;
  std::string sourceName_;
  std::string sourceError_;
  std::string reportedError_;
  std::string modelError_;
  std::chrono::steady_clock::time_point lastAttempt_;
  std::chrono::steady_clock::time_point nextTick_ = std::chrono::steady_clock::now();
  pipeline::DecoderLookahead lookahead_;
  struct {
    std::uint64_t framesDropped = 0;
    std::uint64_t overrunSamples = 0;
  } totals_;  // of sessions since replaced

  face::FapFrame shown_{1.0};
  face::FapFrame lastDecoded_{};  // the decoders' last pose (before idle motion and amplitude)
  int framesWithout_ = 0;          // display frames since the playout last had a frame
  std::array<char, 512> headPath_{};
  std::array<char, 512> mouthPath_{};
  std::vector<float> waveform_;
  std::array<float, 400> peaks_{};  // the waveform plot's
  std::size_t waveformAt_ = 0;
  Curve f0_, energy_, jaw_, chosenFap_;
  std::array<Curve, 3> head_;
  Posteriors headPosteriors_, mouthPosteriors_;
  int plottedFap_ = 5;
  std::deque<double> processingMs_, queueMs_, behindMs_, displayMs_, periodMs_;
  std::array<std::deque<double>, 4> stageMs_;  // face set-up (deform, normals), GL (render + present), panel, swap
  std::vector<double> allPeriodsMs_;           // swap to swap, after the first 30 frames
  std::vector<double> allBusyMs_;              // the loop's top to the swap's return, likewise
  double faceSetupMs_ = 0.0;
  double cpuAtFrame30_ = 0.0;
  KeptCheck keptCheck_ = KeptCheck::kToMark;
  std::chrono::steady_clock::time_point keptCheckedAt_;
  bool keptReported_ = false;
  bool panelStale_ = true;   // animation frames came in since the panel was drawn
  bool panelSpills_ = false;  // it last drew beyond its column
  std::chrono::steady_clock::time_point panelDrawn_, lastInput_;
  std::array<double, 2> cursor_{-1.0, -1.0};
  std::uint64_t panelDraws_ = 0;
  int panelWidth_ = panelWidthFor(1280);
  std::chrono::steady_clock::time_point lastSwap_ = std::chrono::steady_clock::now();
};

}  // namespace

void runLiveWindow(const LiveWindowArguments& arguments, LiveSettings settings) {
  LiveWindow window(arguments, std::move(settings));
  window.run();
}

}  // namespace th::app
