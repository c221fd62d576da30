// LiveDecoder: the live pipeline's decoding, a stream in, FAP frames out, held to the batch animate().
#include "pipeline/live_decoder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "audio/media_audio.h"
#include "core/data_path.h"
#include "core/error.h"
#include "pipeline/offline.h"

namespace {

using th::pipeline::AnimationFrame;
using th::pipeline::LiveDecoder;
using th::pipeline::LiveDecoderOptions;

struct Models {
  th::animation::HeadModel head =
      th::animation::loadHeadModel(std::string(TALKINGHEAD_SOURCE_DIR) + "/models/head.json");
  th::animation::MouthModel mouth =
      th::animation::loadMouthModel(std::string(TALKINGHEAD_SOURCE_DIR) + "/models/mouth.json");
  th::animation::MouthNetwork articulation =
      th::animation::loadMouthNetwork(std::string(TALKINGHEAD_SOURCE_DIR) + "/models/articulation_live.json");
};

const Models& models() {
  static const Models loaded;
  return loaded;
}

std::vector<float> speech(double seconds) {
  const auto clip = th::audio::readRecording(th::sharedDataPath("beat2/audio_only/2_scott_0_4_4.wav"));
  return {clip.samples.begin(), clip.samples.begin() + static_cast<long>(seconds * clip.sampleRateHz)};
}

// Feeds `samples` in chunks of 1..largestChunk samples (seeded), taking the frames as they come, then ends the
// input; checks on the way that frames come out no later than the look-ahead says (one frame of rounding).
std::vector<AnimationFrame> decodeInRandomChunks(LiveDecoder& decoder, const std::vector<float>& samples,
                                                 std::size_t largestChunk, unsigned seed) {
  const th::pipeline::DecoderLookahead lookahead = decoder.lookahead();
  std::mt19937 random(seed);
  std::uniform_int_distribution<std::size_t> chunkSize(1, largestChunk);
  std::vector<AnimationFrame> frames;
  AnimationFrame frame;
  for (std::size_t at = 0; at < samples.size();) {
    const std::size_t n = std::min(chunkSize(random), samples.size() - at);
    decoder.acceptWaveform(std::span<const float>(samples).subspan(at, n));
    at += n;
    while (decoder.next(frame)) frames.push_back(frame);
    const double heard = static_cast<double>(at) / 16000.0;
    const double due = (heard - lookahead.totalMs / 1000.0) * 30.0 - 1.0;
    EXPECT_GE(static_cast<double>(frames.size()), due) << "after " << heard << " s";
  }
  decoder.inputFinished();
  while (decoder.next(frame)) frames.push_back(frame);
  return frames;
}

TEST(LiveDecoder, GivesTheBatchAnimationFrameByFrameWhateverTheChunks) {
  const std::vector<float> samples = speech(12.0);
  for (const bool mmse : {false, true}) {
    LiveDecoderOptions options;
    options.waitForHead = true;
    if (mmse) options.mouth.method = th::animation::MouthMethod::kMmse;
    options.mouth.windowFrames = mmse ? 1 : 2;
    const th::face::FapTrack batch =
        th::pipeline::animate(samples, &models().head, &models().mouth,
                              {.head = options.head, .mouth = options.mouth, .idle = false, .idleOptions = {}});
    LiveDecoder decoder(&models().head, &models().mouth, options);
    const th::pipeline::DecoderLookahead lookahead = decoder.lookahead();
    EXPECT_EQ(decoder.fapNumbers(), batch.faps);
    EXPECT_EQ(lookahead.headFrames, th::animation::kLiveHeadLagFrames + 3);
    EXPECT_EQ(lookahead.mouthFrames, models().mouth.contextFrames + options.mouth.windowFrames - 1);
    EXPECT_EQ(lookahead.headDelayFrames, 0);
    EXPECT_DOUBLE_EQ(lookahead.totalMs, lookahead.headMs);
    const std::vector<AnimationFrame> frames = decodeInRandomChunks(decoder, samples, 3000, 5);
    ASSERT_EQ(static_cast<Eigen::Index>(frames.size()), batch.numFrames());
    double largest = 0.0;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      EXPECT_EQ(frames[f].index, static_cast<int>(f));
      EXPECT_DOUBLE_EQ(frames[f].timeSeconds, static_cast<double>(f) / 30.0);
      for (std::size_t c = 0; c < batch.faps.size(); ++c) {
        const double expected = batch.values(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(f));
        largest = std::max(largest, std::abs(frames[f].faps[static_cast<std::size_t>(batch.faps[c])] - expected));
      }
    }
    EXPECT_LT(largest, 1e-9) << (mmse ? "MMSE" : "inversion");
    // The frames carry what the plots show.
    double voiced = 0.0;
    for (const AnimationFrame& f : frames) voiced += f.f0Hz > 0.0 ? 1.0 : 0.0;
    EXPECT_GT(voiced / static_cast<double>(frames.size()), 0.3);
  }
}

