// `talkinghead sidebyside CLIP -o OUT.mp4`: the original talking video on the left and our face on the right,
// driven by the clip's sound alone (the mouth model, and the head model unless --head none), with the clip's
// sound: for a person to judge a model trained from video (`train --video`) against the speaker it learnt.
// With --avatar, the user's character on the right instead.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>

#include "character.h"
#include "cli_options.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_files.h"
#include "face/fap_track.h"
#include "face_stage.h"
#include "formats/mp4_writer.h"
#include "head_style_clip.h"
#include "interrupt.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"
#include "render/head.h"
#include "render/image.h"
#include "render/text_label.h"
#include "tracking/landmarks.h"
#include "tracking/video_reader.h"
#include "tracking/video_training.h"

namespace th::app {
namespace {

struct SideBySideArguments {
  std::string clip;
  std::string output;
  pipeline::ModelOptions models;
  pipeline::HeadMotionOptions head;
  pipeline::IdleOptions idle;
  int height = 0;      // 0: the clip's (made even)
  std::string avatar;  // a character drawn instead of our face
  // A .png output: a film strip of the stretch [fromSeconds, fromSeconds + seconds), every `every`-th video frame,
  // the clip's mouth above the face's.
  double fromSeconds = 0.0;
  double seconds = 2.0;
  int every = 2;
};

// The clip's frame `frame` (BGR), read through from the start.
struct ClipFrames {
  tracking::VideoReader& reader;
  cv::Mat current;
  int index = -1;
  const cv::Mat& at(int frame) {
    double seconds = 0.0;
    while (index < frame && reader.read(current, seconds)) ++index;
    return current;
  }
};

// Film strip: the speaker's mouth (a square round the lips, placed by the landmarks of the strip's first frame)
// above our face's, framed as close.
void writeStrip(const SideBySideArguments& arguments, tracking::VideoReader& clip, const face::FapTrack& animation,
                const avatar::Avatar* character) {
  const int height = (arguments.height > 0 ? arguments.height : 160) / 2 * 2;
  const int width = height;
  const double fps = clip.framesPerSecond();
  const int first = static_cast<int>(std::lround(arguments.fromSeconds * fps));
  const int count = std::max(1, static_cast<int>(std::floor(arguments.seconds * fps / arguments.every + 1e-9)));
  render::OffscreenHead stage(character, {.width = width, .height = height});
  stage.head->frameMouth();
  cv::Rect box;
  const int labelHeight = 20;
  const int columns = std::min(count, 10);
  const int rowHeight = 2 * height + labelHeight;
  render::Image sheet(width * columns, rowHeight * ((count + columns - 1) / columns));
  std::fill(sheet.pixels.begin(), sheet.pixels.end(), static_cast<unsigned char>(255));
  ClipFrames frames{clip, cv::Mat(), -1};
  cv::Mat scaled, rgb;
  for (int i = 0; i < count; ++i) {
    const int f = first + i * arguments.every;
    const cv::Mat& frame = frames.at(f);
    if (frame.empty() || frames.index < f) throw fileError(arguments.clip, "ends before the strip does");
    if (i == 0) {
      tracking::LandmarkDetector detector;
      tracking::Landmarks points;
      if (!detector.find(frame, points)) throw fileError(arguments.clip, "no face at the strip's start");
      // As much of the face round the lips as the close camera shows of ours: from the nose to the chin.
      const Eigen::Vector2d lips = points.middleCols(48, 20).rowwise().mean();
      const double side = 1.25 * (points.col(8) - points.col(33)).norm();
      box = cv::Rect(static_cast<int>(lips.x() - side / 2), static_cast<int>(lips.y() - side / 2),
                     static_cast<int>(side), static_cast<int>(side)) &
            cv::Rect(0, 0, frame.cols, frame.rows);
    }
    cv::resize(frame(box), scaled, cv::Size(width, height), 0.0, 0.0, cv::INTER_AREA);
    cv::cvtColor(scaled, rgb, cv::COLOR_BGR2RGB);
    const int left = i % columns * width, top = i / columns * rowHeight;
    for (int y = 0; y < height; ++y) std::copy_n(rgb.ptr<std::uint8_t>(y), width * 3, sheet.pixel(left, top + y));
    const render::Image& face = stage.head->draw(animation, f / fps);
    for (int y = 0; y < height; ++y) std::copy_n(face.pixel(0, y), width * 3, sheet.pixel(left, top + height + y));
    char label[32];
    std::snprintf(label, sizeof label, "%.2f", f / fps);
    render::drawLabel(sheet, left + 4, top + 2 * height + 2, label, 2);
  }
  render::writePng(arguments.output, sheet);
  std::cout << "wrote " << arguments.output << ": " << count << " frames of " << arguments.clip << " from "
            << arguments.fromSeconds << " s, every " << arguments.every << ", the clip above the face from its sound\n";
}

void runSideBySide(const SideBySideArguments& arguments) {
  InterruptGuard guard;
  const std::filesystem::path output = arguments.output;
  const bool strip = lowercaseExtension(output) == ".png";
  if (!strip && lowercaseExtension(output) != ".mp4")
    throw fileError(output, "a side-by-side video is an .mp4 file (or a .png film strip)");
  checkOutputTarget(output);
  const std::optional<avatar::Avatar> character = loadCharacter(arguments.avatar);
  const pipeline::AnimationModels models = pipeline::loadModels(arguments.models);
  tracking::VideoReader clip(arguments.clip);
  const audio::AudioClip sound = tracking::readClipSound(arguments.clip);
  pipeline::HeadMotionOptions head = arguments.head;
  pipeline::IdleOptions idle = arguments.idle;
  resolveHeadStyleClip(head, idle, arguments.models, std::cerr);
  face::FapTrack animation;
  try {
    animation = pipeline::animate(sound.samples, models, pipeline::animateOptionsOf(arguments.models, head, idle));
  } catch (const Error& error) {
    throw fileError(arguments.clip, error.what());
  }

  if (strip) {
    writeStrip(arguments, clip, animation, character ? &*character : nullptr);
    return;
  }
  // Both halves as high as the output, each as wide as the clip scaled to it.
  const int height = (arguments.height > 0 ? arguments.height : clip.height()) / 2 * 2;
  const int half = std::max(2, static_cast<int>(static_cast<double>(clip.width()) * height / clip.height()) / 2 * 2);
  const double fps = clip.framesPerSecond();
  render::OffscreenHead stage(character ? &*character : nullptr, {.width = half, .height = height});
  formats::Mp4Options mp4;
  mp4.width = 2 * half;
  mp4.height = height;
  mp4.framesPerSecond = fps;
  mp4.audioSampleRateHz = sound.sampleRateHz;
  formats::Mp4Writer writer(output, mp4);
  writer.addAudio(sound.samples);
  render::Image canvas(2 * half, height);
  cv::Mat frame, scaled, rgb;
  double seconds = 0.0;
  const auto frames = formats::videoFramesFor(sound.samples.size(), sound.sampleRateHz, fps);
  ProgressBar bar(static_cast<double>(frames), "sidebyside", std::cerr, progressAt(fps));
  for (std::int64_t f = 0; f < frames; ++f) {
    InterruptGuard::check();
    // The clip's frame, the last one held if the picture ends before the sound.
    if (clip.read(frame, seconds) || f == 0) {
      cv::resize(frame, scaled, cv::Size(half, height), 0.0, 0.0, cv::INTER_AREA);
      cv::cvtColor(scaled, rgb, cv::COLOR_BGR2RGB);
    }
    for (int y = 0; y < height; ++y) std::copy_n(rgb.ptr<std::uint8_t>(y), half * 3, canvas.pixel(0, y));
    const render::Image& face = stage.head->draw(animation, static_cast<double>(f) / fps);
    for (int y = 0; y < height; ++y) std::copy_n(face.pixel(0, y), half * 3, canvas.pixel(half, y));
    const int scale = height >= 480 ? 2 : 1;
    render::drawLabel(canvas, 6, 6, "video", scale);
    render::drawLabel(canvas, half + 6, 6, "from its sound: " + arguments.models.mouthModelPath().filename().string(),
                      scale);
    writer.addVideoFrame(canvas.pixels.data(), canvas.width * 3);
    bar.update(static_cast<double>(f + 1));
  }
  writer.finish();
  bar.finish();
  std::cout << "wrote " << output.string() << " (" << 2 * half << "x" << height << ", " << fps << " fps, "
            << sound.durationSeconds() << " s): " << arguments.clip << " | the face from its sound\n";
}

}  // namespace

void addSideBySideCommand(CLI::App& app) {
  auto arguments = std::make_shared<SideBySideArguments>();
  CLI::App* command = app.add_subcommand(
      "sidebyside", "Talking video -> MP4 of it beside our face driven by its sound alone (to judge a model by eye)");
  command->add_option("clip", arguments->clip, "Talking video (its sound, or the .wav of its name beside it)")
      ->required();
  command
      ->add_option("-o,--output", arguments->output,
                   "MP4 file to write, or a .png film strip (--from, --seconds, --every)")
      ->required();
  command->add_option("--from", arguments->fromSeconds, ".png: where the strip starts (seconds)")
      ->check(CLI::Range(0.0, 1e6));
  command->add_option("--seconds", arguments->seconds, ".png: how long it lasts")->check(CLI::Range(0.01, 60.0));
  command->add_option("--every", arguments->every, ".png: video frames between tiles")->check(CLI::Range(1, 1000));
  addOptions(*command, arguments->models);  // --head none: the face's head still, the mouth alone
  addOptions(*command, arguments->head);
  addOptions(*command, arguments->idle);
  addAvatarOption(*command, arguments->avatar);
  command->add_option("--height", arguments->height, "Output height in pixels (default: the clip's)")
      ->check(CLI::Range(64, 2160));
  command->callback([arguments] { runSideBySide(*arguments); });
}

}  // namespace th::app
