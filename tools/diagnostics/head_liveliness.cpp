// How lively a speaker's head is, and whether their voice tells it: per speaker, the head's spread in 1.2 s
// windows of speech (the mean over the axes of the rotation's std in each window, then over the windows: the
// length of the news anchors' clips, so every set is measured alike) beside three things of the voice — the
// pitch's spread (semitones, voiced frames), the level's spread in speech (dB) and the rate of onsets (a
// second of speech; eval/head_evaluation.h's speechBeats). Then, each speaker left out in turn, the spread
// predicted from the others: by their geometric mean (one size for everyone), and by a least-squares line of
// the log spread on the voice's three; and the shipped head's spread on the same windows (the "ours" column),
// alone and with one gain. Not the product: a workbench for the head's size (docs/head.md).
//   head_liveliness [--groups 60] [--window 36] [--min-windows 4]
// Sets: BEAT2's scott and StyleTalk's three (their recorded head poses), GRID's other speakers and the Arabic
// news anchors (head rotation tracked by `talkinghead track`; the anchors grouped into speakers by
// eval/speaker_groups.h). Tracks are read from (and made into) ~/.cache/talkinghead/tracks.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "animation/head_model.h"
#include "animation/speech_analysis.h"
#include "audio/media_audio.h"
#include "core/data_path.h"
#include "eval/head_corpus.h"
#include "eval/head_evaluation.h"
#include "eval/speaker_groups.h"
#include "eval/talking_corpus.h"
#include "face/face_model.h"
#include "tracking/track.h"

namespace {

using th::animation::HeadRecording;

struct Speaker {
  std::string name;
  std::string set;
  std::vector<HeadRecording> recordings;
  std::vector<double> windowSpreads;  // degrees
  std::vector<double> modelSpreads;   // the shipped head model's, on the same windows
  std::vector<double> semitones, levels;
  double speechSeconds = 0.0;
  int onsets = 0;
};

double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  double mean = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  double sum = 0.0;
  for (double x : v) sum += (x - mean) * (x - mean);
  return std::sqrt(sum / static_cast<double>(v.size() - 1));
}

void addRecording(Speaker& speaker, const HeadRecording& r, const Eigen::MatrixXd& synthesised, int window);

// A speaker's recordings one after the other (their prosody warm from the one before, as a long take's), the
// head model's rotations for them, and each recording's windows and voice into the speaker's sums.
void measureSpeaker(Speaker& speaker, const th::animation::HeadModel& model, int window) {
  int total = 0;
  for (const HeadRecording& r : speaker.recordings) total += r.numFrames();
  Eigen::MatrixXd prosody(4, total);
  Eigen::RowVectorXd voiced(total);
  int at = 0;
  for (const HeadRecording& r : speaker.recordings) {
    prosody.middleCols(at, r.numFrames()) = r.prosody;
    voiced.segment(at, r.numFrames()) = r.voiced;
    at += r.numFrames();
  }
  const Eigen::MatrixXd synthesised = th::animation::synthesiseHead(model, prosody, voiced);
  at = 0;
  for (const HeadRecording& r : speaker.recordings) {
    addRecording(speaker, r, synthesised.middleCols(at, r.numFrames()), window);
    at += r.numFrames();
  }
}

void addRecording(Speaker& speaker, const HeadRecording& r, const Eigen::MatrixXd& synthesised, int window) {
  const Eigen::RowVectorXd pauses = th::eval::pauseFrames(r.levelDb);
  for (int start = 0; start + window <= r.numFrames(); start += window / 2) {
    if (pauses.segment(start, window).mean() > 0.5) continue;  // a window of speech
    speaker.windowSpreads.push_back(th::eval::poseDiversity(r.rotations.middleCols(start, window)));
    speaker.modelSpreads.push_back(th::eval::poseDiversity(synthesised.middleCols(start, window)));
  }
  for (int t = 0; t < r.numFrames(); ++t) {
    if (pauses[t] > 0.5) continue;
    speaker.levels.push_back(r.levelDb[t]);
    speaker.speechSeconds += 1.0 / r.framesPerSecond;
    if (r.voiced[t] > 0.5) speaker.semitones.push_back(r.prosody(0, t));
  }
  speaker.onsets += static_cast<int>(th::eval::speechBeats(r.levelDb).size());
}

