// The default mouth models, trained and judged on tracked talking video of several speakers:
//   `talkinghead train mouth -o models/mouth.json`  the shared corpora's training clips -> a model file
//   `talkinghead eval mouth`                         the recipe on held-out GRID clips and on each StyleTalk
//                                                    speaker left out, beside the baselines and other models
// (engine/tracking/talking_corpus.h, mouth_scores.h).
#include "mouth_corpus_command.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>

#include "animation/mouth_model.h"
#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/progress.h"
#include "face/face_model.h"
#include "tracking/mouth_scores.h"
#include "tracking/talking_corpus.h"

namespace th::app {
namespace {

using tracking::TalkingClip;

std::filesystem::path defaultTrackFolder() {
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && *cache != '\0')
    return std::filesystem::path(cache) / "talkinghead" / "tracks";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".cache" / "talkinghead" / "tracks";
  return std::filesystem::temp_directory_path() / "talkinghead-tracks";
}

tracking::TalkingCorpus loadCorpus(const std::vector<tracking::TalkingFolder>& folders, const std::string& tracks,
                                   const face::FaceModel& face) {
  tracking::VideoCorpusOptions options;
  options.trackFolder = tracks.empty() ? defaultTrackFolder() : std::filesystem::path(tracks);
  options.synchronise = true;
  ProgressBar bar(1.0, "track", std::cerr);
  tracking::TalkingCorpus corpus = tracking::loadTalkingCorpus(folders, face, options, [&](int done, int total) {
    bar.update(static_cast<double>(done) / total);
  });
  bar.finish();
  std::fprintf(stderr, "%zu clips (tracks in %s), %.1f s\n", corpus.clips.size(), options.trackFolder.c_str(),
               corpus.trackingSeconds);
  for (const auto& skipped : corpus.skipped) std::fprintf(stderr, "  left out: %s\n", skipped.reason.c_str());
  return corpus;
}

// GRID's held-out clips: every fifth of each folder, by name.
bool isHeldOut(const TalkingClip& clip, const tracking::TalkingCorpus& corpus) {
  if (clip.speaker != "grid-s1") return false;
  int index = 0;
  for (const TalkingClip& other : corpus.clips) {
    if (&other == &clip) break;
    if (other.clip.video.parent_path() == clip.clip.video.parent_path()) ++index;
  }
  return index % 5 == 4;
}

std::vector<animation::MouthRecording> recordingsOf(const std::vector<const TalkingClip*>& clips) {
  std::vector<animation::MouthRecording> recordings;
  for (const TalkingClip* clip : clips) recordings.push_back(clip->clip.recording);
  return recordings;
}

void printScores(const char* name, const tracking::MouthScores& s) {
  std::printf("  %-44s %6.3f %6.3f %6.3f   %5.2f %5.2f   %6.3f %6.3f\n", name, s.jaw.rho, s.opening.rho, s.width.rho,
              s.jaw.spread, s.opening.spread, s.jaw.epsilon, s.fapsEpsilon);
}

struct Judged {
  std::string title;
  std::vector<const TalkingClip*> clips;
};

void judge(const Judged& set, const animation::MouthModel& model, const animation::MouthSynthesisOptions& synthesis,
           const std::vector<const TalkingClip*>& training, const std::vector<int>& faps,
           const tracking::MouthShapes& shapes, const std::vector<std::pair<std::string, const animation::MouthModel*>>& others) {
  int frames = 0;
  for (const TalkingClip* clip : set.clips) frames += clip->clip.recording.numFrames();
  std::printf("\n%s (%zu clips, %d frames)\n  %-44s %6s %6s %6s   %5s %5s   %6s %6s\n", set.title.c_str(), set.clips.size(),
              frames, "", "jaw ρ", "lip ρ", "wid ρ", "sprJ", "sprL", "jaw ε", "FAPs ε");
  const auto estimate = [&](const animation::MouthModel& m, int shift) {
    std::vector<Eigen::MatrixXd> out;
    const auto n = static_cast<int>(set.clips.size());
    for (int i = 0; i < n; ++i) {
      const TalkingClip* source = set.clips[static_cast<std::size_t>((i + shift) % n)];
      out.push_back(animation::mouthFapsOf(m, animation::synthesiseMouth(m, source->clip.recording.speech, synthesis)));
    }
    return out;
  };
  const std::vector<int> modelFaps = animation::mouthFapNumbers(model);
  printScores("this recipe", tracking::scoreMouth(estimate(model, 0), modelFaps, shapes, set.clips, faps));
  {
    animation::MouthSynthesisOptions plain = synthesis;
    plain.varianceCompensation = false;
    std::vector<Eigen::MatrixXd> out;
    for (const TalkingClip* clip : set.clips)
      out.push_back(animation::mouthFapsOf(model, animation::synthesiseMouth(model, clip->clip.recording.speech, plain)));
    printScores("this recipe without variance compensation", tracking::scoreMouth(out, modelFaps, shapes, set.clips, faps));
  }
  for (const auto& [name, other] : others)
    printScores(name.c_str(), tracking::scoreMouth(estimate(*other, 0), animation::mouthFapNumbers(*other), shapes, set.clips, faps));
  std::vector<const animation::MouthRecording*> trainingRecordings;
  for (const TalkingClip* clip : training) trainingRecordings.push_back(&clip->clip.recording);
  const tracking::LevelBaseline level(trainingRecordings, 2);
  std::vector<Eigen::MatrixXd> levelEstimates, means;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(faps.size()));
  double count = 0.0;
  for (const auto* r : trainingRecordings) {
    mean += r->visual.rowwise().sum();
    count += r->numFrames();
  }
  mean /= count;
  for (const TalkingClip* clip : set.clips) {
    levelEstimates.push_back(level.predict(clip->clip.recording.speech));
    means.push_back(mean.replicate(1, clip->clip.recording.numFrames()));
  }
  printScores("baseline: the sound's level (linear, ±2 frames)", tracking::scoreMouth(levelEstimates, faps, shapes, set.clips, faps));
  printScores("baseline: the training mean", tracking::scoreMouth(means, faps, shapes, set.clips, faps));
  if (set.clips.size() > 1)
    printScores("baseline: this recipe on another clip's sound", tracking::scoreMouth(estimate(model, 1), modelFaps, shapes, set.clips, faps));
}

}  // namespace

