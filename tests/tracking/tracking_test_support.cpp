#include "tracking_test_support.h"

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/error.h"
#include "eval/mouth_evaluation.h"
#include "formats/mp4_writer.h"
#include "tracking/mjpeg_writer.h"
#include "tracking/video_reader.h"

namespace th::test {

void writeFacelessVideo(const std::filesystem::path& path) {
  constexpr int kWidth = 320, kHeight = 240, kFrames = 50;
  formats::Mp4Options options;
  options.width = kWidth;
  options.height = kHeight;
  options.framesPerSecond = 25.0;
  formats::Mp4Writer writer(path, options);
  std::vector<float> tone(32000);
  for (std::size_t n = 0; n < tone.size(); ++n)
    tone[n] = 0.3f * static_cast<float>(std::sin(2.0 * std::numbers::pi * 220.0 * static_cast<double>(n) / 16000.0));
  writer.addAudio(tone);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(kWidth * kHeight * 3));
  for (int f = 0; f < kFrames; ++f) {
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        for (int c = 0; c < 3; ++c)
          rgb[static_cast<std::size_t>((y * kWidth + x) * 3 + c)] =
              static_cast<std::uint8_t>((x + y + 2 * f + 20 * c) % 256);
    writer.addVideoFrame(rgb.data(), kWidth * 3);
  }
  writer.finish();
}

void writeSoundlessCopy(const std::filesystem::path& source, const std::filesystem::path& path) {
  tracking::VideoReader reader(source);
  tracking::MjpegWriter writer(path, reader.framesPerSecond(), reader.width(), reader.height());
  cv::Mat frame;
  double seconds = 0.0;
  while (reader.read(frame, seconds)) writer.write(frame);
  writer.finish();
}

std::vector<double> levelPerFrame(const audio::AudioClip& sound, double framesPerSecond, std::size_t frames) {
  const std::size_t hop = static_cast<std::size_t>(std::lround(sound.sampleRateHz / framesPerSecond));
  std::vector<double> level;
  for (std::size_t f = 0; f < frames && (f + 1) * hop <= sound.samples.size(); ++f) {
    double energy = 0.0;
    for (std::size_t n = f * hop; n < (f + 1) * hop; ++n)
      energy += static_cast<double>(sound.samples[n]) * sound.samples[n];
    level.push_back(10.0 * std::log10(energy / static_cast<double>(hop) + 1e-10));
  }
  return level;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) throw Error("correlation: the series differ in length");
  const Eigen::Map<const Eigen::RowVectorXd> x(a.data(), static_cast<Eigen::Index>(a.size()));
  const Eigen::Map<const Eigen::RowVectorXd> y(b.data(), static_cast<Eigen::Index>(b.size()));
  return eval::averageCorrelation(x, y);
}

}  // namespace th::test
