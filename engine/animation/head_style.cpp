#include "animation/head_style.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <vector>

#include "animation/head_measures.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_reading.h"

namespace th::animation {
namespace {

constexpr const char* kStyleFormat = "talkinghead-head-style";
constexpr int kStyleVersion = 1;

// The grid the fit searches: the trajectory's smoothing (its velocity and acceleration precisions' factor),
// the residual motion's variation, and its gain in pauses.
constexpr std::array<double, 7> kSmoothings = {0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8};
constexpr std::array<double, 6> kVariations = {0.25, 0.5, 0.75, 1.0, 1.4, 2.0};
constexpr std::array<double, 7> kPauseVariations = {0.05, 0.1, 0.2, 0.4, 0.6, 0.8, 1.0};

double logRatio(double a, double b) {
  if (a <= 0.0 || b <= 0.0) return a == b ? 0.0 : 10.0;
  return std::log(a / b);
}

// The model's motion on the clip's speech under `options`, one trajectory per seed, about each one's own mean.
std::vector<Eigen::MatrixXd> synthesisedMotions(const HeadModel& model, const HeadRecording& clip,
                                                HeadSynthesisOptions options, unsigned seeds) {
  std::vector<Eigen::MatrixXd> motions;
  for (unsigned seed = 1; seed <= seeds; ++seed) {
    options.seed = seed;
    const Eigen::MatrixXd motion = synthesiseHead(model, clip.prosody, clip.voiced, options);
    motions.push_back(motion.colwise() - motion.rowwise().mean());
  }
  return motions;
}

// The measures of several motions of the same clip: the mean of each over them.
HeadStyleMeasures meanMeasures(const std::vector<Eigen::MatrixXd>& motions, const HeadRecording& clip,
                               double minPauseSeconds) {
  HeadStyleMeasures mean;
  for (const auto& motion : motions) {
    const HeadStyleMeasures m = measureHeadStyle(motion, clip.levelDb, clip.framesPerSecond, minPauseSeconds);
    mean.spread += m.spread;
    mean.speedP95 += m.speedP95;
    mean.speedP99 += m.speedP99;
    mean.pauseSpeechRatio += m.pauseSpeechRatio;
    mean.beatsPerSecond += m.beatsPerSecond;
    mean.pauses = m.pauses;
    mean.seconds = m.seconds;
  }
  const auto n = static_cast<double>(motions.size());
  mean.spread /= n;
  mean.speedP95 /= n;
  mean.speedP99 /= n;
  mean.pauseSpeechRatio /= n;
  mean.beatsPerSecond /= n;
  return mean;
}

// One candidate of the grid: its options with the per-axis gain that gives the person's spread, and what it
// then measures. The motion is linear in the gain, so one synthesis at unit gain, scaled, is the candidate's.
struct Candidate {
  HeadSynthesisOptions options;
  HeadStyleMeasures measures;
  double longestStep = 0.0;  // degrees, frame to frame, the longest of any seed's
};

// How far a candidate is from the person: its speed and beats (log ratios), and a step longer than any the person
// makes in the clip, which a viewer sees as a jump, rules it out before any other (the least such overshoot
// wins when every candidate has one).
double lossOf(const Candidate& candidate, const HeadStyleMeasures& person, double personsLongestStep) {
  const double speed = logRatio(candidate.measures.speedP95, person.speedP95);
  const double beats = logRatio(candidate.measures.beatsPerSecond, person.beatsPerSecond);
  const double overshoot = candidate.longestStep / personsLongestStep - 1.0;
  return speed * speed + beats * beats + (overshoot > 0.0 ? 1e3 * (1.0 + overshoot) : 0.0);
}

Candidate candidateFor(const HeadModel& model, const HeadRecording& clip, const HeadStyleMeasures& person,
                       HeadSynthesisOptions options, const HeadStyleFitOptions& fit) {
  options.axisGain = Eigen::Vector3d::Ones();
  std::vector<Eigen::MatrixXd> motions = synthesisedMotions(model, clip, options, fit.seeds);
  const HeadStyleMeasures unit = meanMeasures(motions, clip, fit.minPauseSeconds);
  for (int axis = 0; axis < 3; ++axis)
    options.axisGain[axis] = unit.spread[axis] > 0.0 ? person.spread[axis] / unit.spread[axis] : 1.0;
  // Measured without the step limit applyHeadStyle adds: the fit chooses how the head moves, the limit only
  // shortens the rare steps faster than the person's (a fit that counted on it would choose faster motion).
  double longest = 0.0;
  for (auto& motion : motions) {
    motion = options.axisGain.asDiagonal() * motion;
    longest = std::max(longest, longestStep(motion));
  }
  return {options, meanMeasures(motions, clip, fit.minPauseSeconds), longest};
}

Json vector3(const Eigen::Vector3d& v) {
  return Json::array({v[0], v[1], v[2]});
}

Json measuresJson(const HeadStyleMeasures& m) {
  Json out = Json::object();
  out["spread_deg"] = vector3(m.spread);
  out["speed_p95_deg_s"] = m.speedP95;
  out["speed_p99_deg_s"] = m.speedP99;
  out["pause_speech_ratio"] = m.pauseSpeechRatio;
  out["pauses"] = m.pauses;
  out["beats_per_second"] = m.beatsPerSecond;
  out["seconds"] = m.seconds;
  return out;
}

Eigen::Vector3d readVector3(const JsonFields& fields, const Json& value, const std::string& field) {
  const Json& array = fields.array(value, field);
  if (array.size() != 3) fields.fail(field, "has " + std::to_string(array.size()) + " numbers, not 3");
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i)
    v[static_cast<Eigen::Index>(i)] = fields.number(array[i], JsonFields::indexed(field, i));
  return v;
}

HeadStyleMeasures readMeasures(const JsonFields& fields, const Json& object, const std::string& field) {
  fields.object(object, field);
  fields.onlyKnownFields(object,
                         {"spread_deg", "speed_p95_deg_s", "speed_p99_deg_s", "pause_speech_ratio", "pauses",
                          "beats_per_second", "seconds"},
                         field);
  // Speeds, spreads, ratios and durations: a negative one is a damaged file (a negative speed limit would read as
  // none).
  const auto number = [&](std::string_view key) {
    const double value = fields.number(fields.member(object, key, field), JsonFields::dotted(field, key));
    if (value < 0.0) fields.fail(JsonFields::dotted(field, key), "is negative");
    return value;
  };
  HeadStyleMeasures m;
  m.spread = readVector3(fields, fields.member(object, "spread_deg", field), JsonFields::dotted(field, "spread_deg"));
  if (m.spread.minCoeff() < 0.0) fields.fail(JsonFields::dotted(field, "spread_deg"), "has a negative spread");
  m.speedP95 = number("speed_p95_deg_s");
  // Styles saved before the step limit have none: their head is not limited.
  if (object.contains("speed_p99_deg_s")) m.speedP99 = number("speed_p99_deg_s");
  m.pauseSpeechRatio = number("pause_speech_ratio");
  m.pauses = fields.boolean(fields.member(object, "pauses", field), JsonFields::dotted(field, "pauses"));
  m.beatsPerSecond = number("beats_per_second");
  m.seconds = number("seconds");
  return m;
}

}  // namespace

