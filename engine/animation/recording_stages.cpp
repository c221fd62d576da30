#include "animation/recording_stages.h"

namespace th::animation {
namespace {

SpeechFrames speechFramesOf(const std::vector<SpeechFrame>& frames) {
  SpeechFrames speech;
  const Eigen::Index count = static_cast<Eigen::Index>(frames.size());
  speech.mfcc.resize(frames.empty() ? 0 : frames.front().mfcc.size(), count);
  speech.levelDb.resize(count);
  for (Eigen::Index t = 0; t < count; ++t) {
    speech.mfcc.col(t) = frames[static_cast<std::size_t>(t)].mfcc;
    speech.levelDb[t] = frames[static_cast<std::size_t>(t)].levelDb;
  }
  return speech;
}

std::vector<VisemeFrame> visemeFramesOf(const face::VisemeTrack& track) {
  std::vector<VisemeFrame> frames(track.classes.size());
  for (std::size_t t = 0; t < frames.size(); ++t) {
    frames[t].probabilities = track.posteriors.col(static_cast<Eigen::Index>(t));
    frames[t].mouthClass = track.classes[t];
  }
  return frames;
}

}  // namespace

std::unique_ptr<HeadSource> makeHeadStage(const HeadModel& model, const HeadSynthesisOptions& options) {
  if (options.maxLagFrames >= 0) return std::make_unique<HeadStage>(model, options);
  return std::make_unique<WholeInputStage<ProsodyFrame, HeadFrame>>(
      "head", [&model, options](const std::vector<ProsodyFrame>& input) {
        Eigen::MatrixXd prosody(4, static_cast<Eigen::Index>(input.size()));
        Eigen::RowVectorXd voiced(prosody.cols());
        for (Eigen::Index t = 0; t < prosody.cols(); ++t) {
          prosody.col(t) = input[static_cast<std::size_t>(t)].prosody;
          voiced[t] = input[static_cast<std::size_t>(t)].voiced ? 1.0 : 0.0;
        }
        const Eigen::MatrixXd rotations = synthesiseHead(model, prosody, voiced, options);
        std::vector<HeadFrame> frames(static_cast<std::size_t>(rotations.cols()));
        for (std::size_t t = 0; t < frames.size(); ++t)
          frames[t].rotationDegrees = rotations.col(static_cast<Eigen::Index>(t));
        return frames;
      });
}

std::unique_ptr<MouthSource> makeMouthStage(const MouthModel& model, const MouthSynthesisOptions& options) {
  if (options.windowFrames >= 1) return std::make_unique<MouthStage>(model, options);
  return std::make_unique<WholeInputStage<SpeechFrame, MouthFrame>>(
      "mouth", [&model, options](const std::vector<SpeechFrame>& input) {
        const Eigen::MatrixXd components = synthesiseMouth(model, speechFramesOf(input), options);
        std::vector<MouthFrame> frames(static_cast<std::size_t>(components.cols()));
        for (std::size_t t = 0; t < frames.size(); ++t)
          frames[t].components = components.col(static_cast<Eigen::Index>(t));
        return frames;
      });
}

std::unique_ptr<SpeechVisemeSource> makeVisemeStage(const VisemeModel& model, int lagFrames) {
  if (lagFrames >= 0) return std::make_unique<VisemeStage>(model, lagFrames);
  return std::make_unique<WholeInputStage<SpeechFrame, VisemeFrame>>(
      "visemes", [&model](const std::vector<SpeechFrame>& input) {
        return visemeFramesOf(decodeVisemes(model, speechFramesOf(input)));
      });
}

std::unique_ptr<MouthNetworkSource> makeMouthNetworkStage(const MouthNetwork& model, bool ownMean) {
  if (!ownMean) return std::make_unique<MouthNetworkStage>(model);
  return std::make_unique<WholeInputStage<SpeechFrame, MouthNetworkFrame>>(
      "mouth network",
      [&model](const std::vector<SpeechFrame>& input) {
        const SpeechFrames subframes = speechFramesOf(input);
        const Eigen::VectorXd mean = subframes.mfcc.rowwise().mean();
        const MouthNetworkOutput heard = runMouthNetwork(model, subframes, &mean);
        std::vector<MouthNetworkFrame> frames(static_cast<std::size_t>(heard.numFrames()));
        for (std::size_t t = 0; t < frames.size(); ++t) {
          frames[t].classes = heard.classes.col(static_cast<Eigen::Index>(t));
          frames[t].shut = heard.shut[static_cast<Eigen::Index>(t)];
        }
        return frames;
      },
      kSubframesPerFrame);
}

std::unique_ptr<ArticulationVisemeSource> makeArticulationVisemeStage(const MouthNetwork& model,
                                                                      const ArticulationOptions& options,
                                                                      int lagFrames) {
  if (lagFrames >= 0) return std::make_unique<ArticulationVisemeStage>(model, options, lagFrames);
  options.check();
  return std::make_unique<WholeInputStage<MouthNetworkFrame, VisemeFrame>>(
      "articulation visemes", [&model, options](const std::vector<MouthNetworkFrame>& input) {
        Eigen::MatrixXd classes(input.empty() ? 0 : input.front().classes.size(),
                                static_cast<Eigen::Index>(input.size()));
        for (Eigen::Index t = 0; t < classes.cols(); ++t) classes.col(t) = input[static_cast<std::size_t>(t)].classes;
        return visemeFramesOf(networkVisemes(model, classes, options));
      });
}

}  // namespace th::animation
