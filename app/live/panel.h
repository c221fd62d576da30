// The live window's Dear ImGui panel, a column at the window's left: the sound (source, device, playback),
// plots (waveform, F0, energy, jaw, any FAP, head angles, both models' state posteriors), latency and counters,
// and the settings, whose widgets are made from the option registry (option_widgets.h).
//
//   th::app::LivePanel panel;
//   panel.frameTaken(frame);                    // each animation frame the display takes (the plots)
//   panel.monitor(samples, rateHz);             // the sound the worker read (the waveform)
//   th::app::PanelChanges changes = panel.draw({.live = pipeline, .settings = settings, ...}, size, width);
//
// Thread contract: the ImGui thread.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "live/option_widgets.h"
#include "outputs/live_output.h"
#include "outputs/output_settings.h"
#include "pipeline/animation_frame.h"
#include "pipeline/frame_stats.h"
#include "pipeline/live.h"

namespace th::app {

// What the user changed, for the window to act on.
struct PanelChanges {
  bool reloadModels = false;  // other model files, variants, covariance or preset
  bool redecode = false;      // decoder settings: a new decoder, warmed up, no gap
  bool newPlayout = false;    // the display mode (interpolation)
  bool idle = false;          // the idle behaviour's pace
  bool device = false;        // another sound input, or a rescan
  bool outputs = false;       // an output switched on or off
  int headStyle = -1;         // the head style chosen: an index into PanelView::headStyles (-1: no change)
};

// The settings' widgets, and what their changes ask for (a preset's values applied, a min-f0-hz at or above
// max-f0-hz undone). `record`, if given, receives each widget drawn (tests compare them with the command line's).
PanelChanges settingsWidgets(outputs::LiveSessionSettings& settings, std::vector<WidgetRecord>* record = nullptr);

struct PanelView {
  pipeline::LivePipeline* live = nullptr;  // null: no pipeline yet
  outputs::LiveSessionSettings& settings;
  const pipeline::FrameStats& stats;
  std::uint64_t displayStarved = 0;                 // the playout's
  bool speaking = false;                            // the idle behaviour hears speech
  const std::string& modelError;                    // the last model file that would not load (the running ones stay)
  std::vector<outputs::OutputStatus> outputs = {};  // the open outputs', in the order VMC, OSC, VTube Studio
  std::string character = {};                       // the character drawn and what drives it ("" : our face)
  std::vector<std::string> headStyles = {};         // the head styles offered, "none" first (the window's list)
  int headStyle = 0;                                // the one in use
  std::string headStyleLine = {};  // what it is (describeHeadStyle), or the last one that would not load
};

class LivePanel {
 public:
  static constexpr int kWidth = 440;
  static int widthFor(int windowWidth) { return std::min(kWidth, windowWidth / 2); }

  void frameTaken(const pipeline::AnimationFrame& frame);
  void monitor(std::span<const float> samples, double rateHz);
  // The model files in use, in the text fields.
  void showModelPaths(const std::string& head, const std::string& mouth);

  // Inside ImGui's frame (NewFrame ... Render): the whole column.
  PanelChanges draw(const PanelView& view, std::pair<int, int> windowSize, int width);

 private:
  // Rolling plots: the newest value last.
  struct Curve {
    std::deque<float> values;
    void push(double value);
  };
  // A model's state posteriors over the last 10 s.
  struct Posteriors {
    std::deque<std::array<float, 32>> frames;
    int states = 0;
    template <std::size_t N>
    void push(const std::array<float, N>& posterior, int numStates);
  };

  void soundSection(const PanelView& view, PanelChanges& changes);
  void plotSection();
  void latencySection(const PanelView& view);
  void outputsSection(const PanelView& view, PanelChanges& changes);
  void settingsSection(const PanelView& view, PanelChanges& changes);
  static void plot(const char* label, const Curve& curve, float low, float high, float width);
  static void posteriorPlot(const char* title, const Posteriors& posteriors, float width);

  std::vector<float> waveform_;
  std::size_t waveformAt_ = 0;
  std::array<float, 400> peaks_{};  // the waveform plot's (a member: the panel allocates nothing per frame)
  Curve f0_, energy_, jaw_, chosenFap_;
  std::array<Curve, 3> head_;
  Posteriors headPosteriors_, mouthPosteriors_;
  int plottedFap_ = 5;
  std::array<char, 512> headPath_{};
  std::array<char, 512> mouthPath_{};
};

}  // namespace th::app