std::filesystem::path defaultMouthTrackFolder() { return defaultTrackFolder(); }

void runEvalMouthCorpora(const MouthCorpusArguments& arguments) {
  const face::FaceModel face = face::FaceModel::build(face::loadIctFace(face::ictFaceDirectory()));
  std::vector<std::pair<std::string, animation::MouthModel>> others;
  for (const std::string& file : arguments.compare) others.emplace_back(file, animation::loadMouthModel(file));
  const tracking::TalkingCorpus corpus = loadCorpus(tracking::sharedTalkingFolders(), arguments.tracks, face);
  const tracking::MouthShapes shapes(face);
  std::vector<std::pair<std::string, const animation::MouthModel*>> otherModels;
  for (const auto& [name, model] : others) otherModels.emplace_back(name, &model);

  for (const TalkingClip& clip : corpus.clips)
    if (clip.clip.soundOffset.measured)
      std::printf("%s: the sound lags the picture by %.0f ms (r %.2f)\n", clip.clip.video.filename().c_str(),
                  1000.0 * clip.clip.soundOffset.lateSeconds, clip.clip.soundOffset.correlation);

  std::vector<const TalkingClip*> gridTrain, gridTest, others2;
  std::map<std::string, std::vector<const TalkingClip*>> bySpeaker;
  for (const TalkingClip& clip : corpus.clips) {
    if (clip.speaker == "grid-s1") (isHeldOut(clip, corpus) ? gridTest : gridTrain).push_back(&clip);
    else bySpeaker[clip.speaker].push_back(&clip);
  }
  const auto train = [&](const std::vector<const TalkingClip*>& clips) {
    const auto started = std::chrono::steady_clock::now();
    animation::MouthModel model = animation::trainMouthModel(recordingsOf(clips), arguments.model);
    model.visualFaps = corpus.faps;
    std::fprintf(stderr, "trained on %zu clips in %.1f s (%d iterations)\n", clips.size(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), model.iterations);
    return model;
  };
  {
    std::vector<const TalkingClip*> training = gridTrain;
    for (const auto& [speaker, clips] : bySpeaker) training.insert(training.end(), clips.begin(), clips.end());
    const animation::MouthModel model = train(training);
    std::printf("variance scale:");
    for (Eigen::Index k = 0; k < model.varianceScale.size(); ++k) std::printf(" %.2f", model.varianceScale[k]);
    std::printf("\n");
    judge({"GRID s1, held-out clips", gridTest}, model, arguments.synthesis, training, corpus.faps, shapes, otherModels);
  }
  for (const auto& [speaker, clips] : bySpeaker) {
    std::vector<const TalkingClip*> training = gridTrain;
    for (const auto& [other, otherClips] : bySpeaker)
      if (other != speaker) training.insert(training.end(), otherClips.begin(), otherClips.end());
    const animation::MouthModel model = train(training);
    judge({"StyleTalk speaker left out: " + speaker, clips}, model, arguments.synthesis, training, corpus.faps, shapes, otherModels);
  }
}

}  // namespace th::app
