#include "live/panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "face/fap.h"

namespace th::app {
namespace {

constexpr std::size_t kPlotFrames = 300;  // 10 s of frames in the plots
constexpr double kWaveformSeconds = 2.0;
const ImVec4 kErrorColour(1.0f, 0.45f, 0.35f, 1.0f);

bool differ(outputs::LiveSessionSettings& a, outputs::LiveSessionSettings& b, auto member) {
  return optionsToJson(a.*member) != optionsToJson(b.*member);
}

}  // namespace

PanelChanges settingsWidgets(outputs::LiveSessionSettings& settings, std::vector<WidgetRecord>* record) {
  outputs::LiveSessionSettings before = settings;
  optionWidgets(settings.live, record);
  optionWidgets(settings.models, record);
  optionWidgets(settings.streaming, record);
  optionWidgets(settings.head, record);
  optionWidgets(settings.idle, record);
  PanelChanges changes;
  if (settings.live.preset != before.live.preset) {
    const std::string preset = settings.live.preset;
    settings.live.preset = before.live.preset;
    pipeline::applyLivePreset(settings, preset);
    settings.models.mouthModel.clear();  // the preset's model
    changes.reloadModels = changes.newPlayout = true;
  }
  if (settings.live.covariance != before.live.covariance) {
    settings.models.mouthModel.clear();  // the shipped model's twin
    changes.reloadModels = true;
  }
  if (!(settings.live.minF0 + 10.0 < settings.live.maxF0)) {  // the search range must stay a range
    settings.live.minF0 = before.live.minF0;
    settings.live.maxF0 = before.live.maxF0;
  }
  if (differ(settings, before, &outputs::LiveSessionSettings::models)) changes.reloadModels = true;
  if (differ(settings, before, &outputs::LiveSessionSettings::streaming) ||
      differ(settings, before, &outputs::LiveSessionSettings::head) ||
      settings.live.iterations != before.live.iterations || settings.live.waitForHead != before.live.waitForHead ||
      settings.live.minF0 != before.live.minF0 || settings.live.maxF0 != before.live.maxF0)
    changes.redecode = true;
  if (settings.live.interpolate != before.live.interpolate) changes.newPlayout = true;
  if (settings.idle.blinksPerMinute != before.idle.blinksPerMinute) changes.idle = true;
  return changes;
}

void LivePanel::Curve::push(double value) {
  values.push_back(static_cast<float>(value));
  while (values.size() > kPlotFrames) values.pop_front();
}

template <std::size_t N>
void LivePanel::Posteriors::push(const std::array<float, N>& posterior, int numStates) {
  std::array<float, 32> copy{};
  std::copy(posterior.begin(), posterior.end(), copy.begin());
  frames.push_back(copy);
  states = numStates;
  while (frames.size() > kPlotFrames) frames.pop_front();
}

void LivePanel::frameTaken(const pipeline::AnimationFrame& frame) {
  f0_.push(frame.f0Hz);
  energy_.push(frame.energy);
  jaw_.push(frame.faps[3]);
  chosenFap_.push(frame.faps[static_cast<std::size_t>(plottedFap_)]);
  const Eigen::Vector3d headDegrees = face::headDegreesOf(frame.faps);
  for (int axis = 0; axis < 3; ++axis) head_[static_cast<std::size_t>(axis)].push(headDegrees[axis]);
  headPosteriors_.push(frame.headPosterior, frame.headStates);
  mouthPosteriors_.push(frame.mouthPosterior, frame.mouthStates);
}

void LivePanel::monitor(std::span<const float> samples, double rateHz) {
  const auto size = static_cast<std::size_t>(kWaveformSeconds * rateHz);
  if (waveform_.size() != size) waveform_.assign(size, 0.0f);
  for (const float sample : samples) waveform_[waveformAt_++ % waveform_.size()] = sample;
}

void LivePanel::showModelPaths(const std::string& head, const std::string& mouth) {
  const auto fill = [](std::array<char, 512>& field, const std::string& text) {
    field.fill('\0');
    std::copy_n(text.begin(), std::min(text.size(), field.size() - 1), field.begin());
  };
  fill(headPath_, head);
  fill(mouthPath_, mouth);
}

PanelChanges LivePanel::draw(const PanelView& view, std::pair<int, int> windowSize, int width) {
  // The whole column; its background is the frame's clear (the window's), so the window draws none.
  ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(width), static_cast<float>(windowSize.second)), ImGuiCond_Always);
  ImGui::Begin("Live", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoBackground);
  PanelChanges changes;
  // The plots near the top, where they stay in view whatever the sound section has to say.
  soundSection(view, changes);
  plotSection();
  latencySection(view);
  outputsSection(view, changes);
  settingsSection(view, changes);
  ImGui::End();
  return changes;
}

