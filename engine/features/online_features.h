// Speech features, one frame per animation frame, computed as a stream (the shape of Kaldi's online features).
//
//   th::features::OnlineFeatureExtractor extractor({});      // 16 kHz mono in, 30 frames/s out
//   extractor.acceptWaveform(chunk);                          // chunks of any size
//   std::vector<float> row(extractor.layout().size());
//   for (; next < extractor.numFramesReady(); ++next) extractor.getFrame(next, row);
//   extractor.inputFinished();                                // then read the remaining frames
//
// Frame i is centred at i / framesPerSecond seconds. Its row (see FeatureLayout) holds F0 (Hz, 0 = unvoiced),
// normalised log energy, their regression deltas, MFCC c1..cN, and the MFCCs of frames i-tc .. i+tc stacked
// (edges replicate the first/last frame). Frames are only released once everything they depend on has
// arrived, so the output never depends on how the input was chunked: chunked == whole-buffer, bit for bit.
// lookahead() states, per feature, how far past a frame's time the input must reach.
//
// Thread contract: one thread per instance (the live pipeline's worker); no locks inside.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/frame_store.h"
#include "features/mfcc.h"
#include "features/pitch.h"
#include "features/sample_history.h"

namespace th::features {

enum class EnergyNormalisation {
  kUtterance,  // (e - mean) / std over the whole input: frames are released only after inputFinished()
  kRunning,    // by a causal running mean and std (exponential, time constant runningNormSeconds)
  kNone,       // raw level in dB re full scale
};

struct FeatureOptions {
  double framesPerSecond = 30.0;  // 10 .. 200
  PitchOptions pitch;
  MfccOptions mfcc;        // its window also frames the energy
  int deltaHalfWidth = 2;  // regression deltas over +-2 frames
  int contextFrames = 5;   // MFCC context stacking +-tc frames
  EnergyNormalisation energyNormalisation = EnergyNormalisation::kRunning;
  double runningNormSeconds = 3.0;
  double energyRangeDb = 60.0;  // levels more than this below the loudest frame so far are raised to it
  // false: no F0 (rows say 0 Hz), and frames wait for nothing but their MFCC window. The live mouth uses
  // this: its MFCCs then come sooner, by the pitch tracker's decision lag (features.md's look-ahead table).
  bool trackPitch = true;

  void check() const;  // throws th::Error naming the bad option
};

// Named positions in a feature row.
struct FeatureLayout {
  static constexpr int kF0Hz = 0;
  static constexpr int kEnergy = 1;
  static constexpr int kDeltaF0 = 2;
  static constexpr int kDeltaEnergy = 3;
  static constexpr int kMfccBegin = 4;
  int numMfcc = 11;  // MFCC values per frame: c1..cN, then c0 when hasC0
  bool hasC0 = false;
  int contextFrames = 5;

  int contextBegin() const { return kMfccBegin + numMfcc; }  // stacked MFCCs of frames i-tc .. i+tc
  int contextSize() const { return (2 * contextFrames + 1) * numMfcc; }
  int size() const { return contextBegin() + contextSize(); }
  std::vector<std::string> columnNames() const;  // f0_hz, energy, d_f0, d_energy, mfcc1.., ctx columns
};

// Look-ahead of each feature: how much input past a frame's time is needed before the frame is released.
struct FeatureLookahead {
  double f0Ms;
  double energyMs;
  double mfccMs;
  double deltasMs;
  double contextMs;
  double totalMs;   // what the extractor as a whole waits for
  int totalFrames;  // the same, in output frames (rounded up)
};

class OnlineFeatureExtractor {
 public:
  explicit OnlineFeatureExtractor(const FeatureOptions& options);
  OnlineFeatureExtractor(const OnlineFeatureExtractor&) = delete;
  OnlineFeatureExtractor& operator=(const OnlineFeatureExtractor&) = delete;

  static constexpr int kSampleRateHz = 16000;

  void acceptWaveform(std::span<const float> samples);  // 16 kHz mono
  void inputFinished();

  int numFramesReady() const;
  bool isLastFrame(int frame) const;
  void getFrame(int frame, std::span<float> row) const;
  // A frame's own MFCCs and level are final before its row is (the row waits for deltas and context):
  // frames [0, numBaseFramesReady()) can be read with getMfcc / getEnergy already.
  int numBaseFramesReady() const { return static_cast<int>(f0Hz_.size()); }
  void getMfcc(int frame, std::span<float> mfcc) const;  // numMfcc values
  float getEnergy(int frame) const;                      // as the row's energy (final unless kUtterance)
  float getLevelDb(int frame) const;                     // the level before normalisation, dB re full scale
  double frameTimeSeconds(int frame) const { return frame / options_.framesPerSecond; }

  const FeatureLayout& layout() const { return layout_; }
  const FeatureOptions& options() const { return options_; }
  FeatureLookahead lookahead() const;
  // The caller will read no frame before `frame` again (getFrame, getMfcc, getEnergy, getLevelDb): what only
  // those needed is freed, so that memory stays bounded on an endless stream. Not with kUtterance (it needs
  // every frame at the end).
  void forgetBefore(int frame);
  std::size_t framesHeld() const { return f0Hz_.held(); }

 private:
  void computeAvailableBaseFrames();
  long long frameCentreSample(long long frame) const;
  long long totalFramesForSamples(long long numSamples) const;
  int pitchFrameFor(long long frame) const;
  void normaliseUtterance();

  FeatureOptions options_;
  FeatureLayout layout_;
  OnlinePitchTracker pitch_;
  MfccComputer mfcc_;
  int rightContextFrames_;

  SampleHistory history_;
  bool finished_ = false;

  // Per base frame: F0, normalised energy, MFCCs (row-major numMfcc each).
  FrameStore<float> f0Hz_;
  FrameStore<float> energyDb_;
  FrameStore<float> energy_;
  FrameStore<float> mfccRows_;  // numMfcc values per frame
  std::vector<float> window_;
  std::vector<float> energyWeights_;
  double loudestDb_ = -1e9;
  double runningMean_ = 0.0;
  double runningVariance_ = 0.0;
};

// Batch path: the same extractor fed the whole signal at once. Energy defaults to utterance normalisation.
struct FeatureMatrix {
  FeatureLayout layout;
  double framesPerSecond = 30.0;
  std::vector<float> values;   // numFrames x layout.size(), row-major: a frame's row contiguous
  std::vector<float> levelDb;  // per frame: the level before normalisation (getLevelDb)
  int numFrames() const { return layout.size() > 0 ? static_cast<int>(values.size()) / layout.size() : 0; }
  std::span<const float> row(int frame) const {
    return {values.data() + static_cast<size_t>(frame) * layout.size(), static_cast<size_t>(layout.size())};
  }
};
FeatureOptions batchFeatureOptions();
FeatureMatrix computeFeatures(std::span<const float> samples16k, const FeatureOptions& options = batchFeatureOptions());

}  // namespace th::features
