#include "eval/peer_trackers.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "audio/audio_file.h"
#include "core/error.h"
#include "core/subprocess.h"
#include "core/temporary_file.h"

namespace th::eval {
namespace {

// Praat's "To Pitch (ac)" with its standard parameters except time step and range, one "time f0" per line.
constexpr const char* kPraatScript = R"(form Pitch
  sentence wav
  real step
  real floor
  real ceiling
endform
sound = Read from file: wav$
pitch = To Pitch (ac): step, floor, 15, "no", 0.03, 0.45, 0.01, 0.35, 0.14, ceiling
frames = Get number of frames
for i to frames
  t = Get time from frame number: i
  f = Get value in frame: i, "Hertz"
  if f = undefined
    f = 0
  endif
  appendInfoLine: fixed$(t, 6), " ", fixed$(f, 4)
endfor
)";

F0Track parseTimeValueLines(const std::string& text, const std::string& who) {
  F0Track track;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    double t = 0.0;
    double f = 0.0;
    if (!(fields >> t >> f)) continue;
    track.timesSeconds.push_back(t);
    track.f0Hz.push_back(std::isfinite(f) && f > 0.0 ? f : 0.0);
  }
  if (track.f0Hz.empty()) throw Error(who + ": printed no F0 values");
  return track;
}

F0Track runPraat(const std::filesystem::path& wav, const PeerSettings& settings) {
  TemporaryFile script(".praat");
  std::ofstream(script.path()) << kPraatScript;
  const std::string out = runProgram({"praat", "--run", script.path().string(), std::filesystem::absolute(wav).string(),
                                      std::to_string(settings.hopSeconds), std::to_string(settings.minF0Hz),
                                      std::to_string(settings.maxF0Hz)});
  return parseTimeValueLines(out, "praat");
}

F0Track runSptk(const std::filesystem::path& wav, const PeerSettings& settings, int algorithm) {
  audio::AudioReadOptions keepRate;
  keepRate.outputRateHz = 0;
  const audio::AudioClip clip = audio::readAudioFile(wav, keepRate);
  // SPTK reads raw native floats in 16-bit integer scale.
  TemporaryFile raw(".f32");
  {
    std::ofstream out(raw.path(), std::ios::binary);
    for (float sample : clip.samples) {
      const float scaled = sample * 32768.0f;
      out.write(reinterpret_cast<const char*>(&scaled), sizeof(scaled));
    }
  }
  const int hopSamples = static_cast<int>(std::lround(settings.hopSeconds * clip.sampleRateHz));
  const std::string out =
      runProgram({"sptk", "pitch", "-a", std::to_string(algorithm), "-s", std::to_string(clip.sampleRateHz / 1000.0),
                  "-p", std::to_string(hopSamples), "-L", std::to_string(settings.minF0Hz), "-H",
                  std::to_string(settings.maxF0Hz), "-o", "1"},
                 raw.path().string());
  F0Track track;
  const size_t count = out.size() / sizeof(float);
  for (size_t i = 0; i < count; ++i) {
    float value = 0.0f;
    std::memcpy(&value, out.data() + i * sizeof(float), sizeof(float));
    // SPTK's frame k is centred at k * shift.
    track.timesSeconds.push_back(static_cast<double>(i) * hopSamples / clip.sampleRateHz);
    track.f0Hz.push_back(std::isfinite(value) && value > 0.0f ? value : 0.0);
  }
  if (track.f0Hz.empty()) throw Error("sptk pitch: printed no F0 values");
  return track;
}

F0Track runAubio(const std::filesystem::path& wav, const PeerSettings& settings) {
  audio::AudioReadOptions keepRate;
  keepRate.outputRateHz = 0;
  const int rate = audio::readAudioFile(wav, keepRate).sampleRateHz;
  const int hopSamples = static_cast<int>(std::lround(settings.hopSeconds * rate));
  // A buffer of about 50 ms rounded up to a power of two (1024 at 20 kHz): aubio does better with it on
  // FDA-UE than with 2048 (docs/results.md, "Figures behind choices in the code").
  int buffer = 512;
  while (buffer < 0.05 * rate) buffer *= 2;
  const std::string out = runProgram({"aubiopitch", "-i", wav.string(), "-p", "yinfft", "-H",
                                      std::to_string(hopSamples), "-B", std::to_string(buffer), "-u", "Hz"});
  F0Track track = parseTimeValueLines(out, "aubiopitch");
  // aubio reports no voicing decision other than 0 Hz; values outside the search range count as unvoiced.
  for (double& f : track.f0Hz) {
    if (f < settings.minF0Hz || f > settings.maxF0Hz) f = 0.0;
  }
  return track;
}

}  // namespace

std::vector<PeerTracker> allPeerTrackers() {
  return {PeerTracker::kPraat, PeerTracker::kRapt, PeerTracker::kSwipe, PeerTracker::kAubioYinFft};
}

std::string peerName(PeerTracker peer) {
  switch (peer) {
    case PeerTracker::kPraat:
      return "Praat ac";
    case PeerTracker::kRapt:
      return "SPTK RAPT";
    case PeerTracker::kSwipe:
      return "SPTK SWIPE";
    case PeerTracker::kAubioYinFft:
      return "aubio yinfft";
  }
  return "?";
}

std::string peerProgram(PeerTracker peer) {
  switch (peer) {
    case PeerTracker::kPraat:
      return "praat";
    case PeerTracker::kRapt:
    case PeerTracker::kSwipe:
      return "sptk";
    case PeerTracker::kAubioYinFft:
      return "aubiopitch";
  }
  return "?";
}

F0Track runPeerTracker(PeerTracker peer, const std::filesystem::path& wav, const PeerSettings& settings) {
  switch (peer) {
    case PeerTracker::kPraat:
      return runPraat(wav, settings);
    case PeerTracker::kRapt:
      return runSptk(wav, settings, 0);
    case PeerTracker::kSwipe:
      return runSptk(wav, settings, 1);
    case PeerTracker::kAubioYinFft:
      return runAubio(wav, settings);
  }
  throw Error("unknown peer tracker");
}

}  // namespace th::eval