// A tracked clip as a head recording at 30 fps: the track's head rotation (FAPs 48-50) resampled, its sound's
// prosody and level.
bool trackedHead(const th::eval::TalkingClip& clip, HeadRecording& out) {
  if (clip.trackFile.empty()) return false;
  const th::tracking::Track track = th::tracking::readTrackCsv(clip.trackFile);
  if (track.fittedFaps.empty() || track.frames.size() < 10) return false;
  const std::vector<float> samples = th::audio::readRecording(clip.clip.video).samples;
  const th::animation::SpeechAnalysis heard = th::animation::analyseSpeech(samples);
  const int frames = std::min(heard.numFrames(), static_cast<int>(track.frames.back().seconds * 30.0));
  if (frames < 10) return false;
  out.framesPerSecond = 30.0;
  out.rotations.resize(3, frames);
  std::size_t j = 0;
  for (int t = 0; t < frames; ++t) {
    const double seconds = t / 30.0;
    while (j + 2 < track.frames.size() && track.frames[j + 1].seconds < seconds) ++j;
    const auto& a = track.frames[j];
    const auto& b = track.frames[j + 1];
    const double w = std::clamp((seconds - a.seconds) / (b.seconds - a.seconds), 0.0, 1.0);
    for (int axis = 0; axis < 3; ++axis) {
      const auto fap = static_cast<std::size_t>(48 + axis);
      out.rotations(axis, t) = ((1 - w) * a.fit.faps[fap] + w * b.fit.faps[fap]) * 1e-5 * 180.0 / M_PI;
    }
  }
  out.prosody = heard.prosody.leftCols(frames);
  out.voiced = heard.voiced.head(frames);
  out.levelDb = heard.speech.levelDb.head(frames);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args;
  for (int i = 1; i + 1 < argc; i += 2) args[std::string(argv[i]).substr(2)] = argv[i + 1];
  const auto arg = [&](const std::string& k, const std::string& d) { return args.count(k) ? args[k] : d; };
  const int window = std::stoi(arg("window", "36"));
  const int minWindows = std::stoi(arg("min-windows", "4"));
  try {
    std::map<std::string, Speaker> speakers;
    const auto add = [&](const std::string& name, const std::string& set, const HeadRecording& r) {
      Speaker& s = speakers[name];
      s.name = name;
      s.set = set;
      s.recordings.push_back(r);
    };
    add("scott", "beat2", th::eval::loadBeat2Head());
    for (const HeadRecording& r : th::eval::loadStyleTalkHeads()) add(r.speaker, "styletalk", r);

    const th::face::FaceModel face = th::face::FaceModel::buildDefault();
    const std::filesystem::path tracks =
        std::filesystem::path(std::getenv("HOME") != nullptr ? std::getenv("HOME") : ".") / ".cache/talkinghead/tracks";
    const th::eval::TalkingCorpus talking = th::eval::loadTalkingCorpus(
        {{th::sharedDataPath("grid/samples"), ""}, {th::sharedDataPath("talking/arabic-news"), ""}}, face,
        {.trackFolder = tracks});
    std::vector<const th::eval::TalkingClip*> anchors;
    for (const auto& clip : talking.clips)
      if (clip.clip.video.parent_path().filename() == "arabic-news") anchors.push_back(&clip);
    const th::eval::SpeakerGroups groups =
        th::eval::groupSpeakers(th::eval::clipIdentities(anchors), {.speakers = std::stoi(arg("groups", "60"))});
    std::map<const th::eval::TalkingClip*, int> groupOf;
    for (std::size_t i = 0; i < anchors.size(); ++i) groupOf[anchors[i]] = groups.speaker[i];
    for (const auto& clip : talking.clips) {
      HeadRecording r;
      if (!trackedHead(clip, r)) continue;
      const bool anchor = groupOf.count(&clip) > 0;
      // GRID's samples: pwij3p and id2_vcd_swwp2s are one man, bbaf2n is s1; the rest one speaker each.
      std::string name = clip.clip.video.stem().string();
      if (name == "id2_vcd_swwp2s") name = "pwij3p";
      if (name == "bbaf2n") continue;  // s1, a speaker the head models never used either way
      add(anchor ? "arabic-" + std::to_string(groupOf[&clip]) : "grid-" + name, anchor ? "arabic" : "grid", r);
    }

    const th::animation::HeadModel model =
        th::animation::loadHeadModel(std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "models/head.json");
    for (auto& [name, s] : speakers) measureSpeaker(s, model, window);

    // The speakers with enough speech windows, their voice and head.
    struct Row {
      std::string name, set;
      double spread;
      double model;  // the shipped head's spread on the same windows
      Eigen::Vector3d voice;
      int windows;
    };
    std::vector<Row> rows;
    for (const auto& [name, s] : speakers) {
      if (static_cast<int>(s.windowSpreads.size()) < minWindows || s.speechSeconds <= 0.0) continue;
      double mean = 0.0, modelMean = 0.0;
      for (std::size_t w = 0; w < s.windowSpreads.size(); ++w) {
        mean += s.windowSpreads[w];
        modelMean += s.modelSpreads[w];
      }
      mean /= static_cast<double>(s.windowSpreads.size());
      modelMean /= static_cast<double>(s.windowSpreads.size());
      rows.push_back({name, s.set, mean, modelMean,
                      Eigen::Vector3d(stddev(s.semitones), stddev(s.levels), s.onsets / s.speechSeconds),
                      static_cast<int>(s.windowSpreads.size())});
    }
    const int n = static_cast<int>(rows.size());
    std::printf("%d speakers with %d or more windows of %d frames of speech\n", n, minWindows, window);
    std::printf("%-14s %-9s %7s %7s %8s %8s %8s  %9s %9s\n", "speaker", "set", "spread", "ours", "pitch st", "level dB",
                "onsets/s", "one size", "voice");
    // Leave one out: the geometric mean of the others, and log spread = a + b · voice fitted on the others.
    double errConst = 0.0, errVoice = 0.0;
    int withinConst = 0, withinVoice = 0;
    std::map<std::string, std::pair<double, double>> bySet;  // log-ratio sums
    std::map<std::string, int> setCount;
    Eigen::VectorXd correlationX(n), correlationY(n);
    for (int k = 0; k < n; ++k) {
      Eigen::MatrixXd x(n - 1, 4);
      Eigen::VectorXd y(n - 1);
      int m = 0;
      for (int i = 0; i < n; ++i) {
        if (i == k) continue;
        x.row(m) << 1.0, rows[static_cast<std::size_t>(i)].voice.transpose();
        y[m++] = std::log(rows[static_cast<std::size_t>(i)].spread);
      }
      const double constant = y.mean();
      const Eigen::Vector4d beta =
          (x.transpose() * x + 1e-3 * Eigen::Matrix4d::Identity()).ldlt().solve(x.transpose() * y);
      const Row& r = rows[static_cast<std::size_t>(k)];
      const double predicted = beta.dot((Eigen::Vector4d() << 1.0, r.voice).finished());
      const double lc = constant - std::log(r.spread), lv = predicted - std::log(r.spread);
      errConst += std::abs(lc);
      errVoice += std::abs(lv);
      withinConst += std::exp(lc) >= 0.8 && std::exp(lc) <= 1.25;
      withinVoice += std::exp(lv) >= 0.8 && std::exp(lv) <= 1.25;
      bySet[r.set].first += std::abs(lc);
      bySet[r.set].second += std::abs(lv);
      ++setCount[r.set];
      correlationX[k] = predicted;
      correlationY[k] = std::log(r.spread);
      if (r.set != "arabic" || k % 6 == 0)
        std::printf("%-14s %-9s %7.2f %7.2f %8.2f %8.2f %8.2f  %9.2f %9.2f\n", r.name.c_str(), r.set.c_str(), r.spread,
                    r.model, r.voice[0], r.voice[1], r.voice[2], std::exp(lc), std::exp(lv));
    }
    const auto corr = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
      const Eigen::VectorXd ca = a.array() - a.mean(), cb = b.array() - b.mean();
      return ca.dot(cb) / std::sqrt(ca.squaredNorm() * cb.squaredNorm());
    };
    std::printf("(arabic rows: every sixth printed)\n");
    std::printf(
        "predicted / true spread, left out in turn: one size (the others' geometric mean): mean |log| %.3f, "
        "within 0.8-1.25: %d of %d; from the voice: mean |log| %.3f, within: %d of %d; "
        "correlation of the voice's prediction with the log spread: %.3f\n",
        errConst / n, withinConst, n, errVoice / n, withinVoice, n, corr(correlationX, correlationY));
    for (const auto& [set, sums] : bySet)
      std::printf("  %-9s %3d speakers: mean |log ratio| one size %.3f, voice %.3f\n", set.c_str(), setCount[set],
                  sums.first / setCount[set], sums.second / setCount[set]);

    // The shipped head (models/head.json, its amplitude the geometric mean of its four training speakers'), and
    // the same scaled by one gain: the others' geometric mean of truth / model, each speaker left out in turn.
    std::vector<double> shipped, gained;
    for (int k = 0; k < n; ++k) {
      double logGain = 0.0;
      for (int i = 0; i < n; ++i)
        if (i != k)
          logGain += std::log(rows[static_cast<std::size_t>(i)].spread / rows[static_cast<std::size_t>(i)].model);
      logGain /= n - 1;
      const Row& r = rows[static_cast<std::size_t>(k)];
      shipped.push_back(r.model / r.spread);
      gained.push_back(std::exp(logGain) * r.model / r.spread);
    }
    const auto summary = [&](const char* what, const std::vector<double>& ratios, const std::string& set) {
      std::vector<double> chosen;
      for (int k = 0; k < n; ++k)
        if (set.empty() || rows[static_cast<std::size_t>(k)].set == set)
          chosen.push_back(ratios[static_cast<std::size_t>(k)]);
      if (chosen.empty()) return;
      double logMean = 0.0;
      int within = 0;
      for (double x : chosen) {
        logMean += std::log(x);
        within += x >= 0.8 && x <= 1.25;
      }
      std::sort(chosen.begin(), chosen.end());
      std::printf(
          "  %-34s %-9s spread ratio: geometric mean %.2f, median %.2f, range %.2f-%.2f, within 0.8-1.25: %d of %zu\n",
          what, set.empty() ? "all" : set.c_str(), std::exp(logMean / static_cast<double>(chosen.size())),
          chosen[chosen.size() / 2], chosen.front(), chosen.back(), within, chosen.size());
    };
    for (const std::string set : {"", "arabic", "beat2", "grid", "styletalk"}) {
      summary("the shipped head", shipped, set);
      summary("scaled by the others' gain", gained, set);
    }
    double allGain = 0.0;
    for (const Row& r : rows) allGain += std::log(r.spread / r.model);
    std::printf("the gain over all %d speakers: %.2f\n", n, std::exp(allGain / n));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "head_liveliness: %s\n", error.what());
    return 1;
  }
  return 0;
}
