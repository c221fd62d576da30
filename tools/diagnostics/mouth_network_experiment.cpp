// Experiments with the mouth network (animation/mouth_network.h): leave-speakers-out folds over the shared
// corpora (GRID s1, StyleTalk, the Arabic news anchors, BEAT2's phone-aligned takes), printing per held-out
// set the viseme accuracies, /p b m/ recall and precision (by the class and at thresholds on P(PP) and on the
// closure head), rounded-vowel recall, and the jaw's and lips' correlation with the tracked truth. The fold
// that holds out BEAT2's speaker also judges GRID s1's held-out clips (every fifth) and GRID's other speakers.
// Not the product: a workbench for choosing the recipe.
//   mouth_network_experiment [--folds scott,Obama,KristiNoem,andrew] [--epochs 20] [--hidden 256,256]
//       [--past 24] [--future 9] [--components 6] [--class-weight 1] [--visual-weight 1] [--shape-weight 1]
//       [--closure-weight 1] [--closed 0.04] [--dropout 0.2] [--noise 0.1] [--rate 1e-3] [--decay 1e-4]
//       [--warps 0.9,1.1] [--balance 0.5] [--arabic SHARE] [--threads 2] [--groups NAME_GROUP.csv]
//       [--hold 2] (the articulation's minimum hold, frames)
//       [--grid-phones DIR]   (GRID's phones aligned to the sound: tools/align_phones.py --grid)
//       [--aligned DIR,DIR]   (read corpora aligned by tools/align_phones.py, trained on in every fold)
//       [--aligned-test DIR]  (a read corpus never trained on: judged by fold "none", adults and children apart)
//       [--network FILE]      (judge this model file instead of training one in each fold)
//       [--peer DIR]          (a peer's Oculus weights, DIR/NAME.csv per recording, scored on the same frames)
//       [--arabic-faps 0] [--festival DIR]   (tools/festival_speech.py's phone-aligned synthetic voices, trained on in every fold)
//       [--arabic-folds N [--speaker-groups 60] [--families 2]]   (the N largest anchor groups held out in turn,
//       each with its family kept out of training: eval/speaker_groups.h; --groups-out FILE writes name,speaker,family)
// --groups names each Arabic clip's speaker group (a CSV "name,group" with a header); without it the anchors
// count as one speaker. Tracks are read from (and made into) ~/.cache/talkinghead/tracks.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>

#include "animation/articulation.h"
#include "animation/mouth_model.h"
#include "animation/mouth_network.h"
#include "core/data_path.h"
#include "core/parallel_for.h"
#include "eval/mouth_scores.h"
#include "eval/network_corpus.h"
#include "eval/phone_labels.h"
#include "eval/speaker_groups.h"
#include "eval/talking_corpus.h"
#include "eval/viseme_corpus.h"
#include "face/face_model.h"
#include "face/visemes.h"

using namespace th;

namespace {

std::map<std::string, std::string> readGroups(const std::string& file) {
  std::map<std::string, std::string> groups;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    if (comma != std::string::npos) groups[line.substr(0, comma)] = line.substr(comma + 1);
  }
  return groups;
}

std::vector<int> parseList(const std::string& text) {
  std::vector<int> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) out.push_back(std::stoi(item));
  return out;
}

double correlation(const Eigen::RowVectorXd& a, const Eigen::RowVectorXd& b) {
  const Eigen::RowVectorXd x = a.array() - a.mean(), y = b.array() - b.mean();
  return x.dot(y) / std::sqrt(std::max(x.squaredNorm() * y.squaredNorm(), 1e-300));
}

constexpr double kScales[] = {0.3, 0.5, 0.75, 1.0};

// A peer's Oculus weights (time_s and 15 weights a row, 30 fps) as one mouth class a frame: the first of the 17
// classes that shows the row's largest viseme. Empty if the file is not there.
std::vector<int> readPeerClasses(const std::filesystem::path& csv) {
  std::vector<int> classes;
  std::ifstream in(csv);
  if (!in) return classes;
  std::vector<int> classOf(face::kNumOculusVisemes, -1);
  for (int c = face::kNumMouthClasses - 1; c >= 0; --c) classOf[static_cast<std::size_t>(face::oculusVisemeOf(c))] = c;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string cell;
    std::getline(fields, cell, ',');
    int best = 0;
    double bestWeight = -1.0;
    for (int v = 0; v < face::kNumOculusVisemes && std::getline(fields, cell, ','); ++v)
      if (const double w = std::stod(cell); w > bestWeight) bestWeight = w, best = v;
    classes.push_back(classOf[static_cast<std::size_t>(best)]);
  }
  return classes;
}

