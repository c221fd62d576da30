#include "eval/head_corpus.h"

#include <algorithm>
#include <vector>

#include "core/data_path.h"
#include "core/error.h"

namespace th::eval {

animation::HeadRecording loadBeat2Head(const animation::ProsodyOptions& prosody) {
  animation::HeadRecording take = animation::readHeadRecording(
      sharedDataPath("beat2/2_scott_0_1_1.wav"), sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"), prosody);
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
    animation::HeadRecording clip = animation::readHeadRecording(folder / (name + ".wav"), path, prosody);
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
