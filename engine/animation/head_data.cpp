#include "animation/head_data.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "animation/speech_analysis.h"
#include "animation/time_split.h"
#include "audio/audio_file.h"
#include "core/error.h"
#include "core/numeric_csv.h"

namespace th::animation {
namespace {

// The rotation columns of either kind of head-pose CSV.
std::array<int, 3> poseColumns(const NumericTable& pose) {
  if (pose.findColumn("neckhead_pitch_deg") >= 0)
    return {pose.column("neckhead_pitch_deg"), pose.column("neckhead_yaw_deg"), pose.column("neckhead_roll_deg")};
  if (pose.findColumn("pitch_deg") >= 0)
    return {pose.column("pitch_deg"), pose.column("yaw_deg"), pose.column("roll_deg")};
  throw fileError(pose.source,
                  "has neither pitch_deg, yaw_deg, roll_deg nor neckhead_pitch_deg... columns (a head-pose CSV "
                  "needs one set, as `talkinghead track` writes)");
}

// 3 x N rotations at `fps` as frames at kHeadFramesPerSecond: as they are when the rates agree (a 30 fps pose), else
// linear.
Eigen::MatrixXd atHeadRate(const Eigen::MatrixXd& rotations, double fps) {
  if (std::abs(fps - kHeadFramesPerSecond) < 1e-3 * kHeadFramesPerSecond) return rotations;
  const Eigen::Index poseFrames = rotations.cols();
  const double lastSeconds = static_cast<double>(poseFrames - 1) / fps;
  const auto frames = static_cast<Eigen::Index>(std::floor(lastSeconds * kHeadFramesPerSecond + 1e-9)) + 1;
  Eigen::MatrixXd out(3, frames);
  for (Eigen::Index i = 0; i < frames; ++i) {
    const double position = static_cast<double>(i) / kHeadFramesPerSecond * fps;
    const auto before = std::min<Eigen::Index>(static_cast<Eigen::Index>(position), poseFrames - 1);
    const Eigen::Index after = std::min<Eigen::Index>(before + 1, poseFrames - 1);
    const double share = position - static_cast<double>(before);
    out.col(i) = (1.0 - share) * rotations.col(before) + share * rotations.col(after);
  }
  return out;
}

}  // namespace

Eigen::MatrixXd smoothFrames(const Eigen::MatrixXd& frames, double sigmaFrames) {
  const int radius = static_cast<int>(std::ceil(3.0 * sigmaFrames));
  std::vector<double> kernel(static_cast<size_t>(2 * radius + 1));
  for (int k = -radius; k <= radius; ++k)
    kernel[static_cast<size_t>(k + radius)] = std::exp(-0.5 * k * k / (sigmaFrames * sigmaFrames));
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(frames.rows(), frames.cols());
  const Eigen::Index last = frames.cols() - 1;
  for (Eigen::Index t = 0; t <= last; ++t) {
    double weight = 0.0;
    for (int k = -radius; k <= radius; ++k) {
      const Eigen::Index u = std::clamp<Eigen::Index>(t + k, 0, last);  // the edge frame repeated
      out.col(t) += kernel[static_cast<size_t>(k + radius)] * frames.col(u);
      weight += kernel[static_cast<size_t>(k + radius)];
    }
    out.col(t) /= weight;
  }
  return out;
}

HeadRecording framesOf(const HeadRecording& take, int begin, int count) {
  if (begin < 0 || count < 0 || begin + count > take.numFrames()) throw Error("head data: frames out of range");
  HeadRecording part = take;
  part.rotations = take.rotations.middleCols(begin, count);
  part.prosody = take.prosody.middleCols(begin, count);
  part.voiced = take.voiced.segment(begin, count);
  part.levelDb = take.levelDb.segment(begin, count);
  part.startSeconds = take.startSeconds + begin / take.framesPerSecond;
  return part;
}

HeadRecording headRecordingOf(const Eigen::MatrixXd& rotations, double poseFps, std::span<const float> samples16k,
                              const std::string& name, const ProsodyOptions& prosody) {
  if (rotations.rows() != 3) throw Error(name + ": head rotations need 3 rows (pitch, yaw, roll)");
  if (!(poseFps > 0.0)) throw Error(name + ": the head pose has no frame rate");
  if (rotations.cols() < 2) throw Error(name + ": fewer than 2 frames of head pose");
  const Eigen::MatrixXd pose = atHeadRate(rotations, poseFps);
  const SpeechAnalysis heard = analyseSpeech(samples16k, prosody);
  const int frames = std::min(static_cast<int>(pose.cols()), heard.numFrames());
  if (frames < 2) throw Error(name + ": the sound is shorter than two animation frames");
  HeadRecording take;
  take.name = name;
  take.framesPerSecond = kHeadFramesPerSecond;
  take.rotations = pose.leftCols(frames);
  take.prosody = heard.prosody.leftCols(frames);
  take.voiced = heard.voiced.head(frames);
  take.levelDb = heard.speech.levelDb.head(frames);
  return take;
}

HeadRecording readHeadRecording(const std::filesystem::path& wav, const std::filesystem::path& poseCsv,
                                const ProsodyOptions& prosody) {
  const NumericTable pose = readNumericCsv(poseCsv);
  const std::array<int, 3> columns = poseColumns(pose);
  if (pose.rows.size() < 2) throw fileError(poseCsv, "has fewer than 2 frames of head pose");
  const auto rows = static_cast<Eigen::Index>(pose.rows.size());
  Eigen::MatrixXd rotations(3, rows);
  for (Eigen::Index t = 0; t < rows; ++t) {
    for (int axis = 0; axis < 3; ++axis)
      rotations(axis, t) = pose.rows[static_cast<size_t>(t)][static_cast<size_t>(columns[static_cast<size_t>(axis)])];
  }
  double fps = kHeadFramesPerSecond;
  if (const int time = pose.findColumn("time_s"); time >= 0) {
    const double first = pose.rows.front()[static_cast<size_t>(time)];
    const double last = pose.rows.back()[static_cast<size_t>(time)];
    if (!(last > first)) throw fileError(poseCsv, "its time_s does not increase");
    fps = static_cast<double>(rows - 1) / (last - first);
    // Times printed to a tenth of a millisecond: a 30 fps pose reads as 30 within that.
    if (std::abs(fps - kHeadFramesPerSecond) < 0.01 * kHeadFramesPerSecond) fps = kHeadFramesPerSecond;
  }
  if (const int face = pose.findColumn("face"); face >= 0) {
    double found = 0.0;
    for (const auto& row : pose.rows) found += row[static_cast<size_t>(face)] != 0.0;
    if (found < 0.5 * static_cast<double>(rows)) {
      throw fileError(poseCsv, "the face was found in " + std::to_string(static_cast<int>(found)) + " of its " +
                                   std::to_string(rows) + " frames; a head pose needs it in most");
    }
  }
  const audio::AudioClip sound = audio::readAudioFile(wav);
  return headRecordingOf(rotations, fps, sound.samples, poseCsv.stem().string(), prosody);
}

}  // namespace th::animation