struct Measures {
  eval::VisemeScores visemes;
  std::vector<double> jawEstimate, jawTruth, openEstimate, openTruth, openFace, widthFace, widthTruth;
  std::vector<double> hmmJaw, hmmOpen, hmmWidth, levelJaw,
      levelOpen;  // the mouth model's (HMM) and the level's, if asked
  int shutTruthFrames = 0, shutHits = 0, shutShown = 0;
  int ppFrames = 0, ppShut = 0;  // PP-phone frames where the shut head says shut
  // PP by a threshold on P(PP) (rows) and on P(shut) (last row): truth hits, frames shown.
  std::vector<double> thresholds{0.1, 0.15, 0.2, 0.3, 0.4};
  std::vector<int> ppHit = std::vector<int>(6, 0), ppShown = std::vector<int>(6, 0);
  // Frame accuracy (17 classes) with the decoded classes shifted by -3..+3 frames against the phones.
  std::vector<int> shiftHits = std::vector<int>(7, 0);
  int shiftFrames = 0;
  std::vector<int> truthAll, decodedAll;  // every labelled frame, to pool folds
  // Decoded by the class HMM (animation/articulation.h networkVisemes), one per evidence scale.
  std::vector<eval::VisemeScores> hybrid = std::vector<eval::VisemeScores>(4);
  std::vector<std::vector<int>> hybridAll = std::vector<std::vector<int>>(4);
  // A peer's visemes on the same frames (--peer DIR: Oculus weights as `animate --format oculus` writes them,
  // DIR/NAME.csv per recording; tools/headaudio_visemes.mjs writes HeadAudio's), each frame its largest weight.
  eval::VisemeScores peer;
  std::vector<int> peerTruth, peerAll;
  // As live decodes: the network from the training speech's mean, the classes by the stream (lag 0).
  eval::VisemeScores streamed;
  std::vector<int> streamedAll;
  // The mouth model's FAPs with the lips articulated on the decoded classes (the shipped scale): jaw, opening,
  // width; and on the phones' /p b m/ frames, how often the face's lips are shut (opening < the closed share).
  std::vector<double> fusedJaw, fusedOpen, fusedWidth, closedOnlyWidth;
  // The phones' mouth (animation::blendPhoneMouth: the classes' tracked shapes weighted by the decoded classes'
  // posteriors; alone, and mixed with the mouth model's FAPs at shares 0.25, 0.5, 0.75), articulated as the
  // product does.
  // {jaw, lips} shares.
  static constexpr double kPhoneShares[][2] = {{0.25, 0.0}, {0.5, 0.0}, {0.25, 0.25}, {1.0, 0.0}};
  std::vector<std::vector<double>> phoneJaw = std::vector<std::vector<double>>(4),
                                   phoneOpen = std::vector<std::vector<double>>(4),
                                   phoneWidth = std::vector<std::vector<double>>(4);
  std::vector<int> ppFacePhone = std::vector<int>(4, 0);
  int ppFaceFrames = 0, ppFaceShutHmm = 0, ppFaceShutFused = 0, faceShutHmm = 0, faceShutFused = 0, faceFrames = 0;
  void pool(const Measures& other) {
    visemes.add(other.truthAll, other.decodedAll);
    truthAll.insert(truthAll.end(), other.truthAll.begin(), other.truthAll.end());
    decodedAll.insert(decodedAll.end(), other.decodedAll.begin(), other.decodedAll.end());
    for (std::size_t k = 0; k < ppHit.size(); ++k) ppHit[k] += other.ppHit[k], ppShown[k] += other.ppShown[k];
    for (std::size_t k = 0; k < shiftHits.size(); ++k) shiftHits[k] += other.shiftHits[k];
    shiftFrames += other.shiftFrames;
    ppFrames += other.ppFrames;
    ppShut += other.ppShut;
    for (std::size_t k = 0; k < hybrid.size(); ++k) {
      hybrid[k].add(other.truthAll, other.hybridAll[k]);
      hybridAll[k].insert(hybridAll[k].end(), other.hybridAll[k].begin(), other.hybridAll[k].end());
    }
    streamed.add(other.truthAll, other.streamedAll);
    peer.add(other.peerTruth, other.peerAll);
    peerTruth.insert(peerTruth.end(), other.peerTruth.begin(), other.peerTruth.end());
    peerAll.insert(peerAll.end(), other.peerAll.begin(), other.peerAll.end());
    streamedAll.insert(streamedAll.end(), other.streamedAll.begin(), other.streamedAll.end());
    ppFaceFrames += other.ppFaceFrames, ppFaceShutHmm += other.ppFaceShutHmm, ppFaceShutFused += other.ppFaceShutFused;
    for (std::size_t k = 0; k < 4; ++k) ppFacePhone[k] += other.ppFacePhone[k];
    faceShutHmm += other.faceShutHmm, faceShutFused += other.faceShutFused, faceFrames += other.faceFrames;
  }
  std::string format(const std::string& name) const {
    const Eigen::MatrixXi& c = visemes.oculusConfusion();
    const int pp = 1;
    const double ppRecall = c.row(pp).sum() > 0 ? double(c(pp, pp)) / c.row(pp).sum() : NAN;
    const double ppPrecision = c.col(pp).sum() > 0 ? double(c(pp, pp)) / c.col(pp).sum() : NAN;
    const int oh = 13, ou = 14;
    const double roundTruth = c.row(oh).sum() + c.row(ou).sum();
    const double roundRecall = roundTruth > 0 ? (c(oh, oh) + c(oh, ou) + c(ou, oh) + c(ou, ou)) / roundTruth : NAN;
    const auto rho = [](const std::vector<double>& a, const std::vector<double>& b) {
      if (a.size() < 3) return double(NAN);
      return correlation(Eigen::Map<const Eigen::RowVectorXd>(a.data(), static_cast<Eigen::Index>(a.size())),
                         Eigen::Map<const Eigen::RowVectorXd>(b.data(), static_cast<Eigen::Index>(b.size())));
    };
    const auto spread = [](const std::vector<double>& a, const std::vector<double>& b) {
      if (a.size() < 3) return double(NAN);
      const Eigen::Map<const Eigen::RowVectorXd> x(a.data(), static_cast<Eigen::Index>(a.size()));
      const Eigen::Map<const Eigen::RowVectorXd> y(b.data(), static_cast<Eigen::Index>(b.size()));
      return std::sqrt((x.array() - x.mean()).square().mean() /
                       std::max((y.array() - y.mean()).square().mean(), 1e-300));
    };
    char line[512];
    std::snprintf(
        line, sizeof line,
        "  %-22s frames %6d | oculus %5.1f%% rhubarb %5.1f%% | PP R %5.1f%% P %5.1f%% (n %4d) | round R %5.1f%% | "
        "jaw rho %6.3f spr %5.2f | open rho %6.3f (head) %6.3f | width rho %6.3f | shut R %5.1f%% P %5.1f%% | PP shut "
        "%5.1f%%\n",
        name.c_str(), visemes.labelledFrames() > 0 ? visemes.labelledFrames() : static_cast<int>(jawTruth.size()),
        100.0 * visemes.oculusAccuracy(), 100.0 * visemes.rhubarbAccuracy(), 100.0 * ppRecall, 100.0 * ppPrecision,
        static_cast<int>(c.row(pp).sum()), 100.0 * roundRecall, rho(jawEstimate, jawTruth),
        spread(jawEstimate, jawTruth), rho(openFace, openTruth), rho(openEstimate, openTruth),
        rho(widthFace, widthTruth), shutTruthFrames > 0 ? 100.0 * shutHits / shutTruthFrames : NAN,
        shutShown > 0 ? 100.0 * shutHits / shutShown : NAN, ppFrames > 0 ? 100.0 * ppShut / ppFrames : NAN);
    std::string text = line;
    if (!hmmJaw.empty()) {
      char more[256];
      std::snprintf(
          more, sizeof more,
          "      mouth model (HMM, same training clips): jaw rho %6.3f spr %5.2f open rho %6.3f width rho %6.3f | the "
          "level: jaw rho %6.3f open rho %6.3f\n",
          rho(hmmJaw, jawTruth), spread(hmmJaw, jawTruth), rho(hmmOpen, openTruth), rho(hmmWidth, widthTruth),
          rho(levelJaw, jawTruth), rho(levelOpen, openTruth));
      text += more;
    }
    for (std::size_t k = 0; k < hybrid.size(); ++k) {
      const Eigen::MatrixXi& h = hybrid[k].oculusConfusion();
      if (h.sum() == 0) continue;
      char cell[256];
      std::snprintf(cell, sizeof cell,
                    "      decoded (scale %.2f): oculus %5.1f%% rhubarb %5.1f%% PP R %5.1f%% P %5.1f%% round R %5.1f%% "
                    "short runs %4.1f%%\n",
                    kScales[k], 100.0 * hybrid[k].oculusAccuracy(), 100.0 * hybrid[k].rhubarbAccuracy(),
                    100.0 * h(pp, pp) / std::max(h.row(pp).sum(), 1), 100.0 * h(pp, pp) / std::max(h.col(pp).sum(), 1),
                    100.0 * (h(oh, oh) + h(oh, ou) + h(ou, oh) + h(ou, ou)) / std::max(roundTruth, 1.0),
                    100.0 * hybrid[k].holds().shortRunShare(2));
      text += cell;
    }
    if (streamed.oculusConfusion().sum() > 0) {
      const Eigen::MatrixXi& h = streamed.oculusConfusion();
      char cell[256];
      std::snprintf(
          cell, sizeof cell,
          "      streamed (lag 0, prior mean, scale %.2f): oculus %5.1f%% rhubarb %5.1f%% PP R %5.1f%% P %5.1f%% "
          "round R %5.1f%%\n",
          animation::ArticulationOptions{}.evidenceScale, 100.0 * streamed.oculusAccuracy(),
          100.0 * streamed.rhubarbAccuracy(), 100.0 * h(pp, pp) / std::max(h.row(pp).sum(), 1),
          100.0 * h(pp, pp) / std::max(h.col(pp).sum(), 1),
          100.0 * (h(oh, oh) + h(oh, ou) + h(ou, oh) + h(ou, ou)) / std::max(roundTruth, 1.0));
      text += cell;
    }
    if (!phoneJaw[0].empty()) {
      for (std::size_t k = 0; k < 4; ++k) {
        char cell[320];
        std::snprintf(
            cell, sizeof cell,
            "      phones' mouth, jaw %.2f lips %.2f (articulated): jaw rho %6.3f spr %5.2f open rho %6.3f width rho "
            "%6.3f | face shut on /p b m/ %5.1f%%\n",
            kPhoneShares[k][0], kPhoneShares[k][1], rho(phoneJaw[k], jawTruth), spread(phoneJaw[k], jawTruth),
            rho(phoneOpen[k], openTruth), rho(phoneWidth[k], widthTruth),
            100.0 * ppFacePhone[k] / std::max(ppFaceFrames, 1));
        text += cell;
      }
    }
    if (peer.oculusConfusion().sum() > 0) {
      const Eigen::MatrixXi& h = peer.oculusConfusion();
      const double peerRound = h.row(oh).sum() + h.row(ou).sum();
      char cell[256];
      std::snprintf(cell, sizeof cell,
                    "      peer (--peer, %d frames): oculus %5.1f%% PP R %5.1f%% P %5.1f%% round R %5.1f%%\n",
                    static_cast<int>(h.sum()), 100.0 * peer.oculusAccuracy(),
                    100.0 * h(pp, pp) / std::max(h.row(pp).sum(), 1), 100.0 * h(pp, pp) / std::max(h.col(pp).sum(), 1),
                    100.0 * (h(oh, oh) + h(oh, ou) + h(ou, oh) + h(ou, ou)) / std::max(peerRound, 1.0));
      text += cell;
    }
    if (!fusedJaw.empty()) {
      char cell[320];
      std::snprintf(
          cell, sizeof cell,
          "      mouth model + articulated lips: jaw rho %6.3f open rho %6.3f width rho %6.3f (closures alone %6.3f) | "
          "face shut on /p b m/: %5.1f%% (mouth model %5.1f%%), on all frames %5.1f%% (%5.1f%%)\n",
          rho(fusedJaw, jawTruth), rho(fusedOpen, openTruth), rho(fusedWidth, widthTruth),
          rho(closedOnlyWidth, widthTruth), 100.0 * ppFaceShutFused / std::max(ppFaceFrames, 1),
          100.0 * ppFaceShutHmm / std::max(ppFaceFrames, 1), 100.0 * faceShutFused / std::max(faceFrames, 1),
          100.0 * faceShutHmm / std::max(faceFrames, 1));
      text += cell;
    }
    if (c.row(pp).sum() > 0) {
      text += "      PP by P(PP) >";
      for (std::size_t k = 0; k < 6; ++k) {
        char cell[96];
        std::snprintf(cell, sizeof cell, " %s%.2f: R %4.1f%% P %4.1f%% |", k < 5 ? "" : "shut ",
                      k < 5 ? thresholds[k] : 0.5, 100.0 * ppHit[k] / c.row(pp).sum(),
                      ppShown[k] > 0 ? 100.0 * ppHit[k] / ppShown[k] : 0.0);
        text += cell;
      }
      text += "\n      class accuracy with the estimate k frames later (k = -3..3):";
      for (int k = 0; k < 7; ++k) {
        char cell[32];
        std::snprintf(cell, sizeof cell, " %.1f%%",
                      100.0 * shiftHits[static_cast<std::size_t>(k)] / std::max(shiftFrames, 1));
        text += cell;
      }
      text += "\n";
    }
    return text;
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args;
  for (int i = 1; i + 1 < argc; i += 2) args[std::string(argv[i]).substr(2)] = argv[i + 1];
  const auto arg = [&](const std::string& key, const std::string& fallback) {
    return args.count(key) ? args[key] : fallback;
  };
  animation::MouthNetworkOptions options;
  options.training.epochs = std::stoi(arg("epochs", "20"));
  options.hidden = parseList(arg("hidden", "256,256"));
  options.pastSubframes = std::stoi(arg("past", "24"));
  options.futureSubframes = std::stoi(arg("future", "9"));
  options.visualComponents = std::stoi(arg("components", "6"));
  options.classWeight = std::stod(arg("class-weight", "1"));
  options.visualWeight = std::stod(arg("visual-weight", "1"));
  options.shapeWeight = std::stod(arg("shape-weight", "1"));
  options.closureWeight = std::stod(arg("closure-weight", "1"));
  options.closedOpening = std::stod(arg("closed", "0.04"));
  options.training.dropout = std::stod(arg("dropout", "0.2"));
  options.training.inputNoise = std::stod(arg("noise", "0.1"));
  options.training.learningRate = std::stod(arg("rate", "1e-3"));
  options.training.weightDecay = std::stod(arg("decay", "1e-4"));
  const double arabicWeight = std::stod(arg("arabic", "1"));
  const std::string groupsFile = arg("groups", "");
  const std::map<std::string, std::string> groups =
      groupsFile.empty() ? std::map<std::string, std::string>{} : readGroups(groupsFile);

  const face::FaceModel face = face::FaceModel::buildDefault();
  std::vector<eval::TalkingFolder> folders = eval::sharedTalkingFolders();
  folders.push_back({sharedDataPath("talking/arabic-news"), ""});
  folders.push_back({sharedDataPath("grid/samples"), ""});
  tracking::VideoCorpusOptions corpusOptions;
  const char* home = std::getenv("HOME");
  corpusOptions.trackFolder = std::filesystem::path(home) / ".cache/talkinghead/tracks";
  corpusOptions.synchronise = true;
  auto started = std::chrono::steady_clock::now();
  eval::TalkingCorpus talking = eval::loadTalkingCorpus(folders, face, corpusOptions);
  if (!arg("grid-phones", "").empty()) {
    // The closures' timing on GRID's video: how often the tracked lips are shut on the frames a /p b m/ covers,
    // and where within +-133 ms of the phone's start they are closest, with the phones placed in each word by
    // typical durations and with the phones aligned to the sound.
    const auto report = [&](const char* what) {
      int frames = 0, shut = 0;
      std::vector<int> lags;
      for (const eval::TalkingClip& clip : talking.clips) {
        if (clip.speaker != "grid-s1" || clip.labels.empty()) continue;
        const std::vector<eval::LabelInterval> phones =
            clip.labelsAreWords ? eval::gridPhones(clip.labels) : clip.labels;
        const Eigen::MatrixXd& lips = clip.clip.lipShape;
        const int n = static_cast<int>(lips.cols());
        const std::vector<int> classes = eval::mouthClassesAt(phones, 30.0, n);
        for (int t = 0; t < n; ++t)
          if (classes[static_cast<std::size_t>(t)] == face::kPp) ++frames, shut += lips(0, t) < 0.04;
        for (const eval::LabelInterval& p : phones) {
          if (p.label != "P" && p.label != "B" && p.label != "M") continue;
          const int start = static_cast<int>(std::lround(p.startSeconds * 30.0));
          int best = -99;
          for (int k = -4; k <= 4; ++k)
            if (start + k >= 0 && start + k < n && (best == -99 || lips(0, start + k) < lips(0, start + best)))
              best = k;
          if (best != -99) lags.push_back(best);
        }
      }
      std::sort(lags.begin(), lags.end());
      int near = 0;
      for (const int k : lags) near += k >= 0 && k <= 2;
      std::fprintf(stderr,
                   "GRID s1 %s: the tracked lips shut on %.1f%% of %d /p b m/ frames; closest %+.0f ms after the "
                   "phone's start (median of %zu), 0-67 ms after it in %.1f%%\n",
                   what, 100.0 * shut / std::max(frames, 1), frames,
                   lags.empty() ? 0.0 : 1000.0 / 30.0 * lags[lags.size() / 2], lags.size(),
                   100.0 * near / static_cast<double>(std::max<std::size_t>(lags.size(), 1)));
    };
    report("phones placed by typical durations");
    std::fprintf(stderr, "GRID clips with aligned phones: %d\n",
                 eval::useAlignedPhones(talking, arg("grid-phones", "")));
    report("phones aligned to the sound");
  }
  std::vector<double> warps;
  {
    std::stringstream list(arg("warps", ""));
    for (std::string w; std::getline(list, w, ',');) warps.push_back(std::stod(w));
  }
  std::vector<eval::CorpusRecording> corpus = eval::networkRecordingsOf(talking, warps);
  for (eval::CorpusRecording& r : eval::phoneAlignedSpeech(warps)) corpus.push_back(std::move(r));
  if (!arg("festival", "").empty())
    for (eval::CorpusRecording& r : eval::synthesisedSpeech(arg("festival", ""), warps)) corpus.push_back(std::move(r));
  {
    std::stringstream list(arg("aligned", ""));
    for (std::string folder; std::getline(list, folder, ',');)
      for (eval::CorpusRecording& r : eval::alignedSpeech(folder, "aligned", warps)) corpus.push_back(std::move(r));
  }
  // A held-out read corpus (speechocean762's test speakers, tools/align_phones.py): never trained on, judged
  // by the fold that holds out no one ("none") or else the first, adults and children apart (speakers.csv).
  std::map<std::string, std::string> testGroupOf;
  if (!arg("aligned-test", "").empty()) {
    const std::filesystem::path folder = arg("aligned-test", "");
    std::ifstream speakers(folder / "speakers.csv");
    std::string line;
    std::getline(speakers, line);
    while (std::getline(speakers, line)) {
      std::stringstream fields(line);
      std::string speaker, age;
      std::getline(fields, speaker, ',');
      std::getline(fields, age, ',');
      testGroupOf[speaker] = !age.empty() && std::stoi(age) < 18 ? "unseen children" : "unseen adults";
    }
    for (eval::CorpusRecording& r : eval::alignedSpeech(folder, "aligned-test")) corpus.push_back(std::move(r));
  }
  // The news anchors grouped by face, voice and look (eval/speaker_groups.h): speaker groups nested in families.
  std::map<std::string, std::string> familyOf;  // speaker -> family
  const int arabicFolds = std::stoi(arg("arabic-folds", "0"));
  std::vector<std::string> arabicHeldOut;
  if (arabicFolds > 0) {
    std::vector<const eval::TalkingClip*> anchors;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < corpus.size(); ++i)
      if (corpus[i].set == "talking/arabic-news") anchors.push_back(corpus[i].clip), index.push_back(i);
    const auto t0 = std::chrono::steady_clock::now();
    const eval::SpeakerGroups grouping = eval::groupSpeakers(
        eval::clipIdentities(anchors),
        {.speakers = std::stoi(arg("speaker-groups", "60")), .families = std::stoi(arg("families", "2"))});
    std::map<int, int> sizes;
    for (std::size_t k = 0; k < anchors.size(); ++k) {
      auto& r = corpus[index[k]].recording;
      r.speaker = "arabic-s" + std::to_string(grouping.speaker[k]);
      familyOf[r.speaker] = "arabic-f" + std::to_string(grouping.family[k]);
      ++sizes[grouping.speaker[k]];
    }
    if (!arg("groups-out", "").empty()) {
      std::ofstream out(arg("groups-out", ""));
      out << "name,speaker,family\n";
      for (std::size_t k = 0; k < anchors.size(); ++k)
        out << corpus[index[k]].recording.name << "," << grouping.speaker[k] << "," << grouping.family[k] << "\n";
    }
    // The largest speaker groups, at most one per family while families last.
    std::vector<std::pair<int, int>> bySize;
    for (const auto& [group, count] : sizes) bySize.emplace_back(count, group);
    std::sort(bySize.rbegin(), bySize.rend());
    std::set<std::string> familiesUsed;
    for (int pass = 0; pass < 2 && static_cast<int>(arabicHeldOut.size()) < arabicFolds; ++pass)
      for (const auto& [count, group] : bySize) {
        const std::string speaker = "arabic-s" + std::to_string(group);
        if (static_cast<int>(arabicHeldOut.size()) >= arabicFolds || count < 10) break;
        if (std::find(arabicHeldOut.begin(), arabicHeldOut.end(), speaker) != arabicHeldOut.end()) continue;
        if (pass == 0 && familiesUsed.count(familyOf[speaker])) continue;
        familiesUsed.insert(familyOf[speaker]);
        arabicHeldOut.push_back(speaker);
      }
    std::fprintf(stderr, "news anchors grouped in %.0f s; held out:",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    for (const std::string& s : arabicHeldOut) std::fprintf(stderr, " %s (%s)", s.c_str(), familyOf[s].c_str());
    std::fprintf(stderr, "\n");
  }
  // --arabic-faps 0: the anchors train the classes, lip shape and closures but not the FAP components (their FAPs
  // are measured from each 1.2 s clip's own most closed frame); a held-out anchor's face is still scored.
  const bool arabicFaps = arg("arabic-faps", "1") != "0";
  const std::vector<bool> gridHeld = eval::gridHeldOut(corpus);
  std::vector<std::string> role(corpus.size());  // "train", "grid-held-out", "grid-samples"
  for (std::size_t i = 0; i < corpus.size(); ++i) {
    eval::CorpusRecording& r = corpus[i];
    role[i] = "train";
    if (r.set == "talking/arabic-news" && arabicFolds == 0) {
      const auto found = groups.find(r.recording.name);
      r.recording.speaker = "arabic-" + (found == groups.end() ? std::string("news") : found->second);
    }
    if (r.set == "grid/samples") role[i] = "grid-samples";
    if (r.set == "aligned-test") role[i] = "aligned-test";
    if (gridHeld[i]) role[i] = "grid-held-out";
  }
  std::fprintf(stderr, "corpus: %zu recordings in %.0f s\n", corpus.size(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  std::map<std::string, int> speakerFrames;
  for (const auto& r : corpus) speakerFrames[r.recording.speaker] += r.recording.numFrames();

  // Each speaker's mean c1..c13, as the start of the running cepstral mean (a stream adapted to them).
  if (arg("speaker-mean", "0") == "1") eval::startAtSpeakerMeans(corpus);
  // Speaker balance: each recording's frames weigh (median speaker's frames / its speaker's frames)^power.
  const double balance = std::stod(arg("balance", "0"));
  if (balance > 0.0) {
    std::vector<int> sizes;
    for (const auto& [speaker, frames] : speakerFrames) sizes.push_back(frames);
    std::sort(sizes.begin(), sizes.end());
    const double median = sizes[sizes.size() / 2];
    for (auto& r : corpus) r.recording.weight = std::pow(median / speakerFrames[r.recording.speaker], balance);
  }
  std::vector<std::string> folds;
  std::stringstream foldList(arg("folds", "scott,Obama,KristiNoem,andrew"));
  for (std::string f; std::getline(foldList, f, ',');) folds.push_back(f);
  folds.insert(folds.end(), arabicHeldOut.begin(), arabicHeldOut.end());
  std::printf(
      "options: hidden %s past %d future %d K %d epochs %d weights %.2f/%.2f/%.2f/%.2f closed %.3f dropout %.2f noise "
      "%.2f\n",
      arg("hidden", "256,256").c_str(), options.pastSubframes, options.futureSubframes, options.visualComponents,
      options.training.epochs, options.classWeight, options.visualWeight, options.shapeWeight, options.closureWeight,
      options.closedOpening, options.training.dropout, options.training.inputNoise);
  const eval::MouthShapes shapes(face);
  const int hold = std::stoi(arg("hold", "2"));
  // As `train articulation` measures it: without the anchors' FAPs unless they train.
  const Eigen::VectorXd typical = eval::meanFaps(
      corpus, [&](const eval::CorpusRecording& r) { return arabicFaps || r.set != "talking/arabic-news"; });
  const Eigen::VectorXd gradient = eval::openingGradient(shapes, talking.faps, typical);
  std::fprintf(stderr, "opening gradient:");
  for (Eigen::Index i = 0; i < gradient.size(); ++i)
    std::fprintf(stderr, " %d:%.2e", talking.faps[static_cast<std::size_t>(i)], gradient[i]);
  std::fprintf(stderr, "\n");
  const std::string judgesOthers =
      std::find(folds.begin(), folds.end(), "none") != folds.end() ? std::string("none") : folds.front();
  std::vector<std::string> outputs(folds.size());
  std::vector<Measures> heldOut(folds.size());
  parallelFor(folds.size(), std::stoi(arg("threads", "2")), [&](std::size_t f) {
    const std::string& held = folds[f];
    std::vector<animation::NetworkRecording> training;
    std::vector<const eval::CorpusRecording*> tests;
    // Whether recording i trains this fold's models: a training clip of neither the held-out speaker nor their family.
    const auto trainsOn = [&](std::size_t i) {
      const std::string& speaker = corpus[i].recording.speaker;
      const bool sameFamily =
          familyOf.count(held) && familyOf.count(speaker) && familyOf.at(held) == familyOf.at(speaker);
      return role[i] == "train" && speaker != held && !sameFamily;
    };
    for (std::size_t i = 0; i < corpus.size(); ++i) {
      const auto& r = corpus[i];
      if (r.recording.speaker == held)
        tests.push_back(&r);
      else if (trainsOn(i)) {
        training.push_back(r.recording);
        if (!arabicFaps && r.set == "talking/arabic-news") training.back().faps.resize(0, 0);
        for (const animation::SpeechFrames& w : r.warped) {
          animation::NetworkRecording copy = r.recording;
          copy.subframes = w;
          if (!arabicFaps && r.set == "talking/arabic-news") copy.faps.resize(0, 0);
          training.push_back(std::move(copy));
        }
        if (r.set == "talking/arabic-news" && arabicWeight != 1.0) {
          // weight by dropping: keep a share of the Arabic clips
          if (arabicWeight < 1.0 &&
              static_cast<double>(std::hash<std::string>{}(r.recording.name) % 100) >= arabicWeight * 100)
            training.pop_back();
        }
      }
      if (held == judgesOthers && role[i] != "train") tests.push_back(&r);  // GRID's held out, the unseen sets
    }
    const auto t0 = std::chrono::steady_clock::now();
    // --network FILE: a model file judged instead of one trained here (the shipped one, on the sets it never heard).
    animation::MouthNetworkTraining trained;
    if (arg("network", "").empty()) {
      trained = animation::trainMouthNetwork(training, talking.faps, options);
      trained.model.openingGradient = gradient;
    } else {
      trained.model = animation::loadMouthNetwork(arg("network", ""));
      trained.report.trainingLoss.push_back(0.0);
    }
    // The shipped mouth model's recipe (HMM inversion, `train mouth`) and the level baseline on the same clips.
    std::optional<animation::MouthModel> hmm;
    std::optional<eval::LevelBaseline> level;
    if (arg("hmm", "0") == "1") {
      std::vector<animation::MouthRecording> videoTraining;
      std::vector<const animation::MouthRecording*> pointers;
      for (std::size_t i = 0; i < corpus.size(); ++i) {
        if (corpus[i].clip != nullptr && trainsOn(i)) videoTraining.push_back(corpus[i].clip->clip.recording);
      }
      for (const auto& r : videoTraining) pointers.push_back(&r);
      hmm = animation::trainMouthModel(videoTraining, animation::videoMouthRecipe());
      hmm->visualFaps = talking.faps;
      level.emplace(pointers, 2);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::map<std::string, Measures> measures;
    for (const eval::CorpusRecording* r : tests) {
      const std::string& rowRole = role[static_cast<std::size_t>(r - corpus.data())];
      const std::string key = r->recording.speaker == held ? held
                              : rowRole == "grid-held-out" ? "grid-s1 held-out"
                              : rowRole == "aligned-test"  ? testGroupOf[r->recording.speaker]
                                                           : "grid-samples";
      Measures& m = measures[key];
      const animation::MouthNetworkOutput out =
          animation::runMouthNetwork(trained.model, r->recording.subframes, &r->recording.startMean);
      const int frames = std::min(out.numFrames(), r->recording.numFrames());
      if (!r->recording.classes.empty()) {
        std::vector<int> decoded, truth;
        for (int t = 0; t < frames; ++t) {
          Eigen::Index best = 0;
          out.classes.col(t).maxCoeff(&best);
          decoded.push_back(static_cast<int>(best));
          truth.push_back(r->recording.classes[static_cast<std::size_t>(t)]);
          for (std::size_t k = 0; k < 6; ++k) {
            const bool shown = k < 5 ? out.classes(face::kPp, t) > m.thresholds[k] : out.shut[t] > 0.5;
            m.ppShown[k] += shown;
            m.ppHit[k] += shown && truth.back() == face::kPp;
          }
          if (truth.back() == face::kPp) {
            ++m.ppFrames;
            m.ppShut += out.shut[t] > 0.5 ? 1 : 0;
          }
        }
        m.visemes.add(truth, decoded);
        for (std::size_t k = 0; k < m.hybrid.size(); ++k) {
          animation::ArticulationOptions articulation;
          articulation.evidenceScale = kScales[k];
          articulation.minHoldFrames = hold;
          std::vector<int> path = animation::networkVisemes(trained.model, out.classes, articulation).classes;
          path.resize(static_cast<std::size_t>(frames));
          m.hybrid[k].add(truth, path);
          m.hybridAll[k].insert(m.hybridAll[k].end(), path.begin(), path.end());
        }
        {
          const animation::ArticulationOptions articulation;
          const animation::MouthNetworkOutput fromPrior =
              animation::runMouthNetwork(trained.model, r->recording.subframes);
          const hmm::HmmModel classes = animation::classHmm(trained.model.sequence, articulation.minHoldFrames);
          animation::VisemeStream stream(classes, articulation.minHoldFrames, 0);
          const Eigen::VectorXd logPriors = trained.model.classPriors.array().log().matrix();
          std::vector<int> path;
          animation::VisemeFrame decided;
          for (int t = 0; t < fromPrior.numFrames(); ++t) {
            stream.acceptEvidence(articulation.evidenceScale *
                                  (fromPrior.classes.col(t).array().max(1e-12).log().matrix() - logPriors));
            while (stream.next(decided)) path.push_back(decided.mouthClass);
          }
          stream.finish();
          while (stream.next(decided)) path.push_back(decided.mouthClass);
          path.resize(static_cast<std::size_t>(frames));
          m.streamed.add(truth, path);
          m.streamedAll.insert(m.streamedAll.end(), path.begin(), path.end());
        }
        if (!arg("peer", "").empty()) {
          std::vector<int> shownByPeer =
              readPeerClasses(std::filesystem::path(arg("peer", "")) / (r->recording.name + ".csv"));
          if (!shownByPeer.empty()) {
            shownByPeer.resize(truth.size(), shownByPeer.back());
            m.peer.add(truth, shownByPeer);
            m.peerTruth.insert(m.peerTruth.end(), truth.begin(), truth.end());
            m.peerAll.insert(m.peerAll.end(), shownByPeer.begin(), shownByPeer.end());
          }
        }
        m.truthAll.insert(m.truthAll.end(), truth.begin(), truth.end());
        m.decodedAll.insert(m.decodedAll.end(), decoded.begin(), decoded.end());
        for (int t = 3; t + 3 < frames; ++t) {
          if (truth[static_cast<std::size_t>(t)] < 0) continue;
          ++m.shiftFrames;
          for (int k = -3; k <= 3; ++k)
            m.shiftHits[static_cast<std::size_t>(k + 3)] +=
                decoded[static_cast<std::size_t>(t + k)] == truth[static_cast<std::size_t>(t)];
        }
      }
      if (r->recording.faps.cols() > 0) {
        const Eigen::MatrixXd faps = animation::mouthNetworkFaps(trained.model, out);
        if (hmm && r->clip != nullptr) {
          const animation::SpeechFrames& speech = r->clip->clip.recording.speech;
          const Eigen::MatrixXd hmmFaps = animation::mouthFapsOf(
              *hmm, animation::synthesiseMouth(*hmm, speech, {.method = animation::MouthMethod::kMmse}));
          const Eigen::MatrixXd levelFaps = level->predict(speech);
          const Eigen::MatrixXd hmmShape = shapes.of(hmmFaps, talking.faps);
          // The lips articulated on the decoded classes, as the product does (its evidence scale).
          animation::ArticulationOptions articulation;
          articulation.minHoldFrames = hold;
          const face::VisemeTrack decoded = animation::networkVisemes(trained.model, out.classes, articulation);
          const std::vector<int>& shown = decoded.classes;
          Eigen::MatrixXd fusedFaps = hmmFaps;
          animation::articulateLips(trained.model, shown, talking.faps, fusedFaps, articulation);
          const Eigen::MatrixXd fusedShape = shapes.of(fusedFaps, talking.faps);
          Eigen::MatrixXd closedFaps = hmmFaps;
          animation::ArticulationOptions closuresAlone = articulation;
          closuresAlone.shapeShare = 0.0;
          animation::articulateLips(trained.model, shown, talking.faps, closedFaps, closuresAlone);
          const Eigen::MatrixXd closedShape = shapes.of(closedFaps, talking.faps);
          const Eigen::MatrixXd levelShape = shapes.of(levelFaps, talking.faps);
          // The phones' mouth (animation::blendPhoneMouth, on the decoded classes' posteriors) at each share.
          std::vector<Eigen::MatrixXd> phoneShape;
          for (const auto& share : Measures::kPhoneShares) {
            Eigen::MatrixXd mixed = hmmFaps;
            animation::ArticulationOptions phones = articulation;
            phones.phoneJawShare = share[0];
            phones.phoneLipShare = share[1];
            animation::blendPhoneMouth(trained.model, decoded.posteriors, talking.faps, mixed, phones);
            animation::articulateLips(trained.model, shown, talking.faps, mixed, phones);
            const auto jawAt = std::find(talking.faps.begin(), talking.faps.end(), 3) - talking.faps.begin();
            phoneShape.push_back(shapes.of(mixed, talking.faps));
            phoneShape.push_back(mixed.row(jawAt));
          }
          const auto jawRow = std::find(talking.faps.begin(), talking.faps.end(), 3) - talking.faps.begin();
          // The same frames as the network's below (the HMM's last frame held if it has fewer).
          const Eigen::Index n = std::min<Eigen::Index>(frames, r->recording.faps.cols());
          for (Eigen::Index t = 0; t < n; ++t) {
            const Eigen::Index u = std::min<Eigen::Index>(t, hmmFaps.cols() - 1);
            m.hmmJaw.push_back(hmmFaps(jawRow, u));
            m.hmmOpen.push_back(hmmShape(0, u));
            m.hmmWidth.push_back(hmmShape(1, u));
            m.fusedJaw.push_back(fusedFaps(jawRow, u));
            m.fusedOpen.push_back(fusedShape(0, u));
            m.fusedWidth.push_back(fusedShape(1, u));
            m.closedOnlyWidth.push_back(closedShape(1, u));
            const bool shutHmm = hmmShape(0, u) < options.closedOpening;
            const bool shutFused = fusedShape(0, u) < options.closedOpening;
            ++m.faceFrames;
            m.faceShutHmm += shutHmm;
            m.faceShutFused += shutFused;
            if (!r->recording.classes.empty() && r->recording.classes[static_cast<std::size_t>(t)] == face::kPp) {
              ++m.ppFaceFrames;
              m.ppFaceShutHmm += shutHmm;
              m.ppFaceShutFused += shutFused;
            }
            for (std::size_t k = 0; k < 4; ++k) {
              const Eigen::MatrixXd& shape = phoneShape[2 * k];
              const Eigen::Index v = std::min<Eigen::Index>(t, shape.cols() - 1);
              m.phoneJaw[k].push_back(phoneShape[2 * k + 1](0, v));
              m.phoneOpen[k].push_back(shape(0, v));
              m.phoneWidth[k].push_back(shape(1, v));
              if (!r->recording.classes.empty() && r->recording.classes[static_cast<std::size_t>(t)] == face::kPp)
                m.ppFacePhone[k] += shape(0, v) < options.closedOpening;
            }
            m.levelJaw.push_back(levelFaps(jawRow, u));
            m.levelOpen.push_back(levelShape(0, u));
          }
        }
        const Eigen::MatrixXd faceShape = shapes.of(faps, trained.model.visualFaps);
        const auto jaw = std::find(talking.faps.begin(), talking.faps.end(), 3) - talking.faps.begin();
        for (int t = 0; t < std::min<int>(frames, static_cast<int>(r->recording.faps.cols())); ++t) {
          m.jawEstimate.push_back(faps(jaw, t));
          m.jawTruth.push_back(r->recording.faps(jaw, t));
          m.openEstimate.push_back(out.lipShape(0, t));
          m.openFace.push_back(faceShape(0, t));
          m.openTruth.push_back(r->recording.lipShape(0, t));
          m.widthFace.push_back(faceShape(1, t));
          m.widthTruth.push_back(r->recording.lipShape(1, t));
          const bool shutTruth = r->recording.lipShape(0, t) < options.closedOpening;
          const bool shutShown = out.shut[t] > 0.5;
          m.shutTruthFrames += shutTruth;
          m.shutShown += shutShown;
          m.shutHits += shutTruth && shutShown;
        }
      }
    }
    char header[256];
    std::snprintf(header, sizeof header,
                  "fold %s: %zu training recordings, trained in %.0f s, best epoch %d, loss %.3f\n", held.c_str(),
                  training.size(), seconds, trained.report.bestEpoch, trained.report.trainingLoss.back());
    std::string text = header;
    for (const auto& [name, m] : measures) text += m.format(name);
    if (measures.count(held)) heldOut[f] = measures[held];
    outputs[f] = text;
    std::fprintf(stderr, "%s", text.c_str());
  });
  for (const std::string& text : outputs) std::printf("%s", text.c_str());
  Measures pooled;
  for (const Measures& m : heldOut) pooled.pool(m);
  std::printf("pooled over the held-out speakers' phones:\n%s", pooled.format("all held out").c_str());
  return 0;
}
