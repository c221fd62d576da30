#include "eval/viseme_corpus.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "animation/speech_analysis.h"
#include "audio/media_audio.h"
#include "core/data_path.h"
#include "core/error.h"
#include "eval/talking_corpus.h"
#include "face/visemes.h"

namespace th::eval {
namespace {

int rhubarbIndex(int mouthClass) {
  return static_cast<int>(face::kRhubarbShapes.find(face::rhubarbShapeOf(mouthClass)));
}

}  // namespace

VisemeRecording loadVisemeRecording(const std::filesystem::path& wav, const std::filesystem::path& phones,
                                    const std::string& speaker) {
  VisemeRecording recording;
  recording.name = wav.stem().string();
  recording.speaker = speaker;
  const audio::AudioClip clip = audio::readRecording(wav);
  if (clip.samples.empty()) throw fileError(wav, "has no samples");
  recording.speech = animation::analyseSpeech(clip.samples).speech;
  const std::vector<LabelInterval> labels = phones.extension() == ".json"
                                                ? readFramePhones(phones, phones.parent_path() / "phindex.json")
                                                : readTextGridPhones(phones);
  const int frames = recording.speech.numFrames();
  recording.classes.assign(static_cast<std::size_t>(frames), -1);
  std::size_t next = 0;
  for (int t = 0; t < frames; ++t) {
    const double seconds = t / animation::kAnimationFramesPerSecond;
    while (next < labels.size() && labels[next].endSeconds <= seconds) ++next;
    if (next < labels.size() && labels[next].startSeconds <= seconds)
      recording.classes[static_cast<std::size_t>(t)] = face::mouthClassOfPhone(labels[next].label);
  }
  return recording;
}

std::vector<VisemeRecording> loadVisemeCorpus() {
  std::vector<VisemeRecording> corpus;
  const std::filesystem::path beat2 = sharedDataPath("beat2");
  for (const std::filesystem::path& take :
       {beat2 / "2_scott_0_1_1", beat2 / "audio_only" / "2_scott_0_2_2", beat2 / "audio_only" / "2_scott_0_4_4"})
    corpus.push_back(loadVisemeRecording(take.string() + ".wav", take.string() + ".TextGrid", "scott"));
  const std::filesystem::path styletalk = sharedDataPath("talking/styletalk");
  for (const char* clip :
       {"Obama_clip1", "Obama_clip2", "Obama_clip3", "KristiNoem", "andrew_clip_1", "andrew_clip_2"}) {
    const std::filesystem::path wav = styletalk / (std::string(clip) + ".wav");
    corpus.push_back(loadVisemeRecording(wav, styletalk / (std::string(clip) + "_phonemes.json"), speakerOfClip(wav)));
  }
  return corpus;
}

int HoldTimes::shortest() const {
  return runFrames.empty() ? 0 : *std::min_element(runFrames.begin(), runFrames.end());
}

double HoldTimes::medianFrames() const {
  if (runFrames.empty()) return 0.0;
  std::vector<int> sorted = runFrames;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  return n % 2 == 1 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
}

double HoldTimes::shortRunShare(int maxFrames) const {
  if (runFrames.empty()) return 0.0;
  return static_cast<double>(
             std::count_if(runFrames.begin(), runFrames.end(), [&](int length) { return length <= maxFrames; })) /
         static_cast<double>(runFrames.size());
}

double HoldTimes::switchesPerSecond(double framesPerSecond, int frames) const {
  return frames == 0 ? 0.0 : static_cast<double>(runFrames.size()) * framesPerSecond / frames;
}

void VisemeScores::add(const std::vector<int>& reference, const std::vector<int>& decoded) {
  if (reference.size() != decoded.size())
    throw Error("viseme scores: " + std::to_string(reference.size()) + " reference frames, " +
                std::to_string(decoded.size()) + " decoded");
  frames_ += static_cast<int>(decoded.size());
  for (std::size_t t = 0; t < reference.size(); ++t) {
    if (reference[t] < 0) continue;
    ++oculus_(face::oculusVisemeOf(reference[t]), face::oculusVisemeOf(decoded[t]));
    ++rhubarb_(rhubarbIndex(reference[t]), rhubarbIndex(decoded[t]));
    classHits_ += reference[t] == decoded[t] ? 1 : 0;
  }
  // Hold times of the shown sequence, and of the phones' own classes (runs of labelled frames) for comparison;
  // the last run of a recording is left out (the recording's end cut it, not the decoder).
  const std::vector<face::Run> shown = face::runsOf(decoded);
  for (std::size_t r = 0; r + 1 < shown.size(); ++r) holds_.runFrames.push_back(shown[r].length);
  const std::vector<face::Run> phones = face::runsOf(reference);
  for (std::size_t r = 0; r + 1 < phones.size(); ++r)
    if (phones[r].value >= 0) referenceHolds_.runFrames.push_back(phones[r].length);
}

double VisemeScores::oculusAccuracy() const {
  return oculus_.sum() == 0 ? 0.0 : static_cast<double>(oculus_.trace()) / oculus_.sum();
}
double VisemeScores::rhubarbAccuracy() const {
  return rhubarb_.sum() == 0 ? 0.0 : static_cast<double>(rhubarb_.trace()) / rhubarb_.sum();
}
double VisemeScores::classAccuracy() const {
  return oculus_.sum() == 0 ? 0.0 : static_cast<double>(classHits_) / oculus_.sum();
}

std::vector<animation::LabelledSpeech> labelledSpeechOf(const std::vector<VisemeRecording>& recordings) {
  std::vector<animation::LabelledSpeech> labelled;
  for (const VisemeRecording& r : recordings) labelled.push_back({r.speech, r.classes});
  return labelled;
}

VisemeEvaluation leaveOneSpeakerOut(const std::vector<VisemeRecording>& corpus,
                                    const animation::VisemeModelOptions& options, int lagFrames) {
  VisemeEvaluation evaluation;
  for (const VisemeRecording& r : corpus)
    if (std::find(evaluation.speakers.begin(), evaluation.speakers.end(), r.speaker) == evaluation.speakers.end())
      evaluation.speakers.push_back(r.speaker);
  for (const std::string& heldOut : evaluation.speakers) {
    std::vector<VisemeRecording> training;
    std::vector<const VisemeRecording*> testing;
    for (const VisemeRecording& r : corpus) {
      if (r.speaker == heldOut)
        testing.push_back(&r);
      else
        training.push_back(r);
    }
    const animation::VisemeModel model = animation::trainVisemeModel(labelledSpeechOf(training), options);
    Eigen::VectorXi counts = Eigen::VectorXi::Zero(face::kNumMouthClasses);
    for (const VisemeRecording& r : training)
      for (int c : r.classes)
        if (c >= 0) ++counts[c];
    int majority = 0;
    counts.maxCoeff(&majority);
    for (const VisemeRecording* r : testing) {
      evaluation.batch.add(r->classes, animation::decodeVisemes(model, r->speech).classes);
      evaluation.frameByFrame.add(r->classes, animation::classifyFrames(model, r->speech));
      evaluation.majority.add(r->classes, std::vector<int>(r->classes.size(), majority));
      animation::VisemeStream stream(model, lagFrames);
      std::vector<int> streamed;
      animation::VisemeFrame frame;
      for (int t = 0; t < r->speech.numFrames(); ++t) {
        stream.accept(r->speech.levelDb[t], r->speech.mfcc.col(t));
        while (stream.next(frame)) streamed.push_back(frame.mouthClass);
      }
      stream.finish();
      while (stream.next(frame)) streamed.push_back(frame.mouthClass);
      evaluation.stream.add(r->classes, streamed);
    }
  }
  return evaluation;
}

std::string formatConfusion(const Eigen::MatrixXi& confusion, const std::vector<std::string>& names) {
  std::string text = "  truth   frames recall |";
  char cell[64];
  for (const std::string& name : names) {
    std::snprintf(cell, sizeof cell, " %4s", name.c_str());
    text += cell;
  }
  text += "\n";
  for (Eigen::Index r = 0; r < confusion.rows(); ++r) {
    const int total = confusion.row(r).sum();
    std::snprintf(cell, sizeof cell, "  %-6s %7d %5.1f%% |", names[static_cast<std::size_t>(r)].c_str(), total,
                  total == 0 ? 0.0 : 100.0 * confusion(r, r) / total);
    text += cell;
    for (Eigen::Index c = 0; c < confusion.cols(); ++c) {
      if (confusion(r, c) == 0)
        text += "    .";
      else {
        std::snprintf(cell, sizeof cell, " %4.0f", 100.0 * confusion(r, c) / std::max(total, 1));
        text += cell;
      }
    }
    text += "\n";
  }
  return text;
}

}  // namespace th::eval
