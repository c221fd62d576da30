// glad before GLFW: glad's header stands in for the system GL header that GLFW would otherwise pull in.
#include "live/window.h"

#include <glad/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "audio/media_audio.h"
#include "avatar/avatar_model.h"
#include "character.h"
#include "core/error.h"
#include "head_style_clip.h"
#include "interrupt.h"
#include "live/panel.h"
#include "live/settings_file.h"
#include "outputs/live_display.h"
#include "outputs/live_output.h"
#include "pipeline/frame_stats.h"
#include "pipeline/live.h"
#include "pipeline/playout.h"
#include "render/back_buffer_check.h"
#include "render/gl_context.h"
#include "render/head.h"
#include "render/image.h"
#include "window_capture.h"

namespace th::app {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double millisecondsBetween(std::chrono::steady_clock::time_point from, std::chrono::steady_clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

// 4x MSAA multiplies llvmpipe's CPU time a frame (docs/results.md, "Live: the window's frame rate and cost"):
// without a GPU, the 60 frames a second matter more than smooth edges.
int samplesFor(render::WindowContext& window, int asked) {
  if (asked > 0) return asked;
  return window.description().find("llvmpipe") != std::string::npos ? 1 : 4;
}

std::shared_ptr<const pipeline::AnimationModels> loadModelsOf(const outputs::LiveSessionSettings& settings) {
  return std::make_shared<const pipeline::AnimationModels>(pipeline::loadModels(settings));
}

class LiveWindow {
 public:
  LiveWindow(const LiveWindowArguments& arguments, outputs::LiveSessionSettings settings)
      : arguments_(arguments),
        settings_(std::move(settings)),
        character_(loadCharacter(arguments.avatar)),  // a bad file is an error before a window opens
        window_(
            {.width = 1280, .height = 720, .title = "talkinghead live", .visible = true, .vsync = true, .depth = true}),
        playout_(pipeline::PlayoutOptions{.interpolate = settings_.live.interpolate}),
        display_(settings_.idle, settings_.live.blinks, settings_.live.gaze) {
    const int width = 1280 - LivePanel::widthFor(1280), height = 720, samples = samplesFor(window_, arguments.msaa);
    head_ = render::makeHead(character_ ? &*character_ : nullptr, window_,
                             {.width = width, .height = height, .samples = samples});
    models_ = loadModelsOf(settings_);  // a bad model file is an error before the window is of any use
    panel_.showModelPaths(settings_.models.headModelPath().string(), settings_.mouthModelPath().string());
    offerHeadStyles();
    pipeline::LiveSource source;
    if (!arguments_.input.empty()) {
      source.recording = audio::readRecording(arguments_.input).samples;
      if (source.recording.empty()) throw fileError(arguments_.input, "has no samples");
      source.name = arguments_.input;
    } else {
      source.device = settings_.live.deviceIndex();
    }
    // A recording is played aloud and in a loop, and its sound is the face's clock: each frame shows the
    // instant heard when it is swapped in. Without an output device the face still moves, on the playout's clock.
    live_ = std::make_unique<pipeline::LivePipeline>(
        models_, std::move(source),
        pipeline::LivePipelineOptions{.decoder = settings_.decoderOptions(), .loop = true, .playAloud = true});
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
    openOutputs();  // a bad address is an error before the window is of any use
    live_->supervise();
    handleEvents();
    const outputs::LiveSessionSettings& s = settings_;
    std::cout << "live: preset " << s.live.preset << ", head " << s.models.head << " (lag " << s.streaming.lag
              << "), mouth " << s.models.mouth << " (" << s.live.covariance << " covariance, window "
              << s.streaming.window << ", " << s.live.iterations << " iterations), " << s.mouthModelPath().string()
              << "; " << (live_->sourceError().empty() ? live_->sourceName() : live_->sourceError()) << std::endl;
  }

  ~LiveWindow() {
    live_.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }

  LiveWindow(const LiveWindow&) = delete;
  LiveWindow& operator=(const LiveWindow&) = delete;

  // The loop, in the Dear ImGui example's order: events, pull the decoded frames, play out, display and draw the
  // face, draw the panel, swap.
  void run() {
    InterruptGuard interrupts;
    const auto started = std::chrono::steady_clock::now();
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
      const bool resized = fitTo(size);
      takeFrames();
      pipeline::FrameTimes times;
      drawFrame(size, resized, times);
      if (!arguments_.screenshot.empty() && static_cast<int>(stats_.framesDrawn()) + 1 >= arguments_.frames) {
        render::writePng(arguments_.screenshot, grabWindow(size));
        std::cout << "wrote " << arguments_.screenshot << '\n';
        break;
      }
      swap(loopStart, times);
      holdToMaxFps();
    }
    closeSession(secondsSince(started));
  }

 private:
  // The face's part of the window follows its size; true when it changed.
  bool fitTo(std::pair<int, int> size) {
    if (size == lastSize_) return false;
    panelWidth_ = LivePanel::widthFor(size.first);
    head_->resize(size.first - panelWidth_, size.second);
    lastSize_ = size;
    keptColumn_.again();  // new buffers: check again
    return true;
  }

  // The face, and the panel when it changed or the driver does not keep the column between swaps.
  void drawFrame(std::pair<int, int> size, bool resized, pipeline::FrameTimes& times) {
    const auto drawStart = std::chrono::steady_clock::now();
    keptColumn_.tick();
    const bool checking = keptColumn_.reading();
    if (checking && keptColumn_.read(size))  // said once, and again if it stops keeping them
      std::cout << "live: the window's back buffer " << (keptColumn_.kept() ? "keeps" : "does not keep")
                << " its pixels between frames: the panel is drawn "
                << (keptColumn_.kept() ? "when it changes" : "every frame") << std::endl;
    const bool panelNow = resized || checking || !keptColumn_.kept() || panelNeedsDrawing();
    if (panelNow) {
      // The panel's background is this clear (llvmpipe clears with a memset, where ImGui's window background
      // would be a blended quad the size of the column); the face's part is then drawn over.
      const ImVec4 background = ImGui::GetStyle().Colors[ImGuiCol_WindowBg];
      glClearColor(background.x, background.y, background.z, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT);
    }
    drawFace(times);
    const auto faceDone = std::chrono::steady_clock::now();
    if (panelNow) {
      drawPanel(size);
      if (keptColumn_.marking()) keptColumn_.mark(size);
    }
    times.glMs = millisecondsBetween(drawStart, faceDone) - times.faceSetupMs;
    times.panelMs = panelNow ? millisecondsBetween(faceDone, std::chrono::steady_clock::now()) : -1.0;
  }

  void swap(std::chrono::steady_clock::time_point loopStart, pipeline::FrameTimes& times) {
    const auto swapStart = std::chrono::steady_clock::now();
    window_.swapBuffers();
    const auto swapped = std::chrono::steady_clock::now();
    noteSoundToLips();
    times.swapMs = millisecondsBetween(swapStart, swapped);
    times.busyMs = millisecondsBetween(loopStart, swapped);
    times.periodMs = millisecondsBetween(lastSwap_, swapped);
    lastSwap_ = swapped;
    stats_.frameDrawn(times);
  }

  // No vsync (Xvfb, some drivers): hold the loop near its cap (60 Hz) rather than spin.
  void holdToMaxFps() {
    if (arguments_.maxFps <= 0.0) return;
    const auto tick = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / arguments_.maxFps));
    nextTick_ = std::max(nextTick_ + tick, std::chrono::steady_clock::now() - std::chrono::milliseconds(50));
    std::this_thread::sleep_until(nextTick_);
  }

  // The outputs' reports, the settings saved, the session's statistics.
  void closeSession(double secondsOpen) {
    for (const outputs::OutputStatus& status : display_.statuses())
      std::printf("%s\n", outputs::describe(status, secondsOpen).c_str());
    display_.closeOutputs();  // VTube Studio's thread ends before its token is read
    if (const std::string token = issuedToken_->get(); !token.empty())
      settings_.outputs.get<outputs::VtsSettings>().token = token;
    saveLiveSettings(arguments_.settingsPath, settings_);
    stats_.printSummary(secondsOpen, panelDraws_);
    if (!live_->isRecording())
      std::printf("sound inputs: %llu opened, %llu lost\n", static_cast<unsigned long long>(live_->sourcesOpened()),
                  static_cast<unsigned long long>(live_->sourcesLost()));
    if (const audio::Playback* playback = live_->playback(); playback != nullptr && playback->firstSoundNs() != 0)
      stats_.printSoundToLips(static_cast<double>(playback->firstSoundNs()) * 1e-9,
                              playback->firstDeviceDelaySeconds() * 1000.0, live_->playbackLatencyMs(),
                              playback->underruns());
  }

  // The pipeline watched, its frames into the playout, the panel's plots and the statistics.
  void takeFrames() {
    live_->supervise();
    handleEvents();
    if (live_->sessionsStarted() != sessionsSeen_) {  // a new stream: frame 0 again
      sessionsSeen_ = live_->sessionsStarted();
      playout_.reset();
      display_.newStream();
    }
    const std::int64_t now = pipeline::steadyNanoseconds();
    pipeline::AnimationFrame frame;
    while (live_->nextFrame(frame)) {
      panelStale_ = true;
      playout_.push(frame, now);
      panel_.frameTaken(frame);
      stats_.frameTaken(frame, now);
    }
    std::array<float, 1024> block{};
    for (std::size_t n = live_->readMonitor(block.data(), block.size()); n > 0;
         n = live_->readMonitor(block.data(), block.size()))
      panel_.monitor({block.data(), n}, live_->rateHz());
  }

  // What the pipeline reports goes to the log: what starts on stdout, what fails on stderr.
  void handleEvents() {
    for (const pipeline::LiveEvent& event : live_->events()) {
      if (event.kind == pipeline::LiveEventKind::kSourceLost) playout_.reset();  // the face eases to neutral
      const bool good =
          event.kind == pipeline::LiveEventKind::kStarted || event.kind == pipeline::LiveEventKind::kPlaybackStarted;
      (good ? std::cout : std::cerr) << (good ? "" : "talkinghead: ") << event.text << std::endl;
    }
  }

  // A recording played aloud, over its first pass: at each swap, the instant heard then against the instant
  // the face shows (the device test records the sink to check it against the sound itself).
  void noteSoundToLips() {
    double heard = 0.0;
    if (live_->passes() != 1 || shownSeconds_ < 0.0 || !live_->heardInstant(pipeline::steadyNanoseconds(), heard))
      return;
    stats_.soundToLips((heard - shownSeconds_) * 1000.0);
  }

  // The face's part of a frame: play out, display, draw.
  void drawFace(pipeline::FrameTimes& times) {
    bool shown = false;
    pipeline::AnimationFrame frame = playOut(shown);
    // The idle motion, and the outputs sent the face as drawn (outputs/live_display.h: as headless and the
    // library do).
    display_.setSwitches(settings_.live.blinks, settings_.live.gaze);
    const outputs::AvatarFrame& drawn = display_.present(frame, secondsSince(opened_), shown);
    drawHead(drawn, times);
  }

  // The frame the face shows at this swap; `shown` false when the playout has none (the last pose held).
  pipeline::AnimationFrame playOut(bool& shown) {
    pipeline::PlayoutSample sample;
    // Until the first frame of a new stream (another input, another display mode), the last pose stays: no
    // jump to the neutral face between two streams.
    face::FapFrame faps = lastDecoded_;
    double levelDb = -140.0;  // no sound: silence
    // A recording heard aloud is the clock: the face shows the instant heard when this frame is swapped in (now,
    // plus what drawing and the swap have lately taken). Otherwise the playout's own clock.
    const std::int64_t now = pipeline::steadyNanoseconds();
    double instant = 0.0;
    shown = live_->heardInstant(now + static_cast<std::int64_t>(stats_.displayMs() * 1e6), instant)
                ? playout_.sampleAt(instant, sample)
                : playout_.sample(now, sample);
    if (shown) {
      faps = sample.frame.faps;
      lastDecoded_ = faps;
      shownSeconds_ = sample.streamSeconds;
      levelDb = sample.frame.levelDb;
      stats_.playoutBehind(sample.behindNewestMs);
      framesWithout_ = 0;
    } else if (++framesWithout_ > 30) {
      // Half a second with no stream (a lost input): the face eases to neutral, the mouth closes.
      for (double& value : lastDecoded_) value *= 0.9;
    }
    pipeline::AnimationFrame frame = shown ? sample.frame : pipeline::AnimationFrame{};
    frame.faps = faps;
    frame.levelDb = levelDb;
    return frame;
  }

  // The head posed by the frame as displayed, drawn into the window beside the panel: our face by the FAPs, a
  // character by the weights the outputs got (its mouth by the visemes where the decoder has them and it has
  // viseme targets).
  void drawHead(const outputs::AvatarFrame& drawn, pipeline::FrameTimes& times) {
    const auto setupStart = std::chrono::steady_clock::now();
    head_->pose(drawn.faps, drawn);
    times.faceSetupMs = millisecondsBetween(setupStart, std::chrono::steady_clock::now());
    head_->drawIntoWindow(window_, panelWidth_);
  }

  void drawPanel(std::pair<int, int> size) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const PanelChanges changes = panel_.draw({.live = live_.get(),
                                              .settings = settings_,
                                              .stats = stats_,
                                              .displayStarved = playout_.starvedSamples(),
                                              .speaking = display_.speaking(),
                                              .modelError = modelError_,
                                              .outputs = outputStatuses(),
                                              .character = head_->description(),
                                              .headStyles = headStyleNames(),
                                              .headStyle = headStyle_,
                                              .headStyleLine = headStyleLine_},
                                             size, panelWidth_);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    panelDrawn_ = std::chrono::steady_clock::now();
    panelStale_ = false;
    panelSpills_ = spillsOutOfTheColumn(*ImGui::GetDrawData());
    ++panelDraws_;
    apply(changes);
  }

  // The outputs the settings name, (re)opened; VTube Studio's token, once issued, is kept for the settings file.
  void openOutputs() {
    display_.closeOutputs();
    if (const std::string token = issuedToken_->get(); !token.empty())
      settings_.outputs.get<outputs::VtsSettings>().token = token;
    display_.setOutputs(settings_.outputs.open(
        {.faps = live_->fapNumbers(),
         .tokenIssued = [token = issuedToken_](const std::string& issued) { token->set(issued); }}));
  }

  std::vector<outputs::OutputStatus> outputStatuses() const { return display_.statuses(); }

  // The panel's head styles: none, the one the settings name (fitted already), and those `talkinghead style`
  // keeps (read when chosen).
  void offerHeadStyles() {
    headStyles_ = {{.name = "none (the model's own motion)", .file = {}, .style = {}}};
    if (settings_.head.fittedStyle) {
      headStyles_.push_back({.name = std::filesystem::path(settings_.head.style).filename().string(),
                             .file = settings_.head.style,
                             .style = settings_.head.fittedStyle});
      headStyle_ = 1;
      headStyleLine_ = describeHeadStyle(*settings_.head.fittedStyle);
    }
    for (const std::filesystem::path& file : listHeadStyles()) {
      std::error_code error;
      if (headStyles_.size() > 1 && std::filesystem::equivalent(file, headStyles_[1].file, error)) continue;
      headStyles_.push_back({.name = file.stem().string(), .file = file, .style = {}});
    }
  }

  std::vector<std::string> headStyleNames() const {
    std::vector<std::string> names;
    for (const HeadStyleChoice& choice : headStyles_) names.push_back(choice.name);
    return names;
  }

  void chooseHeadStyle(int index) {
    HeadStyleChoice& choice = headStyles_.at(static_cast<std::size_t>(index));
    try {
      if (index == 0) {
        pipeline::clearHeadStyle(settings_.head, settings_.idle);
        headStyleLine_.clear();
      } else {
        if (!choice.style) choice.style = animation::loadHeadStyle(choice.file);
        settings_.head.style = choice.file.string();
        pipeline::useHeadStyle(*choice.style, settings_.head, settings_.idle);
        headStyleLine_ = describeHeadStyle(*choice.style);
      }
      headStyle_ = index;
      display_.setIdle(settings_.idle);  // the rest pose
      live_->setDecoderOptions(settings_.decoderOptions());
    } catch (const Error& error) {
      headStyleLine_ = error.what();  // the running style stays
    }
  }

  void apply(const PanelChanges& changes) {
    if (changes.headStyle >= 0) chooseHeadStyle(changes.headStyle);
    if (changes.outputs) openOutputs();
    if (changes.newPlayout)
      playout_ = pipeline::Playout(pipeline::PlayoutOptions{.interpolate = settings_.live.interpolate});
    if (changes.idle) display_.setIdle(settings_.idle);
    if (changes.device) live_->selectDevice(settings_.live.deviceIndex());
    if (changes.reloadModels) {
      try {
        models_ = loadModelsOf(settings_);
        modelError_.clear();
        panel_.showModelPaths(settings_.models.headModelPath().string(), settings_.mouthModelPath().string());
        live_->reconfigure(models_, settings_.decoderOptions());
      } catch (const Error& error) {
        modelError_ = error.what();  // the running models stay
      }
    } else if (changes.redecode) {
      live_->setDecoderOptions(settings_.decoderOptions());
    }
  }

  static void noteInput(GLFWwindow* window) {
    static_cast<LiveWindow*>(glfwGetWindowUserPointer(window))->lastInput_ = std::chrono::steady_clock::now();
  }

  // With the column kept: its plots and figures move on with each animation frame (30 a second), while the face
  // is drawn at the display's rate. While the user works the panel (the cursor over the window, a key, a click, a
  // field being edited), at the display's rate; otherwise at least 10 times a second (status text).
  bool panelNeedsDrawing() {
    const auto now = std::chrono::steady_clock::now();
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(window_.window(), &x, &y);
    if (x != cursor_[0] || y != cursor_[1]) lastInput_ = now;
    cursor_ = {x, y};
    return panelStale_ || panelSpills_ || now - lastInput_ < std::chrono::milliseconds(500) ||
           ImGui::GetIO().WantTextInput || ImGui::IsAnyItemActive() ||
           now - panelDrawn_ >= std::chrono::milliseconds(100);
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

  struct HeadStyleChoice {
    std::string name;
    std::filesystem::path file;                 // empty: none
    std::optional<animation::HeadStyle> style;  // read when first chosen
  };

  LiveWindowArguments arguments_;
  outputs::LiveSessionSettings settings_;
  std::optional<avatar::Avatar> character_;  // --avatar: the user's character, drawn instead of our face
  render::WindowContext window_;
  std::unique_ptr<render::Head> head_;  // our face, or the character
  pipeline::Playout playout_;
  outputs::LiveDisplay display_;  // idle motion and outputs, as every live path
  std::chrono::steady_clock::time_point opened_ = std::chrono::steady_clock::now();
  std::shared_ptr<const pipeline::AnimationModels> models_;
  std::unique_ptr<pipeline::LivePipeline> live_;
  std::shared_ptr<outputs::IssuedToken> issuedToken_ = std::make_shared<outputs::IssuedToken>();
  std::uint64_t sessionsSeen_ = 0;
  std::string modelError_;
  std::vector<HeadStyleChoice> headStyles_;
  int headStyle_ = 0;
  std::string headStyleLine_;
  LivePanel panel_;
  pipeline::FrameStats stats_;
  render::BackBufferCheck keptColumn_;  // the panel is drawn again only when it changes, where the column is kept
  face::FapFrame lastDecoded_{};        // the decoders' last pose (before idle motion)
  double shownSeconds_ = -1.0;          // the instant of speech drawn this frame (-1: none yet)
  int framesWithout_ = 0;               // display frames since the playout last had a frame
  bool panelStale_ = true;              // animation frames came in since the panel was drawn
  bool panelSpills_ = false;            // it last drew beyond its column
  std::chrono::steady_clock::time_point panelDrawn_, lastInput_;
  std::array<double, 2> cursor_{-1.0, -1.0};
  std::uint64_t panelDraws_ = 0;
  int panelWidth_ = LivePanel::widthFor(1280);
  std::pair<int, int> lastSize_{0, 0};  // the framebuffer's, as the face and the panel were last fitted to
  std::chrono::steady_clock::time_point nextTick_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point lastSwap_ = std::chrono::steady_clock::now();
};

}  // namespace

void runLiveWindow(const LiveWindowArguments& arguments, outputs::LiveSessionSettings settings) {
  LiveWindow window(arguments, std::move(settings));
  window.run();
}

}  // namespace th::app
