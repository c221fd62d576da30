// `talkinghead show`: the face in a window. Drag to orbit, scroll to zoom; a Dear ImGui panel has a slider for
// every FAP the face can show (grouped as the standard groups them), the key poses, and a player for an
// animation file. With --avatar, the user's character instead, moved by the same sliders and animation. `--screenshot
// PNG --frames N` saves the window after N frames and quits (for tests under Xvfb). glad before GLFW: glad's header
// stands in for the system GL header that GLFW would otherwise pull in.
#include <glad/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "character.h"
#include "commands.h"
#include "core/error.h"
#include "face/face_model.h"
#include "face/fap.h"
#include "face/poses.h"
#include "formats/animation_format.h"
#include "render/gl_context.h"
#include "render/head.h"
#include "render/image.h"
#include "window_capture.h"

namespace th::app {
namespace {

struct ShowArguments {
  std::string animation;
  std::string avatar;  // a character drawn instead of our face
  std::string screenshot;
  int frames = 3;
  int width = 1280, height = 720;
};

// The slider range of a FAP: a full unit of 1024 FAPU each way (a FAP 3 of 1024 drops the chin by the
// mouth-nose distance), ±40° for rotations, 0..1024 for the unidirectional ones.
std::pair<float, float> sliderRange(const face::FapDefinition& fap) {
  if (fap.unit == face::Fapu::kAngle) return {-70000.0f, 70000.0f};
  return {fap.bidirectional ? -1024.0f : 0.0f, 1024.0f};
}

// A slider for every FAP the face shows, under a header per group (the jaw and the inner lip open at start);
// true when one was moved (`faps` holds the new value).
bool fapSliders(const face::FaceModel& face, const std::vector<std::string_view>& groups, face::FapFrame& faps) {
  bool moved = false;
  ImGui::PushItemWidth(-190.0f);
  for (std::string_view group : groups) {
    const bool openAtStart = group == "jaw" || group == "inner lip";
    if (!ImGui::CollapsingHeader(std::string(group).c_str(), openAtStart ? ImGuiTreeNodeFlags_DefaultOpen : 0))
      continue;
    for (int number = 3; number <= face::kNumFaps; ++number) {
      const face::FapDefinition& fap = face::fapDefinition(number);
      if (!face.supports(number) || fap.group != group) continue;
      float value = static_cast<float>(faps[static_cast<std::size_t>(number)]);
      const auto [low, high] = sliderRange(fap);
      char label[64];
      std::snprintf(label, sizeof label, "%d %s", number, std::string(fap.name).c_str());
      if (ImGui::SliderFloat(label, &value, low, high, fap.unit == face::Fapu::kAngle ? "%.0f AU" : "%.0f")) {
        faps[static_cast<std::size_t>(number)] = value;
        moved = true;
      }
    }
  }
  ImGui::PopItemWidth();
  return moved;
}

// One panel header per FAP group, in the order the standard first names it.
std::vector<std::string_view> fapGroupsOf(const face::FaceModel& face) {
  std::vector<std::string_view> groups;
  for (int number = 3; number <= face::kNumFaps; ++number)
    if (face.supports(number) &&
        std::find(groups.begin(), groups.end(), face::fapDefinition(number).group) == groups.end())
      groups.push_back(face::fapDefinition(number).group);
  return groups;
}

// Orbit with the left button, zoom with the wheel, unless the panel has the mouse.
void orbitWithMouse(render::OrbitCamera& camera, const render::OrbitCamera& home) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantCaptureMouse) return;
  if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
    camera.yawDegrees -= 0.3f * io.MouseDelta.x;
    camera.pitchDegrees = std::clamp(camera.pitchDegrees + 0.3f * io.MouseDelta.y, -80.0f, 80.0f);
  }
  camera.distance =
      std::clamp(camera.distance * (1.0f - 0.1f * io.MouseWheel), 0.25f * home.distance, 6.0f * home.distance);
}

// A button per key pose; true when one was pressed (its FAPs are then in `faps`).
bool poseButtons(face::FapFrame& faps) {
  bool pressed = false;
  ImGui::TextUnformatted("Poses:");
  for (const face::Pose& pose : face::keyPoses()) {
    ImGui::SameLine();
    if (ImGui::GetContentRegionAvail().x < 80) ImGui::NewLine();
    if (ImGui::SmallButton(pose.name.c_str())) faps = pose.faps, pressed = true;
  }
  return pressed;
}

// What the panel changes from frame to frame.
struct ShowState {
  face::FapFrame faps{};
  bool playing = false;
  double playStart = 0.0;  // glfwGetTime() when the animation last started playing
};

