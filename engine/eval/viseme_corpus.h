// Phone-aligned speech for the viseme model, and how a decoded viseme sequence is scored against the phones.
//
//   std::vector<th::eval::VisemeRecording> corpus = th::eval::loadVisemeCorpus();   // the shared data's
//   th::eval::VisemeScores scores;
//   scores.add(recording.classes, decoded.classes);
//   scores.oculusAccuracy(); scores.holds.shortRunShare(2);
//
// The corpus: BEAT2's speaker (three takes with a Praat TextGrid "phones" tier, 3.2 min) and StyleTalk's three
// speakers (six clips with a phone per 30 fps frame, 2 min); each recording's speech frames (the mouth model's
// features, 30 fps) and each frame's mouth class (face/visemes.h; -1 where a label is no phone).
// Scores: frame by frame, confusion matrices over the Oculus 15 visemes and Rhubarb's 9 shapes (rows: the
// phones' class, columns: the decoded one), and the hold times of the decoded sequence (how long each shown
// viseme stays: the flicker users complain about is runs of 1-2 frames).
// Thread contract: pure functions of files; a VisemeScores belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "animation/mouth_data.h"
#include "animation/viseme_model.h"

namespace th::eval {

struct VisemeRecording {
  std::string name;
  std::string speaker;
  animation::SpeechFrames speech;
  std::vector<int> classes;  // per frame: a face::MouthClass, or -1
};

// A recording and its phones: `phones` is a TextGrid (.TextGrid) or a per-frame phone list (.json, named by
// phindex.json beside it). Errors name the file.
VisemeRecording loadVisemeRecording(const std::filesystem::path& wav, const std::filesystem::path& phones,
                                    const std::string& speaker);
// The shared data's phone-aligned speech (core/data_path.h): BEAT2 and StyleTalk.
std::vector<VisemeRecording> loadVisemeCorpus();

// Run lengths of a decoded sequence (each recording's last run left out: its end cut it short).
struct HoldTimes {
  std::vector<int> runFrames;
  int shortest() const;
  double medianFrames() const;
  double shortRunShare(int maxFrames) const;  // share of runs at most this long
  double switchesPerSecond(double framesPerSecond, int frames) const;
};

class VisemeScores {
 public:
  void add(const std::vector<int>& reference, const std::vector<int>& decoded);
  const Eigen::MatrixXi& oculusConfusion() const { return oculus_; }
  const Eigen::MatrixXi& rhubarbConfusion() const { return rhubarb_; }
  double oculusAccuracy() const;
  double rhubarbAccuracy() const;
  double classAccuracy() const;  // over the 17 mouth classes
  const HoldTimes& holds() const { return holds_; }
  const HoldTimes& referenceHolds() const { return referenceHolds_; }
  int frames() const { return frames_; }
  int labelledFrames() const { return static_cast<int>(oculus_.sum()); }

 private:
  Eigen::MatrixXi oculus_ = Eigen::MatrixXi::Zero(15, 15);
  Eigen::MatrixXi rhubarb_ = Eigen::MatrixXi::Zero(9, 9);
  long classHits_ = 0;
  HoldTimes holds_, referenceHolds_;
  int frames_ = 0;
};

// Leave one speaker out: for each speaker, a model trained on the others decodes that speaker's recordings.
struct VisemeEvaluation {
  VisemeScores batch;         // decodeVisemes: Viterbi over the whole recording
  VisemeScores stream;        // VisemeStream with `lagFrames`, as live use runs it
  VisemeScores frameByFrame;  // each frame's most likely class alone (no HMM)
  VisemeScores majority;      // every frame the training speech's most frequent class
  std::vector<std::string> speakers;
};
VisemeEvaluation leaveOneSpeakerOut(const std::vector<VisemeRecording>& corpus,
                                    const animation::VisemeModelOptions& options, int lagFrames);
std::vector<animation::LabelledSpeech> labelledSpeechOf(const std::vector<VisemeRecording>& recordings);

// The confusion matrix as text: one row per reference class (its frame count and recall), the share of its
// frames decoded as each class in per cent.
std::string formatConfusion(const Eigen::MatrixXi& confusion, const std::vector<std::string>& names);

}  // namespace th::eval