HeadStyleMeasures measureHeadStyle(const Eigen::MatrixXd& rotations, const Eigen::RowVectorXd& levelDb, double fps,
                                   double minPauseSeconds) {
  if (levelDb.size() != rotations.cols()) throw Error("head style: the level and the motion differ in length");
  const Eigen::RowVectorXd pauses = pauseFrames(levelDb);
  const Eigen::MatrixXd centred = rotations.colwise() - rotations.rowwise().mean();
  const HeadMotionStatistics statistics = motionStatistics(centred, pauses, fps);
  HeadStyleMeasures m;
  m.seconds = static_cast<double>(rotations.cols()) / fps;
  m.spread = statistics.poseStd;
  m.speedP95 = statistics.speedP95;
  m.speedP99 = statistics.speedP99;
  m.pauses = pauses.sum() / fps >= minPauseSeconds && pauses.sum() < static_cast<double>(pauses.size());
  m.pauseSpeechRatio = m.pauses ? statistics.pauseSpeechRatio : 0.0;
  m.beatsPerSecond = static_cast<double>(motionBeats(centred).size()) / m.seconds;
  return m;
}

HeadStyle fitHeadStyle(const HeadModel& model, const HeadRecording& clip, const HeadStyleFitOptions& options) {
  const std::string name = clip.name.empty() ? std::string("the clip") : clip.name;
  const double seconds = static_cast<double>(clip.numFrames()) / clip.framesPerSecond;
  if (seconds < options.minSeconds) {
    throw Error(name + ": " + std::to_string(static_cast<int>(std::round(seconds))) +
                " s of head motion; a style needs " + std::to_string(static_cast<int>(options.minSeconds)) +
                " s at least (20-60 s is best)");
  }
  if (clip.prosody.cols() != clip.numFrames() || clip.voiced.size() != clip.numFrames() ||
      clip.levelDb.size() != clip.numFrames()) {
    throw Error(name + ": its head motion, prosody, voicing and level differ in length");
  }
  const double voicedShare = clip.voiced.mean();
  if (voicedShare < options.minVoicedShare) {
    throw Error(name + ": no speech to fit a head style to (" + std::to_string(static_cast<int>(100 * voicedShare)) +
                " % of its frames are voiced)");
  }
  HeadStyle style;
  style.source = name;
  style.restPose = clip.rotations.rowwise().mean();
  style.person = measureHeadStyle(clip.rotations, clip.levelDb, clip.framesPerSecond, options.minPauseSeconds);
  if (style.person.spread.minCoeff() <= 1e-6) throw Error(name + ": the head does not move");

  const double personsLongestStep = longestStep(clip.rotations.colwise() - clip.rotations.rowwise().mean());
  // Speed and beats: smoothing and variation, each at the gain that gives the person's spread.
  HeadSynthesisOptions base;
  Candidate best;
  double bestLoss = std::numeric_limits<double>::infinity();
  for (const double smoothing : kSmoothings) {
    for (const double variation : kVariations) {
      HeadSynthesisOptions trial = base;
      trial.smoothing = smoothing;
      trial.variation = variation;
      const Candidate candidate = candidateFor(model, clip, style.person, trial, options);
      const double loss = lossOf(candidate, style.person, personsLongestStep);
      if (loss < bestLoss) {
        bestLoss = loss;
        best = candidate;
      }
    }
  }
  // Pauses: the residual's gain there, when the clip has pauses enough to say.
  if (style.person.pauses) {
    double bestPause = std::numeric_limits<double>::infinity();
    const Candidate speedAndBeats = best;
    for (const double pauseVariation : kPauseVariations) {
      HeadSynthesisOptions trial = speedAndBeats.options;
      trial.pauseVariation = pauseVariation;
      const Candidate candidate = candidateFor(model, clip, style.person, trial, options);
      const double overshoot = candidate.longestStep / personsLongestStep - 1.0;
      const double gap = std::abs(candidate.measures.pauseSpeechRatio - style.person.pauseSpeechRatio) +
                         (overshoot > 0.0 ? 1e3 * (1.0 + overshoot) : 0.0);
      if (gap < bestPause) {
        bestPause = gap;
        best = candidate;
      }
    }
  }
  style.axisGain = best.options.axisGain;
  style.smoothing = best.options.smoothing;
  style.variation = best.options.variation;
  style.pauseVariation = best.options.pauseVariation;
  style.fitted = best.measures;
  return style;
}

