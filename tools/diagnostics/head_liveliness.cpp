// How lively a speaker's head is, and whether their voice tells it: per speaker, the head's spread in 1.2 s
// windows of speech (the mean over the axes of the rotation's std in each window, then over the windows: the
// length of the news anchors' clips, so every set is measured alike) beside three things of the voice — the
// pitch's spread (semitones, voiced frames), the level's spread in speech (dB) and the rate of onsets (a
// second of speech; animation/head_measures.h's speechBeats). Then, each speaker left out in turn, the spread
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
  std::vector<Eigen::VectorXd>
      windowVoice;                  // per window: level mean, level std, pitch std, voiced share, onsets, |dlevel|
  std::vector<double> windowSpeed;  // per window: the head's mean angular speed
  std::vector<double> semitones, levels;
  std::vector<double> tilt;        // c1 in speech frames: the spectrum's slope (vocal effort)
  std::vector<double> levelSteps;  // |Δ level| in speech, dB a frame
  double voicedSeconds = 0.0;
  double speechSeconds = 0.0;
  int onsets = 0;
  // Beat locking: the truth's Beat Align on its own speech, and with the speech's beats moved by 1-3 s.
  double beatAlign = 0.0, shiftedBeatAlign = 0.0;
  Eigen::Vector2d pitchAlign = Eigen::Vector2d::Zero(), peakAlign = Eigen::Vector2d::Zero();  // own, moved
  Eigen::Vector2d offsetAlign = Eigen::Vector2d::Zero(), modelAlign = Eigen::Vector2d::Zero();
  int beatClips = 0;
  Eigen::VectorXd speedAroundBeats = Eigen::VectorXd::Zero(31);  // lags -15..15, over mean speed
  int beatsCounted = 0;
};
// c1 of every frame, per recording name (the head corpora keep prosody and level only).
std::map<std::string, Eigen::RowVectorXd> g_tilt;

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

// Local maxima of x (within ±3 frames) standing minRise above the lowest of ±8 frames, where allowed, ≥ 6 apart.
std::vector<int> peaks(const Eigen::RowVectorXd& x, const Eigen::RowVectorXd& allowed, double minRise) {
  std::vector<int> out;
  const int n = static_cast<int>(x.size());
  for (int t = 0; t < n; ++t) {
    if (allowed[t] < 0.5) continue;
    bool top = true;
    double low = x[t];
    for (int d = -8; d <= 8; ++d) {
      const int u = t + d;
      if (u < 0 || u >= n || allowed[u] < 0.5) continue;
      if (std::abs(d) <= 3 && x[u] > x[t]) top = false;
      low = std::min(low, x[u]);
    }
    if (!top || x[t] - low < minRise) continue;
    if (!out.empty() && t - out.back() < 6) continue;
    out.push_back(t);
  }
  return out;
}