void LivePanel::soundSection(const PanelView& view, PanelChanges& changes) {
  if (!ImGui::CollapsingHeader("Sound", ImGuiTreeNodeFlags_DefaultOpen) || view.live == nullptr) return;
  const pipeline::LivePipeline& live = *view.live;
  if (!live.sourceError().empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kErrorColour);
    ImGui::TextWrapped("%s", live.sourceError().c_str());
    ImGui::PopStyleColor();
  } else {
    ImGui::TextWrapped("%s, %.0f Hz", live.sourceName().c_str(), live.rateHz());
  }
  if (live.isRecording()) {
    if (const audio::Playback* playback = live.playback())
      ImGui::TextWrapped(
          "played on %s, heard %.0f ms after it goes in, to meet the lips (device latency %.0f ms), %llu "
          "underruns",
          playback->device().name.c_str(), live.playbackLatencyMs(), playback->outputLatencySeconds() * 1000.0,
          static_cast<unsigned long long>(playback->underruns()));
    else
      ImGui::TextWrapped("not played aloud");
    return;
  }
  std::string& device = view.settings.live.device;
  const std::string current = device == "default" ? "default input" : "input " + device;
  if (ImGui::BeginCombo("input", current.c_str())) {
    if (ImGui::Selectable("default input", device == "default")) {
      device = "default";
      changes.device = true;
    }
    for (const audio::AudioDevice& each : live.devices()) {
      const std::string label = std::to_string(each.index) + ": " + each.name;
      if (ImGui::Selectable(label.c_str(), device == std::to_string(each.index))) {
        device = std::to_string(each.index);
        changes.device = true;
      }
    }
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("rescan")) changes.device = true;
}

