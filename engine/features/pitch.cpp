#include "features/pitch.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"

namespace th::features {
namespace {

int fftSizeFor(int minimumLength) {
  int size = 64;
  while (size < minimumLength) size *= 2;
  return size;
}

}  // namespace

OnlinePitchTracker::OnlinePitchTracker(const PitchOptions& options, int sampleRateHz)
    : options_(options),
      sampleRateHz_(sampleRateHz),
      hopSamples_(static_cast<int>(std::lround(options.hopMs * 1e-3 * sampleRateHz))),
      windowLength_(2 * static_cast<int>(std::lround(options.windowMs * 1e-3 * sampleRateHz / 2.0))),
      minLag_(static_cast<int>(std::floor(sampleRateHz / options.maxF0Hz))),
      maxLag_(static_cast<int>(std::ceil(sampleRateHz / options.minF0Hz))),
      // Praat's convention: costs are stated for a 10 ms step and scaled to the actual one.
      transitionScale_(0.01 / (options.hopMs * 1e-3)),
      shortWindowLength_(static_cast<int>(std::lround(options.shortWindowMs * 1e-3 * sampleRateHz))),
      fft_(fftSizeFor(2 * static_cast<int>(std::lround(options.windowMs * 1e-3 * sampleRateHz / 2.0)) +
                      static_cast<int>(std::ceil(sampleRateHz / options.minF0Hz)) + 2)) {
  if (!(options.minF0Hz > 0) || !(options.maxF0Hz > options.minF0Hz)) {
    throw Error("pitch: need 0 < minF0Hz < maxF0Hz");
  }
  if (hopSamples_ < 1) throw Error("pitch: hop is shorter than one sample");
  if (maxLag_ + 1 >= windowLength_) throw Error("pitch: the window must be longer than the longest period");
  if (minLag_ < 2) throw Error("pitch: maxF0Hz is too close to the sample rate");
  if (options.decisionLagFrames < 0) throw Error("pitch: decisionLagFrames must be >= 0");
  if (shortWindowLength_ / 2 + maxLag_ / 2 + 2 > windowLength_ / 2) {
    throw Error("pitch: the short window plus half the longest period must fit in half the analysis window");
  }

  window_.resize(static_cast<size_t>(windowLength_));
  for (int n = 0; n < windowLength_; ++n) {
    window_[static_cast<size_t>(n)] =
        static_cast<float>(0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * (n + 0.5) / windowLength_));
  }
  // The window's autocorrelation, by the same FFT path as the signal's so the division is consistent.
  float* time = fft_.timeData();
  std::fill(time, time + fft_.size(), 0.0f);
  std::copy(window_.begin(), window_.end(), time);
  fft_.forward();
  for (int k = 0; k < fft_.numBins(); ++k) fft_.spectrum()[k] = std::norm(fft_.spectrum()[k]);
  fft_.inverse();
  windowAutocorrelation_.resize(static_cast<size_t>(maxLag_ + 2));
  std::vector<double> windowEnergyPrefix(static_cast<size_t>(windowLength_ + 1), 0.0);
  for (int n = 0; n < windowLength_; ++n) {
    windowEnergyPrefix[static_cast<size_t>(n + 1)] =
        windowEnergyPrefix[static_cast<size_t>(n)] + window_[static_cast<size_t>(n)] * window_[static_cast<size_t>(n)];
  }
  for (int lag = 0; lag <= maxLag_ + 1; ++lag) {
    if (options_.normalisation == PitchNormalisation::kWindowAutocorrelation) {
      windowAutocorrelation_[static_cast<size_t>(lag)] = time[lag] / time[0];
    } else {
      // What a stationary signal's windowed NCCF would be at this lag: dividing by it removes the window's bias.
      const double head = windowEnergyPrefix[static_cast<size_t>(windowLength_ - lag)];
      const double tail =
          windowEnergyPrefix[static_cast<size_t>(windowLength_)] - windowEnergyPrefix[static_cast<size_t>(lag)];
      windowAutocorrelation_[static_cast<size_t>(lag)] =
          static_cast<float>(time[lag] / time[0] * windowEnergyPrefix.back() / std::sqrt(head * tail));
    }
  }
  energyPrefix_.assign(static_cast<size_t>(windowLength_ + 1), 0.0f);
  correlation_.assign(static_cast<size_t>(maxLag_ + 2), 0.0f);
  segment_.resize(static_cast<size_t>(windowLength_));
  ring_.resize(static_cast<size_t>(options.decisionLagFrames + 2));  // + the frame before the oldest undecided
  for (auto& frame : ring_) {
    frame.candidates.reserve(static_cast<size_t>(options.maxCandidates + 1));
    frame.score.reserve(static_cast<size_t>(options.maxCandidates + 1));
    frame.back.reserve(static_cast<size_t>(options.maxCandidates + 1));
  }
}

