#include "eval/head_corpus.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "animation/speech_analysis.h"
#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/numeric_csv.h"

namespace th::eval {
namespace {

// The pose columns of either set: BEAT2 names the head's rotation relative to the torso "neckhead_…".
std::array<int, 3> poseColumns(const NumericTable& pose) {
  if (pose.findColumn("neckhead_pitch_deg") >= 0)
    return {pose.column("neckhead_pitch_deg"), pose.column("neckhead_yaw_deg"), pose.column("neckhead_roll_deg")};
  if (pose.findColumn("pitch_deg") >= 0)
    return {pose.column("pitch_deg"), pose.column("yaw_deg"), pose.column("roll_deg")};
  throw fileError(pose.source, "has neither neckhead_pitch_deg nor pitch_deg columns (a head-pose CSV needs one set)");
}

}  // namespace

animation::HeadRecording loadHeadRecording(const std::filesystem::path& wav, const std::filesystem::path& headPoseCsv,
                                           const animation::ProsodyOptions& prosody) {
  const NumericTable pose = readNumericCsv(headPoseCsv);
  const std::array<int, 3> columns = poseColumns(pose);
  if (pose.rows.size() < 2) throw fileError(headPoseCsv, "has fewer than 2 frames of head pose");

  const audio::AudioClip clip = audio::readAudioFile(wav);
  const animation::SpeechAnalysis heard = animation::analyseSpeech(clip.samples, prosody);

  animation::HeadRecording take;
  take.name = headPoseCsv.stem().string();
  const int frames = std::min(static_cast<int>(pose.rows.size()), heard.numFrames());
  if (frames < 2) throw fileError(wav, "is shorter than two animation frames");
  take.rotations.resize(3, frames);
  for (int t = 0; t < frames; ++t) {
    const auto& row = pose.rows[static_cast<size_t>(t)];
    for (int axis = 0; axis < 3; ++axis)
      take.rotations(axis, t) = row[static_cast<size_t>(columns[static_cast<size_t>(axis)])];
  }
  take.prosody = heard.prosody.leftCols(frames);
  take.voiced = heard.voiced.head(frames);
  take.levelDb = heard.speech.levelDb.head(frames);
  return take;
}

animation::HeadRecording loadBeat2Head(const animation::ProsodyOptions& prosody) {
  animation::HeadRecording take = loadHeadRecording(sharedDataPath("beat2/2_scott_0_1_1.wav"),
                                                    sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"), prosody);
  take.speaker = "scott";
  take.name = "2_scott_0_1_1";
  return take;
}

std::vector<animation::HeadRecording> loadStyleTalkHeads(const animation::ProsodyOptions& prosody) {
  const std::filesystem::path folder = sharedDataPath("talking/styletalk");
  const std::string suffix = "_headpose_30fps.csv";
  std::vector<std::filesystem::path> poses;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string file = entry.path().filename().string();
    if (file.size() > suffix.size() && file.ends_with(suffix)) poses.push_back(entry.path());
  }
  if (error) throw fileError(folder, "cannot be listed: " + error.message());
  if (poses.empty()) throw fileError(folder, "holds no *" + suffix + " files");
  std::sort(poses.begin(), poses.end());
  std::vector<animation::HeadRecording> clips;
  for (const auto& path : poses) {
    const std::string name = path.filename().string().substr(0, path.filename().string().size() - suffix.size());
    animation::HeadRecording clip = loadHeadRecording(folder / (name + ".wav"), path, prosody);
    clip.name = name;
    clip.speaker = name.substr(0, name.find("_clip"));
    // A 3DMM fitted frame by frame jitters from one frame to the next; a Gaussian of one frame's σ takes that
    // out (what it cuts, here and on BEAT2's motion capture: docs/results.md, "Head: variants measured and not
    // used").
    clip.rotations = animation::smoothFrames(clip.rotations, 1.0);
    clips.push_back(std::move(clip));
  }
  return clips;
}

}  // namespace th::eval
