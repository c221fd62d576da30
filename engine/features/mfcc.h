// Mel-frequency cepstral coefficients of one analysis window, with the conventions of SPTK's `mfcc`
// (SPTK 3.9, the Debian package), so our numbers can be checked against a reference we did not write:
//   - samples in 16-bit integer scale (x 32768), as SPTK and HTK expect (the filterbank floor of 1.0 is then
//     one quantisation step);
//   - pre-emphasis inside the window: y[0] = x[0](1 - a), y[n] = x[n] - a x[n-1];
//   - Hamming window 0.54 - 0.46 cos(2 pi n / (L - 1)), zero-padded to the FFT size;
//   - magnitude (not power) spectrum, bins 1 .. N/2 - 1;
//   - triangular mel filters (mel = 1127.01048 ln(1 + f/700)), channel j peaking at j/(numBands+1) of the
//     Nyquist mel, natural log with floor;
//   - orthonormal DCT-II, HTK lifter 1 + (L/2) sin(pi k / L); c1..cN returned, then c0 if asked for. c0 is
//     SPTK's (`mfcc -0`): sqrt(2/M) * sum of the M log channels, sqrt(2) times the orthonormal DCT's c0.
//     SPTK's log energy (`mfcc -E`) is not offered: OnlineFeatureExtractor computes its own level.
// Framing is the caller's: SPTK's `frame -l L -p P` centres frame i on sample i*P (zeros before the start),
// which is what OnlineFeatureExtractor does at 100 frames/s (P = 160).
//
// Agreement with SPTK (tests/features/mfcc_sptk_test.cpp runs `sptk frame | sptk mfcc` with these options
// on real speech): |ours - SPTK| <= 5e-4 * max(1, |SPTK|) for every coefficient of every frame. Measured
// worst case 1.9e-4 (absolute, c9 of a BEAT2 frame; 1.4e-4 relative) over 24 BEAT2, FDA-UE and ARCTIC
// recordings. Nearly all of it is our single-precision FFT: SPTK is within 2e-6 of an all-double computation.
//
//   th::features::MfccComputer mfcc({}, 16000);
//   std::vector<float> coefficients(mfcc.numOutputs());
//   mfcc.compute(window /* options.windowLength samples */, coefficients);
//
// Thread contract: one instance per thread (it owns FFT scratch buffers).
#pragma once

#include <span>
#include <vector>

#include "features/real_fft.h"

namespace th::features {

struct MfccOptions {
  int numCoefficients = 11;  // c1..c11, as the AV-HMM paper
  bool includeC0 = false;    // if true, c0 (SPTK's scaling, see above) is appended after c1..cN
  int numMelBands = 24;
  double windowMs = 25.0;
  int fftSize = 512;  // at 16 kHz; must be >= the window length
  double preEmphasis = 0.97;
  int lifter = 22;               // 0 disables liftering
  double filterbankFloor = 1.0;  // in 16-bit-scale magnitude units
  // Vocal tract length perturbation (Jaitly & Hinton 2013), for training on more voices than were recorded: the
  // filterbank hears frequency f at α·f (piecewise linear, the Nyquist frequency fixed; 1: none). α 0.9-1.1
  // spans about the difference between a man's and a woman's vocal tract.
  double frequencyWarp = 1.0;
};

class MfccComputer {
 public:
  MfccComputer(const MfccOptions& options, int sampleRateHz);

  int windowLength() const { return windowLength_; }
  int numOutputs() const { return options_.numCoefficients + (options_.includeC0 ? 1 : 0); }
  const MfccOptions& options() const { return options_; }

  // `window` holds windowLength() samples in [-1, 1]; `coefficients` receives numOutputs() values.
  void compute(std::span<const float> window, std::span<float> coefficients);

 private:
  MfccOptions options_;
  int windowLength_;
  RealFft fft_;
  std::vector<float> hamming_;
  // Each FFT bin k (1 .. N/2-1) splits its magnitude between two neighbouring channels.
  std::vector<int> lowerChannel_;
  std::vector<double> lowerWeight_;
  std::vector<double> dctBasis_;  // (numCoefficients + 1) x numMelBands, row-major, orthonormal DCT-II
  std::vector<double> lifterGain_;
  std::vector<double> bands_;
};

}  // namespace th::features