void OnlinePitchTracker::acceptWaveform(std::span<const float> samples) {
  if (finished_) throw Error("pitch: acceptWaveform after inputFinished");
  history_.append(samples);
  analyseAvailableFrames();
}

void OnlinePitchTracker::inputFinished() {
  if (finished_) return;
  finished_ = true;
  analyseAvailableFrames();
  if (numAnalysed_ > 0) decideUpTo(numAnalysed_ - 1, numAnalysed_ - 1);
}

void OnlinePitchTracker::analyseAvailableFrames() {
  const long long half = windowLength_ / 2;
  // Frames whose centre lies inside the signal; the last ones are analysed (zero-padded) only once the input
  // is known to have ended.
  const long long totalFrames = history_.size() > 0 ? (history_.size() - 1) / hopSamples_ + 1 : 0;
  while (numAnalysed_ < totalFrames) {
    const long long centre = numAnalysed_ * hopSamples_;
    if (!finished_ && centre + half > history_.size()) break;
    analyseFrame(numAnalysed_);
    ++numAnalysed_;
    const long long decidable = numAnalysed_ - 1 - options_.decisionLagFrames;
    if (decidable >= static_cast<long long>(decided_.size())) decideUpTo(decidable, numAnalysed_ - 1);
  }
  // Drop samples that no future frame will read.
  history_.forgetBefore(numAnalysed_ * hopSamples_ - half);
}

void OnlinePitchTracker::analyseFrame(long long frameIndex) {
  const long long start = frameIndex * hopSamples_ - windowLength_ / 2;
  history_.copy(start, segment_);
  // Vectorised passes (Eigen) over the frame: remove the mean, window, and the level's peak.
  Eigen::Map<Eigen::VectorXf> segment(segment_.data(), windowLength_);
  const float mean = segment.mean();
  segment.array() -= mean;
  const double localPeak = segment.cwiseAbs().maxCoeff();
  float* time = fft_.timeData();
  Eigen::Map<Eigen::VectorXf>(time, windowLength_) =
      segment.cwiseProduct(Eigen::Map<const Eigen::VectorXf>(window_.data(), windowLength_));
  std::fill(time + windowLength_, time + fft_.size(), 0.0f);
  // Running sums of the windowed frame's squares give each lag's overlap energies (kNccf).
  float cumulative = 0.0f;
  for (int n = 0; n < windowLength_; ++n) {
    cumulative += time[n] * time[n];
    energyPrefix_[static_cast<size_t>(n + 1)] = cumulative;
  }
  runningPeak_ = std::max(runningPeak_, localPeak);

  AnalysedFrame& frame = analysed(frameIndex);
  frame.candidates.clear();
  frame.bestCorrelation = 0.0f;
  frame.candidates.push_back({0.0f, 0.0f, unvoicedStrength(localPeak)});

  if (localPeak > 0.0) {
    fft_.forward();
    std::complex<float>* spectrum = fft_.spectrum();
    for (int k = 0; k < fft_.numBins(); ++k) spectrum[k] = std::norm(spectrum[k]);
    fft_.inverse();
    const float energy = time[0];
    if (energy > 0.0f) {
      normaliseCorrelation(energy);
      addPeakCandidates(frame);
    }
  }
  viterbiStep(frame, frameIndex > 0 ? &analysed(frameIndex - 1) : nullptr);
}

// Praat's unvoiced strength: the voicing threshold, raised for frames much quieter than the loudest so far.
double OnlinePitchTracker::unvoicedStrength(double localPeak) const {
  const double vt = options_.voicingThreshold;
  double levelPeak = localPeak;
  if (options_.levelWindowMs > 0.0) {
    // The level that decides silence is taken near the frame's centre, so that a loud neighbour inside the
    // long window does not make a silent frame look voiced.
    const int half = static_cast<int>(std::lround(options_.levelWindowMs * 1e-3 * sampleRateHz_ / 2.0));
    levelPeak = 0.0;
    for (int n = windowLength_ / 2 - half; n < windowLength_ / 2 + half; ++n) {
      levelPeak = std::max(levelPeak, static_cast<double>(std::abs(segment_[static_cast<size_t>(n)])));
    }
  }
  const double relativePeak = runningPeak_ > 0 ? levelPeak / runningPeak_ : 0.0;
  return vt + std::max(0.0, 2.0 - relativePeak / (options_.silenceThreshold / (1.0 + vt)));
}