// With the articulation, each frame waits for its own class; the visemes and the lips are animate()'s streaming
// form's, frame for frame, and every frame shown as PP has the lips meeting.
TEST(LiveDecoder, ArticulatesAsTheStreamingAnimationAndClosesTheLipsOnEveryPp) {
  const std::vector<float> samples = speech(12.0);
  const th::animation::MouthNetwork& articulation = models().articulation;
  LiveDecoderOptions options;
  options.waitForHead = true;
  options.mouth.windowFrames = 1;
  th::pipeline::AnimateOptions batchOptions{.head = options.head, .mouth = options.mouth, .idle = false};
  batchOptions.articulationLagFrames = options.articulationLagFrames;
  const th::face::FapTrack batch =
      th::pipeline::animate(samples, &models().head, &models().mouth, batchOptions, nullptr, &articulation);
  LiveDecoder decoder(&models().head, &models().mouth, options, nullptr, &articulation);
  const th::pipeline::DecoderLookahead lookahead = decoder.lookahead();
  EXPECT_NEAR(lookahead.articulationMs, 12.5 + 1000.0 * articulation.futureSubframes / 90.0, 1e-9);
  EXPECT_GE(lookahead.mouthMs, lookahead.articulationMs);
  const std::vector<AnimationFrame> frames = decodeInRandomChunks(decoder, samples, 2000, 3);
  ASSERT_EQ(static_cast<Eigen::Index>(frames.size()), batch.numFrames());
  ASSERT_EQ(batch.visemes.numFrames(), batch.numFrames());
  double largest = 0.0;
  int shut = 0, pp = 0;
  Eigen::MatrixXd mouth(static_cast<Eigen::Index>(batch.faps.size()), 1);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(frames[f].visemeIndex, static_cast<int>(f)) << "a frame carries its own class";
    EXPECT_EQ(frames[f].mouthClass, batch.visemes.classes[f]) << f;
    for (int c = 0; c < th::face::kNumMouthClasses; ++c)
      EXPECT_NEAR(frames[f].visemeProbabilities[static_cast<std::size_t>(c)],
                  batch.visemes.posteriors(c, static_cast<Eigen::Index>(f)), 1e-4);
    for (std::size_t c = 0; c < batch.faps.size(); ++c) {
      mouth(static_cast<Eigen::Index>(c), 0) = frames[f].faps[static_cast<std::size_t>(batch.faps[c])];
      largest = std::max(largest, std::abs(mouth(static_cast<Eigen::Index>(c), 0) -
                                           batch.values(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(f))));
    }
    if (frames[f].mouthClass == th::face::kPp) {
      ++pp;
      shut += th::animation::lipOpeningOf(articulation, batch.faps, mouth)[0] < 1e-9 ? 1 : 0;
    }
  }
  EXPECT_LT(largest, 1e-9);
  EXPECT_GT(pp, 5) << "BEAT2's speech has closures";
  EXPECT_EQ(shut, pp);
}

