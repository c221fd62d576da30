// Onset latency of the live pipeline, measured end to end: speech with sharp onsets goes through the real
// pipeline at real-time pace (FileFeeder in 10 ms blocks, as a sound device delivers them → AudioRing →
// worker: features, mouth and head decoders → frame queue → Playout at 60 Hz → the face deformed and rendered
// off-screen at 1280x720, the frame read back). For every onset, the time from the moment the block holding
// the onset's first sample entered the ring until the rendered frame in which the mouth has moved finished.
//
//   build/bench/latency_bench            # 70 onsets per setting, ~4 min (real time)
//   build/bench/latency_bench --quick    # 6 onsets per setting, a smoke check
//   build/bench/latency_bench --only default   # the baseline and the settings whose name holds "default"
//
// The recording: the first onset of each GRID clip (s1 and the other speakers' samples; "bin ...", "place ...",
// "lay ...", "set ..."): the first
// 5 ms hop 10 dB above the opening pause's floor, cut out with 0.4 s of the pause before it and 0.6 s of speech
// after. Onsets that rise 25 dB within 80 ms (a burst, not a voiced /b/'s slow rise) are also reported alone as
// the sharp ones. (BEAT2 is fluent speech with few clean pauses: 15 or so in three minutes.)
// "The mouth has moved": the jaw passes a quarter of the way from where it is when the onset arrives to its
// peak in the 500 ms after, both taken from the same decoder run offline on the same samples (the pipeline's frames are
// the same values, tests/pipeline). Onsets where the model opens the jaw by less than a quarter of its usual range (5th
// to 95th percentile) are skipped (a closure like /m/ moves the lips, not the jaw).
//
// Before the settings, the speakers' own response: their tracked jaws, where `talkinghead train mouth` has left
// the clips' tracks, crossing by the same rule (how late the speech itself moves the jaw).
// Each setting reports the distribution (median, 10th and 90th percentiles, largest), split into the model's own
// response (when the offline jaw crosses, after the onset) and the pipeline (from the crossing instant's samples
// entering to the frame that shows it rendered).
// The baseline is the first live step (frames wait for the head; the offline mouth model, window 2, interpolated
// display); its median is the ratios' base. Then the presets (pipeline/live_presets.h), each with its articulation
// (the lips closed and the visemes from the mouth network: frames wait for their class) and without it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "animation/head_model.h"
#include "animation/mouth_model.h"
#include "animation/mouth_network.h"
#include "audio/media_audio.h"
#include "core/data_path.h"
#include "core/statistics.h"
#include "face/face_model.h"
#include "pipeline/live_decoder.h"
#include "pipeline/live_presets.h"
#include "pipeline/live_session.h"
#include "pipeline/options.h"
#include "pipeline/playout.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "tracking/track.h"

