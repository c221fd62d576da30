#include "eval/network_corpus.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "audio/media_audio.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/parallel_for.h"
#include "core/text_files.h"
#include "eval/phone_labels.h"
#include "tracking/video_training.h"

namespace th::eval {
namespace {

std::string setOf(const std::filesystem::path& video) {
  const std::filesystem::path folder = video.parent_path().lexically_normal();
  return (folder.parent_path().filename() / folder.filename()).generic_string();
}

}  // namespace

std::vector<CorpusRecording> networkRecordingsOf(const TalkingCorpus& corpus, const std::vector<double>& warps,
                                                 unsigned threads) {
  std::vector<CorpusRecording> out(corpus.clips.size());
  parallelFor(corpus.clips.size(), threads, [&](std::size_t i) {
    const TalkingClip& clip = corpus.clips[i];
    CorpusRecording& r = out[i];
    r.clip = &clip;
    r.set = setOf(clip.clip.video);
    r.recording.name = clip.clip.video.stem().string();
    r.recording.speaker = clip.speaker;
    const audio::AudioClip sound = tracking::readClipSound(clip.clip.video);
    r.recording.subframes = animation::speechSubframesOf(sound.samples);
    for (const double warp : warps) r.warped.push_back(animation::speechSubframesOf(sound.samples, warp));
    r.recording.faps = clip.clip.recording.visual;
    r.recording.lipShape = clip.clip.lipShape;
    const int frames = clip.clip.recording.numFrames();
    if (!clip.labels.empty())
      r.recording.classes = mouthClassesAt(clip.labelsAreWords ? gridPhones(clip.labels) : clip.labels,
                                           animation::kMouthFramesPerSecond, frames);
  });
  return out;
}

std::vector<CorpusRecording> phoneAlignedSpeech(const std::vector<double>& warps) {
  std::vector<CorpusRecording> out;
  const std::filesystem::path beat2 = sharedDataPath("beat2");
  for (const std::filesystem::path& take :
       {beat2 / "2_scott_0_1_1", beat2 / "audio_only" / "2_scott_0_2_2", beat2 / "audio_only" / "2_scott_0_4_4"}) {
    const std::filesystem::path wav = take.string() + ".wav";
    const audio::AudioClip sound = audio::readRecording(wav);
    if (sound.samples.empty()) throw fileError(wav, "has no samples");
    CorpusRecording r;
    r.set = "beat2";
    r.recording.name = take.filename().string();
    r.recording.speaker = "scott";
    r.recording.subframes = animation::speechSubframesOf(sound.samples);
    for (const double warp : warps) r.warped.push_back(animation::speechSubframesOf(sound.samples, warp));
    const int frames =
        (r.recording.subframes.numFrames() + animation::kSubframesPerFrame - 1) / animation::kSubframesPerFrame;
    r.recording.classes =
        mouthClassesAt(readTextGridPhones(take.string() + ".TextGrid"), animation::kMouthFramesPerSecond, frames);
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<CorpusRecording> alignedSpeech(const std::filesystem::path& folder, const std::string& set,
                                           const std::vector<double>& warps) {
  const std::filesystem::path indexPath = folder / "index.csv";
  std::istringstream index(readTextFile(indexPath, "index"));
  std::string line;
  std::getline(index, line);
  std::vector<std::pair<std::string, std::string>> files;
  while (std::getline(index, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::size_t comma = line.find(',');
    const std::size_t second = line.find(',', comma + 1);
    if (comma == std::string::npos || second == std::string::npos)
      throw fileError(indexPath, "a line is not file,speaker,text");
    files.emplace_back(line.substr(0, comma), line.substr(comma + 1, second - comma - 1));
  }
  if (files.empty()) throw fileError(indexPath, "names no recording");
  std::vector<CorpusRecording> out(files.size());
  parallelFor(files.size(), 0, [&](std::size_t i) {
    const std::filesystem::path wav = folder / (files[i].first + ".wav");
    const audio::AudioClip sound = audio::readRecording(wav);
    if (sound.samples.empty()) throw fileError(wav, "has no samples");
    CorpusRecording& r = out[i];
    r.set = set;
    r.recording.name = files[i].first;
    r.recording.speaker = files[i].second;
    r.recording.subframes = animation::speechSubframesOf(sound.samples);
    for (const double warp : warps) r.warped.push_back(animation::speechSubframesOf(sound.samples, warp));
    const int frames =
        (r.recording.subframes.numFrames() + animation::kSubframesPerFrame - 1) / animation::kSubframesPerFrame;
    r.recording.classes = mouthClassesAt(readPhoneTable(folder / (files[i].first + ".phones.csv")),
                                         animation::kMouthFramesPerSecond, frames);
  });
  return out;
}

std::vector<CorpusRecording> synthesisedSpeech(const std::filesystem::path& folder, const std::vector<double>& warps) {
  return alignedSpeech(folder, "festival", warps);
}

int useAlignedPhones(TalkingCorpus& corpus, const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) throw fileError(folder, "is not a folder of aligned phones");
  int used = 0;
  for (TalkingClip& clip : corpus.clips) {
    if (!clip.labelsAreWords) continue;
    const std::filesystem::path phones = folder / (clip.clip.video.stem().string() + ".phones.csv");
    if (!std::filesystem::exists(phones)) continue;
    clip.labels = readPhoneTable(phones);
    clip.labelsAreWords = false;
    ++used;
  }
  return used;
}

std::vector<bool> gridHeldOut(const std::vector<CorpusRecording>& corpus) {
  std::map<std::string, int> seen;
  std::vector<bool> heldOut;
  for (const CorpusRecording& r : corpus) heldOut.push_back(r.recording.speaker == "grid-s1" && seen[r.set]++ % 5 == 4);
  return heldOut;
}

void startAtSpeakerMeans(std::vector<CorpusRecording>& corpus) {
  std::map<std::string, std::pair<Eigen::VectorXd, double>> sums;
  for (const CorpusRecording& r : corpus) {
    auto& [sum, count] = sums[r.recording.speaker];
    if (sum.size() == 0) sum = Eigen::VectorXd::Zero(r.recording.subframes.mfcc.rows());
    sum += r.recording.subframes.mfcc.rowwise().sum();
    count += static_cast<double>(r.recording.subframes.numFrames());
  }
  for (CorpusRecording& r : corpus) {
    const auto& [sum, count] = sums[r.recording.speaker];
    r.recording.startMean = sum / std::max(count, 1.0);
  }
}

Eigen::VectorXd meanFaps(const std::vector<CorpusRecording>& corpus,
                         const std::function<bool(const CorpusRecording&)>& include) {
  Eigen::VectorXd sum;
  double frames = 0.0;
  for (const CorpusRecording& r : corpus) {
    if (r.recording.faps.cols() == 0 || (include && !include(r))) continue;
    if (sum.size() == 0) sum = Eigen::VectorXd::Zero(r.recording.faps.rows());
    sum += r.recording.faps.rowwise().sum();
    frames += static_cast<double>(r.recording.faps.cols());
  }
  if (frames == 0.0) throw Error("network corpus: no recording has tracked FAPs");
  return sum / frames;
}

}  // namespace th::eval
