// The face on screen and in files: `render` (animation → PNG frames), `poses` (a contact sheet of key poses),
// `strip` (a film strip of a stretch of speech), `export` (recording → MP4 with the face speaking it, plus the
// animation files on request).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "audio/media_audio.h"
#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "character.h"
#include "cli_options.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/text_files.h"
#include "eval/phone_labels.h"
#include "eval/talking_corpus.h"
#include "face/face_model.h"
#include "face/poses.h"
#include "face_stage.h"
#include "formats/animation_format.h"
#include "formats/arkit_format.h"
#include "formats/mp4_writer.h"
#include "head_style_clip.h"
#include "interrupt.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"
#include "pipeline/recording_export.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "render/head.h"
#include "render/image.h"
#include "render/text_label.h"

namespace th::app {
namespace {

// ---- render ----

struct RenderArguments {
  std::string animation;
  std::string output;
  std::string size = "640x480";
  double fps = 0.0;  // 0: the animation's
  pipeline::IdleOptions idle;
  std::string avatar;  // --avatar: the user's character instead of our face
};

void runRender(const RenderArguments& arguments) {
  InterruptGuard guard;
  const auto [width, height] = parseSize(arguments.size);
  face::FapTrack animation = formats::readAnimation(arguments.animation);
  pipeline::addIdleIfMissing(animation, arguments.idle);
  const std::optional<avatar::Avatar> character = loadCharacter(arguments.avatar);
  const std::filesystem::path folder = arguments.output;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (!std::filesystem::is_directory(folder, error)) throw fileError(folder, "is not a folder and cannot be made one");
  const double fps = arguments.fps > 0.0 ? arguments.fps : animation.framesPerSecond;
  const auto frames = static_cast<int>(std::ceil(animation.durationSeconds() * fps - 1e-9));
  render::OffscreenHead stage(character ? &*character : nullptr, {.width = width, .height = height});
  ProgressBar progress(frames, "render", std::cerr, progressAt(fps));
  char name[32];
  for (int frame = 0; frame < frames; ++frame) {
    InterruptGuard::check();
    std::snprintf(name, sizeof name, "frame_%06d.png", frame);
    const double seconds = frame / fps;
    render::writePng(folder / name, stage.head->draw(animation, seconds));
    progress.update(frame + 1);
  }
  progress.finish();
  std::cout << "wrote " << frames << " frames (" << width << "x" << height << ", " << fps << " fps) to "
            << folder.string() << '\n';
}

// ---- poses ----

struct PosesArguments {
  std::string output = "docs/face_poses.png";
  int tile = 360;
  int columns = 3;
};

void runPoses(const PosesArguments& arguments) {
  checkOutputTarget(arguments.output);
  const std::vector<face::Pose> poses = face::keyPoses();
  const int rows = (static_cast<int>(poses.size()) + arguments.columns - 1) / arguments.columns;
  render::OffscreenHead stage(nullptr, {.width = arguments.tile, .height = arguments.tile});
  render::Image sheet(arguments.tile * arguments.columns, arguments.tile * rows);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const render::Image& tile = stage.head->draw(poses[i].faps);
    const int left = static_cast<int>(i) % arguments.columns * arguments.tile;
    const int top = static_cast<int>(i) / arguments.columns * arguments.tile;
    for (int y = 0; y < tile.height; ++y) std::copy_n(tile.pixel(0, y), tile.width * 3, sheet.pixel(left, top + y));
    render::drawLabel(sheet, left + 8, top + 8, poses[i].title, 2);
  }
  render::writePng(arguments.output, sheet);
  std::cout << "wrote " << arguments.output << ": " << poses.size() << " poses\n";
}

// ---- strip ----

struct StripArguments {
  std::string animation;
  std::string output;
  double fromSeconds = 0.0;
  double seconds = 2.0;
  int every = 2;  // animation frames between tiles
  int columns = 10;
  int tile = 160;
  std::string phones;  // a TextGrid whose "phones" tier labels each tile
  bool wholeHead = false;
};

// Film strip: every `every`-th frame of a stretch of an animation side by side, the mouth framed close (the head
// held still), each tile labelled with its time (and its phone, given a TextGrid), so a reader sees the lips follow the
// syllables.
void runStrip(const StripArguments& arguments) {
  if (lowercaseExtension(arguments.output) != ".png")
    throw fileError(arguments.output, "a film strip is written as .png");
  checkOutputTarget(arguments.output);
  const face::FapTrack animation = formats::readAnimation(arguments.animation);
  std::vector<eval::LabelInterval> phones;
  if (!arguments.phones.empty())
    phones = lowercaseExtension(arguments.phones) == ".align"
                 ? eval::gridPhones(eval::readGridAlignment(arguments.phones))
                 : eval::readTextGridPhones(arguments.phones);
  const double step = arguments.every / animation.framesPerSecond;
  const int count = std::max(1, static_cast<int>(std::floor(arguments.seconds / step + 1e-9)));
  if (arguments.fromSeconds + (count - 1) * step > animation.durationSeconds() + 1e-9)
    throw fileError(arguments.animation,
                    "ends before the strip does (" + std::to_string(animation.durationSeconds()) + " s)");
  render::OffscreenHead stage(nullptr, {.width = arguments.tile, .height = arguments.tile});
  if (!arguments.wholeHead) stage.head->frameMouth();
  const int rows = (count + arguments.columns - 1) / arguments.columns;
  const int labelHeight = 22;
  render::Image sheet(arguments.tile * std::min(count, arguments.columns), (arguments.tile + labelHeight) * rows);
  std::fill(sheet.pixels.begin(), sheet.pixels.end(), static_cast<unsigned char>(255));
  for (int i = 0; i < count; ++i) {
    const double seconds = arguments.fromSeconds + i * step;
    face::FapFrame faps = animation.at(seconds);
    if (!arguments.wholeHead) faps[48] = faps[49] = faps[50] = 0.0;  // the head held still under a close camera
    const render::Image& tile = stage.head->draw(faps);
    const int left = i % arguments.columns * arguments.tile;
    const int top = i / arguments.columns * (arguments.tile + labelHeight);
    for (int y = 0; y < tile.height; ++y) std::copy_n(tile.pixel(0, y), tile.width * 3, sheet.pixel(left, top + y));
    char label[64];
    std::snprintf(label, sizeof label, "%.2f", seconds);
    std::string text = label;
    for (const eval::LabelInterval& phone : phones)
      if (phone.startSeconds <= seconds && seconds < phone.endSeconds && phone.label != "SIL")
        text += " " + phone.label;
    render::drawLabel(sheet, left + 4, top + arguments.tile + 3, text, 2);
  }
  render::writePng(arguments.output, sheet);
  std::cout << "wrote " << arguments.output << ": " << count << " frames from " << arguments.fromSeconds << " s, every "
            << arguments.every << " frames\n";
}

// ---- export ----

struct ExportArguments {
  std::string input;
  std::string output;
  std::string size = "1280x720";
  double fps = 30.0;
  std::string animation;                   // --anim: play this instead of the models' animation
  std::vector<std::string> saveAnimation;  // --save-anim: .fap / .csv / .json beside the video
  std::string arkit;                       // --arkit: ARKit blendshape weights CSV
  pipeline::ModelOptions models;
  pipeline::HeadMotionOptions head;
  pipeline::IdleOptions idle;
  int crf = 20;
  std::string preset = "veryfast";
  std::string avatar;  // --avatar: the user's character instead of our face
};

void runExport(const ExportArguments& arguments) {
  InterruptGuard guard;
  // Everything that can be checked before the work is checked first.
  const auto [width, height] = parseSize(arguments.size);
  if (lowercaseExtension(arguments.output) != ".mp4") throw fileError(arguments.output, "an export is an .mp4 file");
  checkOutputTarget(arguments.output);
  for (const std::string& path : arguments.saveAnimation) {
    formats::animationFormatFor(path);
    checkOutputTarget(path);
  }
  if (!arguments.arkit.empty()) checkOutputTarget(arguments.arkit);
  const std::optional<avatar::Avatar> character = loadCharacter(arguments.avatar);

  pipeline::RecordingExport job;
  job.recording = arguments.input;
  job.output = arguments.output;
  job.video.width = width;
  job.video.height = height;
  job.video.framesPerSecond = arguments.fps;
  job.video.crf = arguments.crf;
  job.video.preset = arguments.preset;
  job.video.avatar = character ? &*character : nullptr;
  job.animation = arguments.animation;
  job.models = arguments.models;
  job.head = arguments.head;
  job.idle = arguments.idle;
  if (arguments.animation.empty()) resolveHeadStyleClip(job.head, job.idle, job.models, std::cerr);
  std::optional<ProgressBar> progress;  // made when the number of frames is known
  const auto showProgress = [&](int frames, int total) {
    if (!progress) progress.emplace(static_cast<double>(total), "export", std::cerr, progressAt(arguments.fps));
    progress->update(frames);
  };
  pipeline::RecordingExportResult done;
  try {
    done = pipeline::exportRecording(job, {.progress = showProgress, .cancelled = InterruptGuard::requested});
  } catch (const Cancelled&) {
    InterruptGuard::check();  // says it was an interrupt
    throw;
  }
  if (progress) progress->finish();
  for (const std::string& path : arguments.saveAnimation) formats::writeAnimation(path, done.animation);
  if (!arguments.arkit.empty())
    formats::writeAnimation(arguments.arkit, done.animation, formats::ArkitFormat(formats::arkitScaleFor(done.face)));
  std::cout << "wrote " << arguments.output << " (" << width << "x" << height << ", " << arguments.fps << " fps, "
            << done.seconds << " s)\n";
}

}  // namespace