namespace {

using th::pipeline::AnimationFrame;
using th::pipeline::LiveDecoderOptions;

constexpr int kRate = 16000;
constexpr std::size_t kBlock = 160;  // 10 ms: a sound device's period
constexpr double kFps = 30.0;

struct OnsetRecording {
  std::vector<float> samples;
  std::vector<std::size_t> onsets;           // sample of each onset
  std::vector<bool> sharp;                   // rising 25 dB within 80 ms
  std::vector<std::filesystem::path> clips;  // the clip each onset came from
  std::vector<double> clipSeconds;           // and where in it
};

// Level in dB of 5 ms hops (10 ms windows).
std::vector<double> hopLevels(const std::vector<float>& x, std::size_t hop) {
  std::vector<double> levels;
  for (std::size_t at = 0; at + 2 * hop <= x.size(); at += hop) {
    double sum = 0.0;
    for (std::size_t n = at; n < at + 2 * hop; ++n) sum += static_cast<double>(x[n]) * x[n];
    levels.push_back(10.0 * std::log10(sum / static_cast<double>(2 * hop) + 1e-12));
  }
  return levels;
}

double percentileOf(std::vector<double> values, double p) {
  return values.empty() ? std::nan("") : th::quantile(std::move(values), p / 100.0);
}

OnsetRecording buildOnsetRecording(std::size_t wanted) {
  const std::size_t hop = kRate / 200;        // 5 ms
  const std::size_t before = kRate * 4 / 10;  // 400 ms of the pause before the onset
  const std::size_t after = kRate * 6 / 10;
  OnsetRecording result;
  std::vector<std::filesystem::path> clips;
  for (const char* folder : {"grid/s1", "grid/samples"})
    for (const auto& entry : std::filesystem::directory_iterator(th::sharedDataPath(folder)))
      if (entry.path().extension() == ".mpg") clips.push_back(entry.path());
  std::sort(clips.begin(), clips.end());
  for (const auto& clip : clips) {
    if (result.onsets.size() >= wanted) break;
    const std::vector<float> x = th::audio::readRecording(clip).samples;
    const std::vector<double> levels = hopLevels(x, hop);
    if (levels.size() < 200) continue;
    // The clip opens with a pause: its floor is the median level of the first 250 ms. The onset is the first
    // 5 ms hop after 300 ms that is 10 dB over it; sharp if 25 dB over within 80 ms.
    const double floor = percentileOf({levels.begin(), levels.begin() + 50}, 50.0);
    std::size_t k = 60;
    while (k < levels.size() && levels[k] < floor + 10.0) ++k;
    const std::size_t onset = k * hop;
    if (onset < before || onset + after > x.size()) continue;
    bool sharp = false;
    for (std::size_t j = k; j < std::min(k + 16, levels.size()); ++j) sharp = sharp || levels[j] >= floor + 25.0;
    result.samples.insert(result.samples.end(), x.begin() + static_cast<long>(onset - before),
                          x.begin() + static_cast<long>(onset + after));
    result.onsets.push_back(result.samples.size() - after);
    result.sharp.push_back(sharp);
    result.clips.push_back(clip);
    result.clipSeconds.push_back(static_cast<double>(onset) / kRate);
  }
  return result;
}

// The jaw of every frame, the decoder run offline on the same samples.
std::vector<double> offlineJaw(const std::vector<float>& samples, const th::animation::HeadModel& head,
                               const th::animation::MouthModel& mouth, const LiveDecoderOptions& options,
                               const th::animation::MouthNetwork* articulation) {
  th::pipeline::LiveDecoder decoder(&head, &mouth, options, nullptr, articulation);
  decoder.acceptWaveform(samples);
  decoder.inputFinished();
  std::vector<double> jaw;
  AnimationFrame frame;
  while (decoder.next(frame)) jaw.push_back(frame.faps[3]);
  return jaw;
}

struct Crossing {
  double threshold = 0.0;
  double rise = 0.0;
  double referenceSeconds = 0.0;  // when the offline jaw (linear between frames) crosses
};

std::vector<Crossing> crossings(const std::vector<double>& jaw, const std::vector<std::size_t>& onsets) {
  std::vector<Crossing> result;
  const auto frameAt = [&](double seconds) {
    return std::clamp<long>(std::lround(seconds * kFps), 0, static_cast<long>(jaw.size()) - 1);
  };
  for (std::size_t onset : onsets) {
    // From where the jaw is when the onset arrives (whatever it did before) to its peak in the 500 ms after.
    const double t = static_cast<double>(onset) / kRate;
    const long first = static_cast<long>(std::floor(t * kFps));
    const double rest = jaw[static_cast<std::size_t>(std::clamp<long>(first, 0, static_cast<long>(jaw.size()) - 1))];
    const double peak = *std::max_element(jaw.begin() + frameAt(t), jaw.begin() + frameAt(t + 0.5) + 1);
    Crossing crossing{.threshold = rest + 0.25 * (peak - rest), .rise = peak - rest, .referenceSeconds = std::nan("")};
    for (long f = first; f < frameAt(t + 0.5); ++f) {
      const auto i = static_cast<std::size_t>(f);
      if (jaw[i + 1] >= crossing.threshold && jaw[i] < crossing.threshold) {
        const double w = (crossing.threshold - jaw[i]) / (jaw[i + 1] - jaw[i]);
        crossing.referenceSeconds = std::max(t, (static_cast<double>(f) + w) / kFps);
        break;
      }
    }
    result.push_back(crossing);
  }
  return result;
}

struct Shown {
  double streamSeconds;
  double jaw;  // FAP 3
  std::int64_t renderedNs;
};

struct Setting {
  std::string name;
  LiveDecoderOptions options;
  bool interpolate = false;
  const th::animation::MouthModel* mouth = nullptr;
  const th::animation::MouthNetwork* articulation = nullptr;  // the preset's, or none
};

struct Result {
  std::vector<double> totalMs, sharpMs, responseMs, pipelineMs, decodeMs, queueMs, behindMs, renderMs;
  int skipped = 0;
  int missed = 0;
  double lookaheadMs = 0.0;
};

Result run(const Setting& setting, const OnsetRecording& recording, const th::animation::HeadModel& head,
           const th::face::FaceModel& face, th::render::FaceRenderer& renderer, const th::render::OrbitCamera& camera) {
  Result result;
  const th::animation::MouthModel& mouth = *setting.mouth;
  const std::vector<double> reference =
      offlineJaw(recording.samples, head, mouth, setting.options, setting.articulation);
  const std::vector<Crossing> expected = crossings(reference, recording.onsets);
  // Models differ in how far they open the jaw: an onset counts if it opens it by a quarter of the model's
  // usual range (5th to 95th percentile over the recording).
  const double jawRange = percentileOf(reference, 95.0) - percentileOf(reference, 5.0);
  auto decoder =
      std::make_unique<th::pipeline::LiveDecoder>(&head, &mouth, setting.options, nullptr, setting.articulation);
  result.lookaheadMs = decoder->lookahead().totalMs;
  th::pipeline::LiveSession session(std::move(decoder));
  th::pipeline::Playout playout(th::pipeline::PlayoutOptions{.interpolate = setting.interpolate});
  std::vector<Shown> shown;
  th::render::RawFrame raw;
  session.start();
  th::pipeline::FileFeeder feeder(session, recording.samples, 1.0, kBlock);
  auto tick = std::chrono::steady_clock::now();
  AnimationFrame frame;
  while (!session.done()) {
    const std::int64_t now = th::pipeline::steadyNanoseconds();
    while (session.nextFrame(frame)) {
      playout.push(frame, now);
      result.decodeMs.push_back(static_cast<double>(frame.decodedNs - frame.inputReadNs) * 1e-6);
      result.queueMs.push_back(static_cast<double>(now - frame.decodedNs) * 1e-6);
    }
    th::pipeline::PlayoutSample sample;
    if (playout.sample(now, sample)) {
      renderer.setPositions(face.deform(sample.frame.faps));
      renderer.render(camera);
      renderer.readRaw(raw);  // waits for the frame
      const std::int64_t rendered = th::pipeline::steadyNanoseconds();
      shown.push_back({sample.streamSeconds, sample.frame.faps[3], rendered});
      result.behindMs.push_back(sample.behindNewestMs);
      result.renderMs.push_back(static_cast<double>(rendered - now) * 1e-6);
    }
    tick += std::chrono::microseconds(16667);
    std::this_thread::sleep_until(tick);
  }
  session.rethrowError();
  feeder.stop();
  const std::vector<std::int64_t>& written = feeder.blockWrittenNs();
  const auto enteredNs = [&](double seconds) {
    const auto block = static_cast<std::size_t>(std::max(0.0, seconds) * kRate) / kBlock;
    return written[std::min(block, written.size() - 1)];
  };
  for (std::size_t k = 0; k < recording.onsets.size(); ++k) {
    const Crossing& crossing = expected[k];
    const double onsetSeconds = static_cast<double>(recording.onsets[k]) / kRate;
    if (crossing.rise < 0.25 * jawRange || std::isnan(crossing.referenceSeconds)) {
      ++result.skipped;
      continue;
    }
    const auto moved = std::find_if(shown.begin(), shown.end(), [&](const Shown& s) {
      return s.streamSeconds >= std::floor(onsetSeconds * kFps) / kFps && s.streamSeconds <= onsetSeconds + 0.6 &&
             s.jaw >= crossing.threshold;
    });
    if (moved == shown.end()) {
      ++result.missed;
      continue;
    }
    result.totalMs.push_back(static_cast<double>(moved->renderedNs - enteredNs(onsetSeconds)) * 1e-6);
    if (recording.sharp[k]) result.sharpMs.push_back(result.totalMs.back());
    result.responseMs.push_back((crossing.referenceSeconds - onsetSeconds) * 1000.0);
    result.pipelineMs.push_back(static_cast<double>(moved->renderedNs - enteredNs(crossing.referenceSeconds)) * 1e-6);
  }
  return result;
}

void printDistribution(const char* what, const std::vector<double>& ms) {
  std::printf("    %-34s median %7.1f   p10 %7.1f   p90 %7.1f   max %7.1f ms\n", what, percentileOf(ms, 50),
              percentileOf(ms, 10), percentileOf(ms, 90), percentileOf(ms, 100));
}

// The speaker's own response to the same onsets: their tracked jaw (FAP 3 of `talkinghead track`'s fit, as the
// mouth models train on it; the tracks the training commands keep in $XDG_CACHE_HOME/talkinghead/tracks), by
// the same rule as the model's. How late a face that articulates like the speaker may move, before any
// pipeline: a jaw that opens with the vowel after a /b/, an /s/ or an /l/ is late against the sound's onset.
struct SpeakerResponse {
  std::vector<double> allMs, sharpMs;
  std::size_t withTrack = 0;
};

std::filesystem::path trackCacheFolder() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != 0)
    return std::filesystem::path(xdg) / "talkinghead" / "tracks";
  const char* home = std::getenv("HOME");
  return std::filesystem::path(home != nullptr ? home : ".") / ".cache" / "talkinghead" / "tracks";
}