void LivePanel::plotSection() {
  if (!ImGui::CollapsingHeader("Plots", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const float width = ImGui::GetContentRegionAvail().x;
  // The waveform as the peak of each of 400 stretches of the last two seconds, oldest first.
  peaks_.fill(0.0f);
  if (!waveform_.empty()) {
    const std::size_t span = waveform_.size() / peaks_.size();
    for (std::size_t p = 0; p < peaks_.size(); ++p)
      for (std::size_t i = 0; i < span; ++i)
        peaks_[p] = std::max(peaks_[p], std::abs(waveform_[(waveformAt_ + p * span + i) % waveform_.size()]));
  }
  ImGui::PlotHistogram("##wave", peaks_.data(), static_cast<int>(peaks_.size()), 0, "waveform (2 s)", 0.0f, 1.0f,
                       ImVec2(width, 50));
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

void LivePanel::latencySection(const PanelView& view) {
  if (!ImGui::CollapsingHeader("Latency", ImGuiTreeNodeFlags_DefaultOpen) || view.live == nullptr) return;
  const pipeline::LivePipeline& live = *view.live;
  const pipeline::FrameStats& stats = view.stats;
  const pipeline::DecoderLookahead& lookahead = live.lookahead();
  const double processing = stats.processingMs();
  const double queue = stats.queueMs();
  const double display = stats.behindMs() + stats.displayMs();
  ImGui::Text("look-ahead  %6.1f ms  (mouth %.0f, head %.0f%s)", lookahead.totalMs, lookahead.mouthMs, lookahead.headMs,
              lookahead.headDelayFrames > 0 ? ", shown late" : "");
  ImGui::Text("processing  %6.1f ms  (median, read to frame out)", processing);
  ImGui::Text("queueing    %6.1f ms  (frame out to the display)", queue);
  ImGui::Text("display     %6.1f ms  (playout %.1f + drawing %.1f)", display, stats.behindMs(), stats.displayMs());
  ImGui::Text("in all      %6.1f ms  (+ the sound device's buffer)", lookahead.totalMs + processing + queue + display);
  const pipeline::SessionCounters counters = live.counters();
  ImGui::Text("frames dropped %llu   samples overrun %llu   display starved %llu",
              static_cast<unsigned long long>(counters.framesDropped),
              static_cast<unsigned long long>(counters.overrunSamples),
              static_cast<unsigned long long>(view.displayStarved));
  if (!live.isRecording())
    ImGui::Text("device overflows %llu", static_cast<unsigned long long>(live.deviceOverflows()));
  const double period = stats.periodMs();
  ImGui::Text("display %.1f frames/s; per frame (median ms):", period > 0.0 ? 1000.0 / period : 0.0);
  ImGui::Text("  face %.1f, GL %.1f, panel %.1f (when drawn), swap %.1f", stats.faceSetupMs(), stats.glMs(),
              stats.panelMs(), stats.swapMs());
}

// Each output switched on and off, and how it is doing: where it sends, whether the receiver takes the frames.
void LivePanel::outputsSection(const PanelView& view, PanelChanges& changes) {
  if (!ImGui::CollapsingHeader("Outputs", ImGuiTreeNodeFlags_DefaultOpen)) return;
  for (const outputs::OutputRow& row : view.settings.outputs.rows()) {
    bool on = !row.address->empty();
    if (ImGui::Checkbox(std::string(row.title).c_str(), &on)) {
      *row.address = on ? std::string(row.defaultAddress) : std::string();
      changes.outputs = true;
    }
    for (const outputs::OutputStatus& status : view.outputs) {
      if (status.name != row.name) continue;
      if (!status.connected) ImGui::PushStyleColor(ImGuiCol_Text, kErrorColour);
      ImGui::TextWrapped("  %s: %s; %llu frames, %llu dropped", status.target.c_str(), status.state.c_str(),
                         static_cast<unsigned long long>(status.framesSent),
                         static_cast<unsigned long long>(status.framesDropped));
      if (!status.connected) ImGui::PopStyleColor();
      // Refused by its user (VTube Studio's Deny): asked again only when they say so; opening the outputs again
      // asks anew.
      if (status.refused && ImGui::Button(("Ask again##" + std::string(row.name)).c_str())) changes.outputs = true;
    }
  }
}

void LivePanel::settingsSection(const PanelView& view, PanelChanges& changes) {
  if (!ImGui::CollapsingHeader("Settings", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const PanelChanges made = settingsWidgets(view.settings);
  changes.reloadModels |= made.reloadModels;
  changes.redecode |= made.redecode;
  changes.newPlayout |= made.newPlayout;
  changes.idle |= made.idle;
  if (view.headStyles.size() > 1) {
    // A person's head style (talkinghead style, or --head-style): the head moves like them, or as the model does.
    int chosen = view.headStyle;
    std::vector<const char*> names;
    for (const std::string& name : view.headStyles) names.push_back(name.c_str());
    if (ImGui::Combo("head style", &chosen, names.data(), static_cast<int>(names.size())) && chosen != view.headStyle)
      changes.headStyle = chosen;
    if (!view.headStyleLine.empty()) ImGui::TextWrapped("%s", view.headStyleLine.c_str());
  }
  ImGui::TextUnformatted(view.speaking ? "(speech)" : "(silence: head at rest)");
  ImGui::InputText("head model", headPath_.data(), headPath_.size());
  ImGui::InputText("mouth model", mouthPath_.data(), mouthPath_.size());
  if (ImGui::Button("load model files")) {
    view.settings.models.headModel = headPath_.data();
    view.settings.models.mouthModel = mouthPath_.data();
    changes.reloadModels = true;
  }
  if (!view.modelError.empty()) ImGui::TextColored(kErrorColour, "%s", view.modelError.c_str());
  if (!view.character.empty()) ImGui::TextWrapped("character: %s", view.character.c_str());
}

// A column per frame, a row per state, brighter for more probable.
void LivePanel::posteriorPlot(const char* title, const Posteriors& posteriors, float width) {
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
void LivePanel::plot(const char* label, const Curve& curve, float low, float high, float width) {
  ImGui::PushID(label);
  ImGui::PlotLines(
      "##curve", [](void* data, int i) { return static_cast<const Curve*>(data)->values[static_cast<std::size_t>(i)]; },
      const_cast<Curve*>(&curve), static_cast<int>(curve.values.size()), 0, label, low, high, ImVec2(width, 40));
  ImGui::PopID();
}

}  // namespace th::app