// The autocorrelation in the FFT's time buffer (the inverse FFT of the power spectrum; `energy` its lag 0) into
// correlation_, every lag normalised once, in a loop the compiler can vectorise.
void OnlinePitchTracker::normaliseCorrelation(float energy) {
  const float* time = fft_.timeData();
  if (options_.normalisation == PitchNormalisation::kNccf) {
    // By the energies of the two overlapping parts (<= 1 by Cauchy-Schwarz even at onsets, where the
    // window-autocorrelation normalisation overshoots for long lags). The inverse FFT is unnormalised:
    // its output is fft size times the autocorrelation.
    const float total = energyPrefix_[static_cast<size_t>(windowLength_)];
    const auto scale = static_cast<float>(fft_.size());
    for (int lag = 1; lag <= maxLag_ + 1; ++lag) {
      const float head = energyPrefix_[static_cast<size_t>(windowLength_ - lag)];
      const float tail = total - energyPrefix_[static_cast<size_t>(lag)];
      const float denominator = std::sqrt(head * tail) * scale * windowAutocorrelation_[static_cast<size_t>(lag)];
      correlation_[static_cast<size_t>(lag)] = denominator > 0.0f ? time[lag] / denominator : 0.0f;
    }
  } else {
    for (int lag = 1; lag <= maxLag_ + 1; ++lag) {
      correlation_[static_cast<size_t>(lag)] = time[lag] / (energy * windowAutocorrelation_[static_cast<size_t>(lag)]);
    }
  }
}

// Each peak of the normalised autocorrelation between the lags of maxF0Hz and minF0Hz, refined by a parabola,
// as a voiced candidate (the strongest maxCandidates of them kept).
void OnlinePitchTracker::addPeakCandidates(AnalysedFrame& frame) const {
  auto r = [&](int lag) { return correlation_[static_cast<size_t>(lag)]; };
  float previous = r(minLag_ - 1);
  float current = r(minLag_);
  for (int lag = minLag_; lag <= maxLag_; ++lag) {
    const float next = r(lag + 1);
    if (current > 0.0f && current >= previous && current > next) {
      // Parabolic refinement of the peak's lag and height.
      const double curvature = previous - 2.0 * current + next;
      double offset = curvature < 0.0 ? 0.5 * (previous - next) / curvature : 0.0;
      offset = std::clamp(offset, -0.5, 0.5);
      double height = current - 0.25 * (previous - next) * offset;
      if (height > 1.0) height = 1.0 / height;  // as Praat: interpolation overshoot counts against it
      const double period = lag + offset;
      const double f0 = sampleRateHz_ / period;
      if (f0 >= options_.minF0Hz && f0 <= options_.maxF0Hz) {
        const double periodicity = shortWindowLength_ > 0 ? (1.0 - options_.shortWeight) * height +
                                                                options_.shortWeight * shortCorrelation(period)
                                                          : height;
        double strength = periodicity - options_.octaveCost * std::log2(options_.minF0Hz / f0);
        // A signal periodic in P is periodic in 2P too: if half this period correlates nearly as well,
        // this candidate is most likely a sub-octave, so it pays a penalty.
        const int halfLag = static_cast<int>(std::lround(period / 2.0));
        if (options_.subharmonicPenalty > 0.0 && halfLag - 1 >= 1) {
          float halfBest = 0.0f;
          for (int h = halfLag - 1; h <= halfLag + 1; ++h) halfBest = std::max(halfBest, r(h));
          if (halfBest >= options_.subharmonicRatio * height) strength -= options_.subharmonicPenalty;
        }
        Candidate candidate{static_cast<float>(f0), static_cast<float>(height), strength};
        frame.bestCorrelation = std::max(frame.bestCorrelation, candidate.correlation);
        if (static_cast<int>(frame.candidates.size()) <= options_.maxCandidates) {
          frame.candidates.push_back(candidate);
        } else {
          // Replace the weakest voiced candidate if this one is stronger.
          auto weakest =
              std::min_element(frame.candidates.begin() + 1, frame.candidates.end(),
                               [](const Candidate& a, const Candidate& b) { return a.strength < b.strength; });
          if (weakest->strength < strength) *weakest = candidate;
        }
      }
    }
    previous = current;
    current = next;
  }
}