void addFaceCommands(CLI::App& app) {
  auto renderArguments = std::make_shared<RenderArguments>();
  CLI::App* render = app.add_subcommand("render", "Animation (.csv, .json or .fap) -> PNG frames of the face");
  render->add_option("animation", renderArguments->animation, "Animation file")->required();
  render->add_option("-o,--output", renderArguments->output, "Folder for frame_000000.png, ...")->required();
  render->add_option("--size", renderArguments->size, "WIDTHxHEIGHT")->capture_default_str();
  render->add_option("--fps", renderArguments->fps, "Frames per second (default: the animation's)")
      ->check(CLI::Range(1.0, 240.0));
  addOptions(*render, renderArguments->idle);
  addAvatarOption(*render, renderArguments->avatar);
  render->callback([renderArguments] { runRender(*renderArguments); });

  auto posesArguments = std::make_shared<PosesArguments>();
  CLI::App* poses = app.add_subcommand("poses", "A contact sheet PNG of the face's key poses");
  poses->add_option("-o,--output", posesArguments->output, "PNG to write")->capture_default_str();
  poses->add_option("--tile", posesArguments->tile, "Pixels per pose (square)")
      ->check(CLI::Range(64, 2048))
      ->capture_default_str();
  poses->callback([posesArguments] { runPoses(*posesArguments); });

  auto stripArguments = std::make_shared<StripArguments>();
  CLI::App* strip =
      app.add_subcommand("strip", "Animation -> a film strip PNG: every N-th frame of a stretch, the mouth close");
  strip->add_option("animation", stripArguments->animation, "Animation file (.csv, .json or .fap)")->required();
  strip->add_option("-o,--output", stripArguments->output, "PNG to write")->required();
  strip->add_option("--from", stripArguments->fromSeconds, "Start (seconds)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  strip->add_option("--seconds", stripArguments->seconds, "Length (seconds)")
      ->check(CLI::Range(0.01, 60.0))
      ->capture_default_str();
  strip->add_option("--every", stripArguments->every, "Animation frames between tiles")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  strip->add_option("--columns", stripArguments->columns, "Tiles per row")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  strip->add_option("--tile", stripArguments->tile, "Pixels per tile (square)")
      ->check(CLI::Range(64, 1024))
      ->capture_default_str();
  strip->add_option("--phones", stripArguments->phones,
                    "Praat TextGrid with a \"phones\" tier, or a GRID .align of words (phones from GRID's lexicon): "
                    "each tile's phone under it");
  strip->add_flag("--whole-head", stripArguments->wholeHead,
                  "Frame the whole head, turning as animated, rather than the mouth");
  strip->callback([stripArguments] { runStrip(*stripArguments); });

  auto exportArguments = std::make_shared<ExportArguments>();
  CLI::App* exporter =
      app.add_subcommand("export", "Recording -> MP4 (H.264 + AAC) of the face speaking it, rendered off-screen");
  exporter->add_option("input", exportArguments->input, "Recording (WAV, FLAC, ... or a video's audio track)")
      ->required();
  exporter->add_option("-o,--output", exportArguments->output, "MP4 file to write")->required();
  exporter->add_option("--size", exportArguments->size, "WIDTHxHEIGHT, both even")->capture_default_str();
  exporter->add_option("--fps", exportArguments->fps, "Video frames per second")
      ->check(CLI::Range(1.0, 120.0))
      ->capture_default_str();
  exporter->add_option("--anim", exportArguments->animation,
                       "Play this animation (.csv, .json, .fap) instead of the models'");
  exporter->add_option("--save-anim", exportArguments->saveAnimation,
                       "Also write the animation (.fap MPEG-4 FAP stream, .csv or .json); repeatable");
  exporter->add_option("--arkit", exportArguments->arkit,
                       "Also write ARKit blendshape weights (CSV: time_s + 52 names)");
  addOptions(*exporter, exportArguments->models);
  addOptions(*exporter, exportArguments->head);
  addOptions(*exporter, exportArguments->idle);
  exporter->add_option("--crf", exportArguments->crf, "H.264 quality (lower is better and larger)")
      ->check(CLI::Range(0, 51))
      ->capture_default_str();
  exporter->add_option("--preset", exportArguments->preset, "x264 preset (ultrafast ... veryslow)")
      ->capture_default_str();
  addAvatarOption(*exporter, exportArguments->avatar);
  exporter->callback([exportArguments] { runExport(*exportArguments); });
}

}  // namespace th::app