// By default the mouth sets the pace: frame i has the batch mouth of frame i and the batch head of frame
// i - headDelayFrames, and frames come out as soon as the mouth's look-ahead allows.
TEST(LiveDecoder, ShowsTheMouthAtOnceAndTheHeadLate) {
  const std::vector<float> samples = speech(12.0);
  const LiveDecoderOptions options;
  ASSERT_FALSE(options.waitForHead);
  const th::face::FapTrack batch =
      th::pipeline::animate(samples, &models().head, &models().mouth,
                            {.head = options.head, .mouth = options.mouth, .idle = false, .idleOptions = {}});
  LiveDecoder decoder(&models().head, &models().mouth, options);
  const th::pipeline::DecoderLookahead lookahead = decoder.lookahead();
  EXPECT_LT(lookahead.mouthFeaturesMs, 20.0) << "the mouth's MFCCs wait for neither the pitch tracker nor deltas";
  EXPECT_LT(lookahead.totalMs, 120.0);
  // The head waits for the pitch tracker's decisions (about 100 ms) and its own lag and trajectory (5 frames).
  EXPECT_GT(lookahead.headMs - lookahead.totalMs, 150.0);
  const int delay = lookahead.headDelayFrames;
  EXPECT_GE(delay, 5);
  // The head's own decisions are due by the time its delayed frame is shown.
  EXPECT_LE(lookahead.headMs - delay * 1000.0 / 30.0, lookahead.totalMs + 1e-9);

  const std::vector<AnimationFrame> frames = decodeInRandomChunks(decoder, samples, 800, 11);
  ASSERT_EQ(static_cast<Eigen::Index>(frames.size()), batch.numFrames());

  const auto column = [&](int fap) {
    return static_cast<Eigen::Index>(std::find(batch.faps.begin(), batch.faps.end(), fap) - batch.faps.begin());
  };
  double mouthError = 0.0;
  double headError = 0.0;
  double headMoved = 0.0;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const auto i = static_cast<Eigen::Index>(f);
    EXPECT_EQ(frames[f].prosodyIndex, static_cast<int>(f) - delay);
    for (int fap : batch.faps) {
      const double value = frames[f].faps[static_cast<std::size_t>(fap)];
      if (fap >= 48 && fap <= 50) {
        const double expected = i >= delay ? batch.values(column(fap), i - delay) : 0.0;
        headError = std::max(headError, std::abs(value - expected));
        headMoved = std::max(headMoved, std::abs(value));
      } else {
        mouthError = std::max(mouthError, std::abs(value - batch.values(column(fap), i)));
      }
    }
  }
  EXPECT_LT(mouthError, 1e-9);
  EXPECT_LT(headError, 1e-9);
  EXPECT_GT(headMoved, 1.0) << "the head moves";
  // The frames carry both models' state posteriors (forward filters), each a distribution that moves.
  std::set<int> headLikeliest;
  std::set<int> mouthLikeliest;
  for (const AnimationFrame& f : frames) {
    ASSERT_EQ(f.headStates, models().head.hmm.numStates());
    ASSERT_EQ(f.mouthStates, models().mouth.hmm.numStates());
    double headSum = 0.0;
    double mouthSum = 0.0;
    for (int k = 0; k < f.headStates; ++k) headSum += f.headPosterior[static_cast<std::size_t>(k)];
    for (int k = 0; k < f.mouthStates; ++k) mouthSum += f.mouthPosterior[static_cast<std::size_t>(k)];
    EXPECT_NEAR(headSum, f.prosodyIndex >= 0 ? 1.0 : 0.0, 1e-4) << "no head before the head's delay";
    EXPECT_NEAR(mouthSum, 1.0, 1e-4);
    headLikeliest.insert(static_cast<int>(
        std::max_element(f.headPosterior.begin(), f.headPosterior.begin() + f.headStates) - f.headPosterior.begin()));
    mouthLikeliest.insert(
        static_cast<int>(std::max_element(f.mouthPosterior.begin(), f.mouthPosterior.begin() + f.mouthStates) -
                         f.mouthPosterior.begin()));
  }
  EXPECT_GT(headLikeliest.size(), 3U);
  EXPECT_GT(mouthLikeliest.size(), 2U);
}

// An endless stream in bounded memory: three minutes of speech (the same 12 s over and over), and what the
// decoder holds after one minute and after three is the same small number of frames (the articulation's
// subframes included).
TEST(LiveDecoder, HoldsOnlyTheRecentFramesOnALongStream) {
  const std::vector<float> samples = speech(12.0);
  LiveDecoder decoder(&models().head, &models().mouth, {}, nullptr, &models().articulation);
  AnimationFrame frame;
  int frames = 0;
  std::size_t heldAfterAMinute = 0;
  for (int pass = 0; pass < 15; ++pass) {
    for (std::size_t at = 0; at < samples.size(); at += 1600) {
      decoder.acceptWaveform(
          std::span<const float>(samples).subspan(at, std::min<std::size_t>(1600, samples.size() - at)));
      while (decoder.next(frame)) ++frames;
    }
    if (pass == 4) heldAfterAMinute = decoder.framesHeld();
  }
  EXPECT_GT(frames, 15 * 360 - 20);
  EXPECT_LT(heldAfterAMinute, 400U);
  EXPECT_LE(decoder.framesHeld(), heldAfterAMinute + 10) << "no growth with the stream's length";
  EXPECT_GT(decoder.framesHeld(), 0U);
}

TEST(LiveDecoder, RefusesWhatCannotStream) {
  LiveDecoderOptions batchHead;
  batchHead.head.maxLagFrames = -1;
  EXPECT_THROW(LiveDecoder(&models().head, nullptr, batchHead), th::Error);
  LiveDecoderOptions batchMouth;
  batchMouth.mouth.windowFrames = 0;
  EXPECT_THROW(LiveDecoder(nullptr, &models().mouth, batchMouth), th::Error);
  EXPECT_THROW(LiveDecoder(nullptr, nullptr, {}), th::Error);
  th::animation::MouthModel sweep = models().mouth;
  sweep.fapMap.reset();
  sweep.visualFaps.clear();
  EXPECT_THROW(LiveDecoder(nullptr, &sweep, {}), th::Error);
  // One model alone: its FAPs only.
  LiveDecoder headOnly(&models().head, nullptr, {});
  const std::vector<float> samples = speech(2.0);
  headOnly.acceptWaveform(samples);
  headOnly.inputFinished();
  AnimationFrame frame;
  int count = 0;
  while (headOnly.next(frame)) {
    EXPECT_EQ(frame.faps[3], 0.0);
    ++count;
  }
  EXPECT_NEAR(count, 60, 1);
}

}  // namespace
