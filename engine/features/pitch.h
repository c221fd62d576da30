// Streaming F0 tracker: normalised autocorrelation candidates + fixed-lag Viterbi over candidate paths.
//
//   th::features::OnlinePitchTracker pitch({}, 16000);
//   pitch.acceptWaveform(chunk);            // any chunk size, as often as you like
//   for (; next < pitch.numFramesReady(); ++next) use(pitch.frame(next));   // f0Hz == 0: unvoiced
//   pitch.inputFinished();                  // flushes the last frames
//
// Frame k is centred at k * hopMs. Per frame: a Hann-windowed autocorrelation (FFT) divided by the window's own
// autocorrelation (Boersma 1993, "Accurate short-term analysis of the fundamental frequency ..."), whose local
// maxima in [1/maxF0, 1/minF0] are the voiced candidates (lag refined by parabolic interpolation), plus
// one unvoiced candidate scored from the frame's level against the running peak. A Viterbi search trades
// candidate strength against octave jumps and voicing changes; frame k is decided when frame k + lag has been
// analysed (traceback from the best current state), so the look-ahead is fixed: lookaheadSamples().
// The decision for a frame never depends on how the input was chunked: streaming == batch, bit for bit.
//
// Thread contract: one thread per instance.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "core/frame_store.h"
#include "features/real_fft.h"
#include "features/sample_history.h"

namespace th::features {

enum class PitchNormalisation {
  kWindowAutocorrelation,  // Boersma 1993 / Praat: r(lag) / (r(0) * r_window(lag))
  kNccf,                   // energies of the overlapping parts, corrected for the window's own NCCF
};

struct PitchOptions {
  double minF0Hz = 60.0;
  double maxF0Hz = 500.0;
  double hopMs = 5.0;
  double windowMs = 30.0;           // analysis window (Hann); look-ahead is half of it plus the decision lag
  int decisionLagFrames = 6;        // fixed-lag Viterbi: frames after a frame that are seen before deciding it
  int maxCandidates = 6;            // voiced candidates per frame
  double voicingThreshold = 0.5;    // autocorrelation strength a voiced frame needs
  double silenceThreshold = 0.05;   // frame peak relative to the running peak below which a frame is silent
  double octaveCost = 0.02;         // per octave: favours the higher of two candidates (against sub-octaves)
  double octaveJumpCost = 0.35;     // per octave of change between consecutive voiced frames (at 10 ms)
  double voicedUnvoicedCost = 0.2;  // per voicing change (at 10 ms)
  // Time resolution at voicing boundaries: each candidate's periodicity is also measured by a normalised
  // cross-correlation over a short window centred on the frame (as RAPT's NCCF), and mixed into its strength.
  double shortWindowMs = 10.0;      // 0 disables
  double shortWeight = 0.5;         // weight of the short-window periodicity in a candidate's strength
  double subharmonicPenalty = 0.1;  // strength taken from a candidate whose half period correlates as well
  double subharmonicRatio = 0.9;    // "as well": at least this fraction of the candidate's correlation
  PitchNormalisation normalisation = PitchNormalisation::kNccf;
  double levelWindowMs = 10.0;  // silence is judged on the peak within this window at the centre (0: whole)
};

struct PitchFrame {
  float f0Hz = 0.0f;      // 0 when unvoiced
  float strength = 0.0f;  // best normalised autocorrelation in the frame, 0..1
};

class OnlinePitchTracker {
 public:
  OnlinePitchTracker(const PitchOptions& options, int sampleRateHz);
  OnlinePitchTracker(const OnlinePitchTracker&) = delete;
  OnlinePitchTracker& operator=(const OnlinePitchTracker&) = delete;

  void acceptWaveform(std::span<const float> samples);
  void inputFinished();

  int numFramesReady() const { return static_cast<int>(decided_.size()); }
  bool isLastFrame(int frame) const { return finished_ && frame == numFramesReady() - 1; }
  const PitchFrame& frame(int frame) const { return decided_[static_cast<size_t>(frame)]; }
  // Frames before `frame` will not be read again: they are freed (an endless stream stays bounded).
  void forgetBefore(int frame) { decided_.forgetBefore(static_cast<size_t>(std::max(0, frame))); }
  std::size_t framesHeld() const { return decided_.held(); }

  int hopSamples() const { return hopSamples_; }
  // Samples after a frame's centre that must have arrived before the frame is decided.
  int lookaheadSamples() const { return windowLength_ / 2 + options_.decisionLagFrames * hopSamples_; }
  const PitchOptions& options() const { return options_; }

 private:
  struct Candidate {
    float f0Hz;
    float correlation;
    double strength;
  };
  struct AnalysedFrame {
    std::vector<Candidate> candidates;  // [0] is the unvoiced candidate
    std::vector<double> score;
    std::vector<int> back;
    float bestCorrelation;
  };

  void analyseAvailableFrames();
  void analyseFrame(long long frameIndex);
  double unvoicedStrength(double localPeak) const;
  void normaliseCorrelation(float energy);
  void addPeakCandidates(AnalysedFrame& frame) const;
  void viterbiStep(AnalysedFrame& current, const AnalysedFrame* previous) const;
  void decideUpTo(long long lastFrameToDecide, long long tracebackFrom);
  AnalysedFrame& analysed(long long frameIndex) { return ring_[static_cast<size_t>(frameIndex % ring_.size())]; }

  PitchOptions options_;
  int sampleRateHz_;
  int hopSamples_;
  int windowLength_;
  int minLag_;
  int maxLag_;
  double transitionScale_;
  int shortWindowLength_;
  RealFft fft_;
  std::vector<float> window_;
  std::vector<float> windowAutocorrelation_;  // normalised to 1 at lag 0
  std::vector<float> energyPrefix_;           // running sums of the windowed frame's squared samples
  std::vector<float> correlation_;            // the frame's normalised autocorrelation by lag
  std::vector<float> segment_;                // the frame's samples, mean removed, unwindowed
  double shortCorrelation(double lag) const;

  SampleHistory history_;
  bool finished_ = false;

  double runningPeak_ = 0.0;
  long long numAnalysed_ = 0;
  std::vector<AnalysedFrame> ring_;  // the last decisionLag + 2 analysed frames
  FrameStore<PitchFrame> decided_;   // by frame number; forgetBefore() drops the old ones
};

// Whole-signal convenience: the same streaming object, fed once.
std::vector<PitchFrame> trackPitch(std::span<const float> samples, int sampleRateHz, const PitchOptions& options = {});

}  // namespace th::features