SpeakerResponse speakerResponse(const OnsetRecording& recording) {
  SpeakerResponse result;
  std::vector<std::vector<double>> times, jaws;
  std::vector<double> everyJaw;
  std::vector<std::size_t> onsetOf;
  for (std::size_t i = 0; i < recording.clips.size(); ++i) {
    const std::filesystem::path& clip = recording.clips[i];
    // The training commands keep a folder's tracks under its path with '/' as '_' ("grid_s1").
    const std::filesystem::path track =
        trackCacheFolder() / ("grid_" + clip.parent_path().filename().string()) / (clip.filename().string() + ".csv");
    if (!std::filesystem::exists(track)) continue;
    const th::tracking::Track tracked = th::tracking::readTrackCsv(track);
    if (tracked.fittedFaps.empty()) continue;
    std::vector<double> t, jaw;
    for (const th::tracking::TrackedFrame& frame : tracked.frames) {
      t.push_back(frame.seconds);
      jaw.push_back(frame.fit.faps[3]);
    }
    everyJaw.insert(everyJaw.end(), jaw.begin(), jaw.end());
    times.push_back(std::move(t));
    jaws.push_back(std::move(jaw));
    onsetOf.push_back(i);
  }
  result.withTrack = onsetOf.size();
  if (everyJaw.empty()) return result;
  const double range = percentileOf(everyJaw, 95.0) - percentileOf(everyJaw, 5.0);
  for (std::size_t k = 0; k < onsetOf.size(); ++k) {
    const std::vector<double>& t = times[k];
    const std::vector<double>& jaw = jaws[k];
    const auto at = [&](double seconds) {  // linear between the video's frames
      const auto upper = std::upper_bound(t.begin(), t.end(), seconds);
      if (upper == t.begin()) return jaw.front();
      if (upper == t.end()) return jaw.back();
      const auto j = static_cast<std::size_t>(upper - t.begin());
      const double w = (seconds - t[j - 1]) / (t[j] - t[j - 1]);
      return jaw[j - 1] + w * (jaw[j] - jaw[j - 1]);
    };
    const double onset = recording.clipSeconds[onsetOf[k]];
    const double rest = at(onset);
    double peak = rest;
    for (double s = onset; s <= onset + 0.5; s += 0.001) peak = std::max(peak, at(s));
    if (peak - rest < 0.25 * range) continue;  // as for the models: the jaw hardly opens
    const double threshold = rest + 0.25 * (peak - rest);
    double s = onset;
    while (s < onset + 0.5 && at(s) < threshold) s += 0.001;
    result.allMs.push_back(1000.0 * (s - onset));
    if (recording.sharp[onsetOf[k]]) result.sharpMs.push_back(result.allMs.back());
  }
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
      only = argv[++i];
    } else {
      std::fprintf(stderr, "latency_bench: unknown argument %s (--quick, --only TEXT)\n", argv[i]);
      return 1;
    }
  }
  try {
    const std::filesystem::path models = TALKINGHEAD_SOURCE_DIR "/models";
    const th::animation::HeadModel head = th::animation::loadHeadModel(models / "head.json");
    const OnsetRecording recording = buildOnsetRecording(quick ? 6 : 1000);
    std::printf("onset latency: %zu onsets in %.1f s of GRID speech, played at real-time pace in %zu-sample blocks\n",
                recording.onsets.size(), static_cast<double>(recording.samples.size()) / kRate, kBlock);
    const SpeakerResponse speaker = speakerResponse(recording);
    if (speaker.allMs.empty()) {
      std::printf("  the speakers' own jaws: no tracks in %s (made by `talkinghead train mouth`)\n",
                  trackCacheFolder().c_str());
    } else {
      std::printf("  the speakers' own jaws (tracked video, the same rule; %zu onsets with a track, %zu opening):\n",
                  speaker.withTrack, speaker.allMs.size());
      printDistribution("  sharp onsets", speaker.sharpMs);
      printDistribution("  all onsets", speaker.allMs);
    }

    const th::face::FaceModel face = th::face::FaceModel::buildDefault();
    th::render::OffscreenContext context;
    th::render::FaceRenderer renderer(context, face.mesh(), {.width = 1280, .height = 720, .samples = 1, .fxaa = true});
    renderer.setMouthOpening(face.innerLipVertices());
    renderer.setEyeOpenings(face.eyeLidVertices(0), face.eyeLidVertices(1));
    const th::render::OrbitCamera camera = th::render::frameHead(face.mesh().positions, 1280.0 / 720.0);

    // The baseline (the first live step: frames wait for the head, the offline mouth model, window 2,
    // interpolated), then the presets of pipeline/live_presets.h.
    std::vector<th::animation::MouthModel> mouths;
    mouths.reserve(th::pipeline::kLivePresets.size());
    std::vector<th::animation::MouthNetwork> articulations;
    articulations.reserve(th::pipeline::kLivePresets.size());
    std::vector<Setting> settings;
    LiveDecoderOptions baseline;
    baseline.waitForHead = true;
    baseline.mouth.windowFrames = 2;
    for (const th::pipeline::LivePreset& preset : th::pipeline::kLivePresets) {
      mouths.push_back(th::animation::loadMouthModel(models / std::string(preset.mouthModelFile)));
      articulations.push_back(th::animation::loadMouthNetwork(models / std::string(preset.articulationFile)));
      if (preset.name == "accurate")
        settings.push_back({"baseline: frames wait for the head (accurate's mouth)", baseline, true, &mouths.back()});
    }
    for (std::size_t p = 0; p < th::pipeline::kLivePresets.size(); ++p) {
      const th::pipeline::LivePreset& preset = th::pipeline::kLivePresets[p];
      // The preset's values as the live command applies them (pipeline/options.h).
      th::pipeline::LiveSettings applied;
      th::pipeline::applyLivePreset(applied, preset.name);
      LiveDecoderOptions options;
      options.mouth.windowFrames = applied.streaming.window;
      const bool interpolate = applied.live.interpolate;
      const std::string name = "preset " + std::string(preset.name) + ": " + std::string(preset.mouthModelFile) +
                               ", window " + std::to_string(applied.streaming.window) +
                               (interpolate ? ", interpolated" : ", newest frame");
      settings.push_back(
          {name + ", " + std::string(preset.articulationFile), options, interpolate, &mouths[p], &articulations[p]});
      // The same without the articulation: what the preset was before it.
      settings.push_back({name + ", no articulation", options, interpolate, &mouths[p], nullptr});
    }
    double baselineMedian = 0.0;
    for (const Setting& setting : settings) {
      if (!only.empty() && baselineMedian != 0.0 && setting.name.find(only) == std::string::npos) continue;
      const Result result = run(setting, recording, head, face, renderer, camera);
      const double median = percentileOf(result.sharpMs, 50);
      if (baselineMedian == 0.0) baselineMedian = median;
      std::printf("\n  %s (look-ahead %.1f ms): %zu onsets measured, %d skipped (the jaw hardly opens), %d not seen\n",
                  setting.name.c_str(), result.lookaheadMs, result.totalMs.size(), result.skipped, result.missed);
      char sharpLabel[64];
      std::snprintf(sharpLabel, sizeof sharpLabel, "sharp onsets (%zu) -> mouth rendered", result.sharpMs.size());
      printDistribution(sharpLabel, result.sharpMs);
      printDistribution("  all onsets", result.totalMs);
      printDistribution("  the model's response", result.responseMs);
      printDistribution("  the pipeline", result.pipelineMs);
      printDistribution("  decoding (read -> frame out)", result.decodeMs);
      printDistribution("  queue (frame out -> display)", result.queueMs);
      printDistribution("  playout (newest frame - shown)", result.behindMs);
      printDistribution("  deform + render + read back", result.renderMs);
      std::printf("    sharp onsets' median against the baseline: %.2fx\n", median / baselineMedian);
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "latency_bench: %s\n", error.what());
    return 1;
  }
  return 0;
}