// What the panel shows, unchanged from frame to frame.
struct ShowPanel {
  const std::optional<face::FapTrack>& animation;
  const face::FaceModel& face;
  const std::vector<std::string_view>& groups;
  std::string description;  // the character's (empty for our face)
  int height = 0;           // the window's, for the panel's first size
};

// The panel, ImGui's "Face" window: reset buttons, play or pause, key poses, the FAPs'
// sliders. Returns the instant of the animation playing (-1: none; the FAPs in `state` are shown).
double facePanel(ShowState& state, const ShowPanel& panel, render::OrbitCamera& camera,
                 const render::OrbitCamera& home) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(420, static_cast<float>(panel.height) - 20), ImGuiCond_FirstUseEver);
  ImGui::Begin("Face");
  if (!panel.description.empty()) ImGui::TextUnformatted(panel.description.c_str());
  if (ImGui::Button("Reset FAPs")) state.faps = {};
  ImGui::SameLine();
  if (ImGui::Button("Reset view")) camera = home;
  if (panel.animation) {
    ImGui::SameLine();
    if (ImGui::Button(state.playing ? "Pause" : "Play")) {
      state.playing = !state.playing;
      state.playStart = glfwGetTime();
    }
  }
  if (poseButtons(state.faps)) state.playing = false;
  double seconds = -1.0;
  if (state.playing && panel.animation) {
    seconds = std::fmod(glfwGetTime() - state.playStart, panel.animation->durationSeconds());
    state.faps = panel.animation->at(seconds);
  }
  if (fapSliders(panel.face, panel.groups, state.faps)) state.playing = false;
  ImGui::End();
  return seconds;
}

void runShow(const ShowArguments& arguments) {
  std::optional<face::FapTrack> animation;
  if (!arguments.animation.empty()) animation = formats::readAnimation(arguments.animation);
  const std::optional<avatar::Avatar> character = loadCharacter(arguments.avatar);
  const face::FaceModel face = face::FaceModel::buildDefault();  // its FAPs are the sliders, whoever is drawn
  render::WindowContext window(
      {.width = arguments.width, .height = arguments.height, .title = "talkinghead", .visible = true, .vsync = true});
  const std::unique_ptr<render::Head> head = render::makeHead(
      character ? &*character : nullptr, window, {.width = arguments.width, .height = arguments.height}, &face);
  render::OrbitCamera& camera = head->camera();
  const render::OrbitCamera home = camera;

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window.window(), true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  const std::vector<std::string_view> groups = fapGroupsOf(face);

  ShowState state{.playing = animation.has_value(), .playStart = glfwGetTime()};
  int frame = 0;
  std::pair<int, int> lastSize{0, 0};
  while (!window.shouldClose()) {
    glfwPollEvents();
    const auto size = window.framebufferSize();
    if (size.first <= 0 || size.second <= 0) continue;  // minimised
    if (size != lastSize) {
      // The orbit the user set stays.
      const render::OrbitCamera orbit = camera;
      head->resize(size.first, size.second);
      camera = orbit;
      lastSize = size;
    }
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();

    orbitWithMouse(camera, home);

    const double seconds = facePanel(state,
                                     {.animation = animation,
                                      .face = face,
                                      .groups = groups,
                                      .description = character ? head->description() : std::string(),
                                      .height = size.second},
                                     camera, home);
    ImGui::Render();

    // A playing animation poses the head with its visemes too (a character's viseme targets); sliders and poses
    // with FAPs.
    if (seconds >= 0.0)
      head->poseAt(*animation, seconds);
    else
      head->pose(state.faps, nullptr);
    head->drawIntoWindow(window);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (!arguments.screenshot.empty() && ++frame >= arguments.frames) {
      render::writePng(arguments.screenshot, grabWindow(size));
      std::cout << "wrote " << arguments.screenshot << '\n';
      break;
    }
    window.swapBuffers();
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

}  // namespace

void addShowCommand(CLI::App& app) {
  auto arguments = std::make_shared<ShowArguments>();
  CLI::App* show =
      app.add_subcommand("show", "The face in a window: orbit it, move every FAP with sliders, play an animation");
  show->add_option("--anim", arguments->animation, "Animation to play (.csv, .json, .fap)");
  addAvatarOption(*show, arguments->avatar);
  show->add_option("--screenshot", arguments->screenshot, "Save the window as PNG after --frames frames and quit");
  show->add_option("--frames", arguments->frames, "Frames before the screenshot")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  show->add_option("--width", arguments->width, "Window width")->check(CLI::Range(320, 7680))->capture_default_str();
  show->add_option("--height", arguments->height, "Window height")->check(CLI::Range(240, 4320))->capture_default_str();
  show->callback([arguments] { runShow(*arguments); });
}

}  // namespace th::app