Eigen::Vector2d ownAndMoved(const std::vector<int>& beats, const std::vector<int>& motion, int frames) {
  double shifted = 0.0;
  for (int shift : {30, 45, 60, 75, 90}) {
    std::vector<int> moved;
    for (int b : beats) moved.push_back((b + shift) % frames);
    shifted += th::eval::beatAlign(moved, motion) / 5.0;
  }
  return {th::eval::beatAlign(beats, motion), shifted};
}

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
  const Eigen::RowVectorXd pauses = th::animation::pauseFrames(r.levelDb);
  for (int start = 0; start + window <= r.numFrames(); start += window / 2) {
    if (pauses.segment(start, window).mean() > 0.5) continue;  // a window of speech
    speaker.windowSpreads.push_back(th::eval::poseDiversity(r.rotations.middleCols(start, window)));
    {
      std::vector<double> lv, st;
      double voicedShare = 0.0, steps = 0.0, speed = 0.0;
      for (int t = start; t < start + window; ++t) {
        lv.push_back(r.levelDb[t]);
        if (r.voiced[t] > 0.5) st.push_back(r.prosody(0, t));
        voicedShare += r.voiced[t] / window;
        if (t > start) {
          steps += std::abs(r.levelDb[t] - r.levelDb[t - 1]) / window;
          speed += (r.rotations.col(t) - r.rotations.col(t - 1)).norm() / window;
        }
      }
      double lm = 0.0;
      for (double x : lv) lm += x / static_cast<double>(lv.size());
      int onsets = 0;
      for (int b : th::animation::speechBeats(r.levelDb)) onsets += b >= start && b < start + window;
      Eigen::VectorXd f(6);
      f << lm, stddev(lv), stddev(st), voicedShare, onsets, steps;
      speaker.windowVoice.push_back(f);
      speaker.windowSpeed.push_back(speed);
    }
    speaker.modelSpreads.push_back(th::eval::poseDiversity(synthesised.middleCols(start, window)));
  }
  const auto tilt = g_tilt.find(r.name);
  for (int t = 0; t < r.numFrames(); ++t) {
    if (pauses[t] > 0.5) continue;
    speaker.levels.push_back(r.levelDb[t]);
    if (t > 0) speaker.levelSteps.push_back(std::abs(r.levelDb[t] - r.levelDb[t - 1]));
    if (tilt != g_tilt.end() && t < tilt->second.size()) speaker.tilt.push_back(tilt->second[t]);
    if (r.voiced[t] > 0.5) speaker.voicedSeconds += 1.0 / r.framesPerSecond;
    speaker.speechSeconds += 1.0 / r.framesPerSecond;
    if (r.voiced[t] > 0.5) speaker.semitones.push_back(r.prosody(0, t));
  }
  const std::vector<int> beats = th::animation::speechBeats(r.levelDb);
  speaker.onsets += static_cast<int>(beats.size());
  if (r.numFrames() >= 60 && !beats.empty()) {
    const std::vector<int> motion = th::animation::motionBeats(r.rotations);
    speaker.beatAlign += th::eval::beatAlign(beats, motion);
    double shifted = 0.0;
    for (int shift : {30, 45, 60, 75, 90}) {
      std::vector<int> moved;
      for (int b : beats) moved.push_back((b + shift) % r.numFrames());
      shifted += th::eval::beatAlign(moved, motion) / 5.0;
    }
    speaker.shiftedBeatAlign += shifted;
    ++speaker.beatClips;
    const Eigen::RowVectorXd speech = Eigen::RowVectorXd::Ones(r.numFrames()) - th::animation::pauseFrames(r.levelDb);
    speaker.pitchAlign += ownAndMoved(peaks(r.prosody.row(0), r.voiced, 1.5), motion, r.numFrames());
    speaker.peakAlign += ownAndMoved(peaks(r.levelDb, speech, 4.0), motion, r.numFrames());
    speaker.offsetAlign += ownAndMoved(th::animation::speechBeats(-r.levelDb), motion, r.numFrames());
    speaker.modelAlign += ownAndMoved(beats, th::animation::motionBeats(synthesised), r.numFrames());
    // Summed in the loop: GCC's -Wnull-dereference flags Eigen's reduction over a vector that could be empty.
    Eigen::RowVectorXd speed = Eigen::RowVectorXd::Zero(r.numFrames());
    double meanSpeed = 0.0;
    for (int t = 1; t < r.numFrames(); ++t) {
      speed[t] = (r.rotations.col(t) - r.rotations.col(t - 1)).norm();
      meanSpeed += speed[t] / r.numFrames();
    }
    if (meanSpeed > 0.0)
      for (int b : beats) {
        if (b < 15 || b + 15 >= r.numFrames()) continue;
        for (int lag = -15; lag <= 15; ++lag) speaker.speedAroundBeats[lag + 15] += speed[b + lag] / meanSpeed;
        ++speaker.beatsCounted;
      }
  }
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
  out.name = clip.clip.video.string();
  g_tilt[out.name] = heard.speech.mfcc.row(0).head(frames);
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
    for (auto& [name, s] : speakers)
      for (const HeadRecording& r : s.recordings) {
        const std::filesystem::path wav = name == "scott" ? th::sharedDataPath("beat2") / (r.name + ".wav")
                                                          : th::sharedDataPath("talking/styletalk") / (r.name + ".wav");
        g_tilt[r.name] = th::animation::analyseSpeech(th::audio::readRecording(wav).samples).speech.mfcc.row(0);
      }

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
      Eigen::VectorXd voice;
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
      std::vector<double> sorted = s.semitones;
      std::sort(sorted.begin(), sorted.end());
      const double range = sorted.size() > 10 ? sorted[sorted.size() * 9 / 10] - sorted[sorted.size() / 10] : 0.0;
      double tilt = 0.0, steps = 0.0;
      for (double x : s.tilt) tilt += x / static_cast<double>(std::max<std::size_t>(s.tilt.size(), 1));
      for (double x : s.levelSteps) steps += x / static_cast<double>(std::max<std::size_t>(s.levelSteps.size(), 1));
      Eigen::VectorXd voice(7);
      voice << stddev(s.semitones), stddev(s.levels), s.onsets / s.speechSeconds, tilt, steps,
          s.voicedSeconds / s.speechSeconds, range;
      rows.push_back({name, s.set, mean, modelMean, voice, static_cast<int>(s.windowSpreads.size())});
    }
    const int n = static_cast<int>(rows.size());
    {
      // Each cue set, each speaker left out in turn: log spread = a + b · cues, least squares on the others.
      const char* names[] = {"pitch std", "level std", "onsets/s", "tilt c1", "|dlevel|", "voiced", "pitch range"};
      const std::vector<std::vector<int>> sets = {
          {}, {0, 1, 2}, {0}, {1}, {2}, {3}, {4}, {5}, {6}, {3, 4}, {0, 1, 2, 3, 4, 5, 6}};
      for (const auto& set : sets) {
        const int d = static_cast<int>(set.size()) + 1;
        double err = 0.0;
        int within = 0;
        Eigen::VectorXd px(n), py(n);
        for (int k = 0; k < n; ++k) {
          Eigen::MatrixXd x(n - 1, d);
          Eigen::VectorXd y(n - 1);
          int m = 0;
          // Standardise each cue on the others, so the ridge term treats them alike.
          for (int i = 0; i < n; ++i) {
            if (i == k) continue;
            x(m, 0) = 1.0;
            for (int c = 0; c < d - 1; ++c) x(m, c + 1) = rows[static_cast<std::size_t>(i)].voice[set[c]];
            y[m++] = std::log(rows[static_cast<std::size_t>(i)].spread);
          }
          Eigen::VectorXd mu = x.colwise().mean(),
                          sd = ((x.rowwise() - mu.transpose()).array().square().colwise().mean()).sqrt();
          mu[0] = 0.0;
          sd[0] = 1.0;
          for (int c = 1; c < d; ++c)
            if (sd[c] <= 0) sd[c] = 1.0;
          const Eigen::MatrixXd z = (x.rowwise() - mu.transpose()).array().rowwise() / sd.transpose().array();
          Eigen::MatrixXd ridge = 1.0 * Eigen::MatrixXd::Identity(d, d);
          ridge(0, 0) = 0.0;
          const Eigen::VectorXd beta = (z.transpose() * z + ridge).ldlt().solve(z.transpose() * y);
          std::vector<double> q(static_cast<std::size_t>(d), 1.0);  // the intercept's 1, then the cues
          for (int c = 0; c < d - 1; ++c)
            q[static_cast<std::size_t>(c) + 1] =
                (rows[static_cast<std::size_t>(k)].voice[set[c]] - mu[c + 1]) / sd[c + 1];
          double predicted = 0.0;
          for (int c = 0; c < d; ++c) predicted += beta[c] * q[static_cast<std::size_t>(c)];
          const double lp = predicted - std::log(rows[static_cast<std::size_t>(k)].spread);
          err += std::abs(lp);
          within += std::exp(lp) >= 0.8 && std::exp(lp) <= 1.25;
          px[k] = predicted;
          py[k] = std::log(rows[static_cast<std::size_t>(k)].spread);
        }
        const Eigen::VectorXd cx = px.array() - px.mean(), cy = py.array() - py.mean();
        std::string label;
        for (int c : set) label += std::string(label.empty() ? "" : " + ") + names[c];
        std::printf("cues %-40s mean |log| %.3f  within %2d of %d  corr %.2f\n",
                    label.empty() ? "(one size)" : label.c_str(), err / n, within, n,
                    set.empty() ? 0.0 : cx.dot(cy) / std::sqrt(cx.squaredNorm() * cy.squaredNorm()));
      }
      // Within a speaker: do windows with more of the voice come with more head motion? Correlations of the
      // window's log spread and log speed with each window cue, per long-take speaker.
      std::printf(
          "within speakers (windows of speech): correlation of log spread | log speed with level mean, level std, "
          "pitch std, voiced, onsets, |dlevel|\n");
      for (const auto& [name, sp] : speakers) {
        const std::size_t w = sp.windowSpreads.size();
        if (w < 20) continue;
        std::printf("  %-14s %3zu windows:", name.c_str(), w);
        for (int target = 0; target < 2; ++target) {
          for (int c = 0; c < 6; ++c) {
            Eigen::VectorXd a(w), b(w);
            for (std::size_t i = 0; i < w; ++i) {
              a[i] = sp.windowVoice[i][c];
              b[i] = std::log(std::max(1e-6, target == 0 ? sp.windowSpreads[i] : sp.windowSpeed[i]));
            }
            const Eigen::VectorXd ca = a.array() - a.mean(), cb = b.array() - b.mean();
            std::printf(" %5.2f", ca.dot(cb) / std::sqrt(std::max(1e-12, ca.squaredNorm() * cb.squaredNorm())));
          }
          std::printf(target == 0 ? "  |" : "\n");
        }
      }
      // Whether heads move on the speech's beats: Beat Align of the truth on its own speech and shifted.
      std::printf(
          "beat locking (truth): speaker, BA on its speech, BA with the beats moved 1-3 s, speed around a beat (lag "
          "-6..+6 over mean)\n");
      double own = 0.0, moved = 0.0;
      Eigen::Vector2d pitchSum = Eigen::Vector2d::Zero(), peakSum = Eigen::Vector2d::Zero();
      Eigen::Vector2d offsetSum = Eigen::Vector2d::Zero(), modelSum = Eigen::Vector2d::Zero();
      int counted = 0;
      Eigen::VectorXd pooled = Eigen::VectorXd::Zero(31);
      int pooledBeats = 0;
      for (const auto& [name, s] : speakers) {
        if (s.beatClips == 0) continue;
        own += s.beatAlign / s.beatClips;
        pitchSum += s.pitchAlign / s.beatClips;
        peakSum += s.peakAlign / s.beatClips;
        offsetSum += s.offsetAlign / s.beatClips;
        modelSum += s.modelAlign / s.beatClips;
        moved += s.shiftedBeatAlign / s.beatClips;
        ++counted;
        pooled += s.speedAroundBeats;
        pooledBeats += s.beatsCounted;
        if (s.set != "arabic") {
          std::printf("  %-14s %.3f %.3f  pitch peaks %.3f %.3f  level peaks %.3f %.3f ", name.c_str(),
                      s.beatAlign / s.beatClips, s.shiftedBeatAlign / s.beatClips, s.pitchAlign[0] / s.beatClips,
                      s.pitchAlign[1] / s.beatClips, s.peakAlign[0] / s.beatClips, s.peakAlign[1] / s.beatClips);
          std::printf(" offsets %.3f %.3f  ours %.3f %.3f ", s.offsetAlign[0] / s.beatClips,
                      s.offsetAlign[1] / s.beatClips, s.modelAlign[0] / s.beatClips, s.modelAlign[1] / s.beatClips);
          for (int lag = -6; lag <= 6; ++lag)
            std::printf(" %.2f", s.speedAroundBeats[lag + 15] / std::max(1, s.beatsCounted));
          std::printf("\n");
        }
      }
      std::printf("  all %d speakers: %.3f %.3f  pitch peaks %.3f %.3f  level peaks %.3f %.3f ", counted, own / counted,
                  moved / counted, pitchSum[0] / counted, pitchSum[1] / counted, peakSum[0] / counted,
                  peakSum[1] / counted);
      std::printf(" offsets %.3f %.3f  ours %.3f %.3f ", offsetSum[0] / counted, offsetSum[1] / counted,
                  modelSum[0] / counted, modelSum[1] / counted);
      for (int lag = -15; lag <= 15; ++lag) std::printf(" %.2f", pooled[lag + 15] / std::max(1, pooledBeats));
      std::printf("\n");
    }
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
        x.row(m) << 1.0, rows[static_cast<std::size_t>(i)].voice.head(3).transpose();
        y[m++] = std::log(rows[static_cast<std::size_t>(i)].spread);
      }
      const double constant = y.mean();
      const Eigen::Vector4d beta =
          (x.transpose() * x + 1e-3 * Eigen::Matrix4d::Identity()).ldlt().solve(x.transpose() * y);
      const Row& r = rows[static_cast<std::size_t>(k)];
      const double predicted = beta.dot((Eigen::Vector4d() << 1.0, r.voice.head(3)).finished());
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
    // The --head-amplitude that would give each speaker their own size: its spread of the people's.
    std::vector<double> amplitudes;
    for (const Row& r : rows) amplitudes.push_back(r.spread / r.model);
    std::sort(amplitudes.begin(), amplitudes.end());
    const auto at = [&](double q) {
      return amplitudes[static_cast<std::size_t>(q * static_cast<double>(amplitudes.size() - 1) + 0.5)];
    };
    std::printf(
        "--head-amplitude that matches a speaker: 10th percentile %.2f, 25th %.2f, median %.2f, 75th %.2f, 90th %.2f\n",
        at(0.1), at(0.25), at(0.5), at(0.75), at(0.9));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "head_liveliness: %s\n", error.what());
    return 1;
  }
  return 0;
}