// Normalised cross-correlation between the two halves of a lag-spanning pair of short windows centred on the
// frame: x[c + n - lag/2] against x[c + n + lag/2]. Best of the three integer lags around `lag`.
double OnlinePitchTracker::shortCorrelation(double lag) const {
  const int centre = windowLength_ / 2;
  const int half = shortWindowLength_ / 2;
  double best = 0.0;
  const int rounded = static_cast<int>(std::lround(lag));
  for (int candidateLag = std::max(1, rounded - 1); candidateLag <= rounded + 1; ++candidateLag) {
    const int first = centre - half - candidateLag / 2;
    // Eigen's dot products are vectorised.
    const Eigen::Map<const Eigen::VectorXf> a(segment_.data() + first, shortWindowLength_);
    const Eigen::Map<const Eigen::VectorXf> b(segment_.data() + first + candidateLag, shortWindowLength_);
    const double cross = a.dot(b);
    const double energyA = a.squaredNorm();
    const double energyB = b.squaredNorm();
    if (energyA > 0.0 && energyB > 0.0) best = std::max(best, cross / std::sqrt(energyA * energyB));
  }
  return best;
}

void OnlinePitchTracker::viterbiStep(AnalysedFrame& current, const AnalysedFrame* previous) const {
  const size_t count = current.candidates.size();
  current.score.assign(count, 0.0);
  current.back.assign(count, 0);
  const double vuCost = options_.voicedUnvoicedCost * transitionScale_;
  const double jumpCost = options_.octaveJumpCost * transitionScale_;
  for (size_t j = 0; j < count; ++j) {
    const Candidate& to = current.candidates[j];
    if (!previous) {
      current.score[j] = to.strength;
      continue;
    }
    double best = -std::numeric_limits<double>::infinity();
    int bestFrom = 0;
    for (size_t i = 0; i < previous->candidates.size(); ++i) {
      const Candidate& from = previous->candidates[i];
      const bool fromVoiced = from.f0Hz > 0.0f;
      const bool toVoiced = to.f0Hz > 0.0f;
      double cost = 0.0;
      if (fromVoiced != toVoiced) {
        cost = vuCost;
      } else if (fromVoiced) {
        cost = jumpCost * std::abs(std::log2(static_cast<double>(to.f0Hz) / from.f0Hz));
      }
      const double value = previous->score[i] - cost;
      if (value > best) {
        best = value;
        bestFrom = static_cast<int>(i);
      }
    }
    current.score[j] = best + to.strength;
    current.back[j] = bestFrom;
  }
  // Keep scores bounded over long streams; only differences matter.
  const double top = *std::max_element(current.score.begin(), current.score.end());
  for (double& s : current.score) s -= top;
}

void OnlinePitchTracker::decideUpTo(long long lastFrameToDecide, long long tracebackFrom) {
  const AnalysedFrame& end = analysed(tracebackFrom);
  int state = static_cast<int>(std::max_element(end.score.begin(), end.score.end()) - end.score.begin());
  // Walk back to the oldest undecided frame, remembering the states on the way.
  const long long firstUndecided = static_cast<long long>(decided_.size());
  std::vector<int> path(static_cast<size_t>(tracebackFrom - firstUndecided + 1));
  for (long long t = tracebackFrom; t >= firstUndecided; --t) {
    path[static_cast<size_t>(t - firstUndecided)] = state;
    if (t > 0) state = analysed(t).back[static_cast<size_t>(state)];
  }
  for (long long t = firstUndecided; t <= lastFrameToDecide; ++t) {
    const AnalysedFrame& frame = analysed(t);
    const Candidate& chosen = frame.candidates[static_cast<size_t>(path[static_cast<size_t>(t - firstUndecided)])];
    decided_.push_back({chosen.f0Hz, frame.bestCorrelation});
  }
}

std::vector<PitchFrame> trackPitch(std::span<const float> samples, int sampleRateHz, const PitchOptions& options) {
  OnlinePitchTracker tracker(options, sampleRateHz);
  tracker.acceptWaveform(samples);
  tracker.inputFinished();
  std::vector<PitchFrame> frames;
  frames.reserve(static_cast<size_t>(tracker.numFramesReady()));
  for (int t = 0; t < tracker.numFramesReady(); ++t) frames.push_back(tracker.frame(t));
  return frames;
}

}  // namespace th::features