void saveHeadStyle(const std::filesystem::path& path, const HeadStyle& style) {
  Json out = Json::object();
  out["format"] = kStyleFormat;
  out["version"] = kStyleVersion;
  out["source"] = style.source;
  out["rest_pose_deg"] = vector3(style.restPose);
  Json synthesis = Json::object();
  synthesis["axis_gain"] = vector3(style.axisGain);
  synthesis["smoothing"] = style.smoothing;
  synthesis["variation"] = style.variation;
  synthesis["pause_variation"] = style.pauseVariation;
  out["synthesis"] = synthesis;
  out["person"] = measuresJson(style.person);
  out["fitted"] = measuresJson(style.fitted);
  AtomicFile file(path);
  file.stream() << out.dump(2) << "\n";
  file.commit();
}

HeadStyle loadHeadStyle(const std::filesystem::path& path) {
  const Json document = readJsonFile(path, "head style");
  const JsonFields fields(path.string());
  fields.object(document, "");
  const std::string& format = fields.string(fields.member(document, "format", ""), "format");
  if (format != kStyleFormat) fields.fail("format", "is \"" + format + "\", not \"" + kStyleFormat + "\"");
  const std::int64_t version = fields.integer(fields.member(document, "version", ""), "version");
  if (version != kStyleVersion)
    fields.fail("version", "is " + std::to_string(version) + "; this program reads version 1");
  fields.onlyKnownFields(document, {"format", "version", "source", "rest_pose_deg", "synthesis", "person", "fitted"},
                         "");
  HeadStyle style;
  style.source = fields.string(fields.member(document, "source", ""), "source");
  style.restPose = readVector3(fields, fields.member(document, "rest_pose_deg", ""), "rest_pose_deg");
  const Json& synthesis = fields.member(document, "synthesis", "");
  fields.object(synthesis, "synthesis");
  fields.onlyKnownFields(synthesis, {"axis_gain", "smoothing", "variation", "pause_variation"}, "synthesis");
  const auto positive = [&](std::string_view key, double most) {
    const std::string field = JsonFields::dotted("synthesis", key);
    const double value = fields.number(fields.member(synthesis, key, "synthesis"), field);
    if (!(value >= 0.0 && value <= most))
      fields.fail(field, "is " + std::to_string(value) + ", outside 0.." + std::to_string(most));
    return value;
  };
  style.axisGain = readVector3(fields, fields.member(synthesis, "axis_gain", "synthesis"), "synthesis.axis_gain");
  for (int axis = 0; axis < 3; ++axis) {
    if (!(style.axisGain[axis] >= 0.0 && style.axisGain[axis] <= 20.0))
      fields.fail(JsonFields::indexed("synthesis.axis_gain", static_cast<std::size_t>(axis)), "is outside 0..20");
  }
  style.smoothing = positive("smoothing", 10.0);
  if (style.smoothing <= 0.0) fields.fail("synthesis.smoothing", "must be above 0");
  style.variation = positive("variation", 10.0);
  style.pauseVariation = positive("pause_variation", 10.0);
  style.person = readMeasures(fields, fields.member(document, "person", ""), "person");
  style.fitted = readMeasures(fields, fields.member(document, "fitted", ""), "fitted");
  return style;
}

bool isHeadStyleFile(const std::filesystem::path& path) {
  try {
    const Json document = readJsonFile(path, "head style");
    return document.is_object() && document.contains("format") && document["format"] == kStyleFormat;
  } catch (const Error&) {
    return false;
  }
}

HeadStyle headStyleFromFile(const HeadModel& model, const std::filesystem::path& file,
                            const HeadStyleFitOptions& options) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) throw fileError(file, "no such file");
  if (isHeadStyleFile(file)) return loadHeadStyle(file);
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".json") return loadHeadStyle(file);  // its error says what is wrong with it
  if (extension != ".csv") {
    throw fileError(file,
                    "not a head style (a style file, a head-pose CSV with its WAV beside it, or a talking video)");
  }
  const std::filesystem::path sound = std::filesystem::path(file).replace_extension(".wav");
  if (!std::filesystem::is_regular_file(sound, error))
    throw fileError(file, "a head-pose CSV needs the sound of the same take beside it, " + sound.filename().string());
  HeadRecording clip = readHeadRecording(sound, file);
  clip.name = file.string();  // the fit's errors name the file
  HeadStyle style = fitHeadStyle(model, clip, options);
  style.source = file.filename().string();
  return style;
}

}  // namespace th::animation
