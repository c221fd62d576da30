#include "animation/online_stages.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace th::animation {
namespace {

template <typename T>
void readHeld(const FrameStore<T>& store, int frame, T& out, const char* stage) {
  if (frame < 0 || static_cast<std::size_t>(frame) < store.firstKept() ||
      static_cast<std::size_t>(frame) >= store.size())
    throw Error(std::string(stage) + ": frame " + std::to_string(frame) + " is not held");
  out = store[static_cast<std::size_t>(frame)];
}

const ArticulationOptions& checked(const ArticulationOptions& options) {
  options.check();
  return options;
}

// Frames not yet ready are never forgotten.
std::size_t forgettable(int frame, int ready) {
  return static_cast<std::size_t>(std::clamp(frame, 0, ready));
}

}  // namespace

HeadStage::HeadStage(const HeadModel& model, const HeadSynthesisOptions& options) : synthesiser_(model, options) {
  if (options.maxLagFrames < 0) throw Error("head stage: batch decoding (maxLagFrames < 0) does not stream");
}

void HeadStage::accept(const ProsodyFrame& frame) {
  synthesiser_.acceptProsody(frame.prosody, frame.voiced);
  posteriors_.push_back(synthesiser_.filteredPosterior());
}

void HeadStage::inputFinished() {
  synthesiser_.finish();
}

int HeadStage::numFramesReady() const {
  return synthesiser_.numReady();
}

void HeadStage::getFrame(int frame, HeadFrame& out) const {
  out.rotationDegrees = synthesiser_.rotation(frame);  // throws for a frame not held
  out.filteredPosterior = posteriors_[static_cast<std::size_t>(frame)];
}

void HeadStage::forgetBefore(int frame) {
  const std::size_t before = forgettable(frame, numFramesReady());
  synthesiser_.forgetBefore(static_cast<int>(before));
  posteriors_.forgetBefore(before);
}

int HeadStage::latencyFrames() const {
  return synthesiser_.lookaheadFrames();
}

std::size_t HeadStage::framesHeld() const {
  return synthesiser_.framesHeld() + posteriors_.held();
}

int HeadStage::numStates() const {
  return synthesiser_.numStates();
}

MouthStage::MouthStage(const MouthModel& model, const MouthSynthesisOptions& options) : synthesiser_(model, options) {}

void MouthStage::accept(const SpeechFrame& frame) {
  synthesiser_.acceptFrame(frame.levelDb, frame.mfcc);
  take();
}

void MouthStage::inputFinished() {
  synthesiser_.finish();
  take();
}

void MouthStage::take() {
  MouthFrame frame;
  while (synthesiser_.next(frame.components)) {
    frame.posterior = synthesiser_.posterior();  // of the frame next() gave
    ready_.push_back(frame);
  }
}

void MouthStage::getFrame(int frame, MouthFrame& out) const {
  readHeld(ready_, frame, out, "mouth stage");
}

void MouthStage::forgetBefore(int frame) {
  ready_.forgetBefore(forgettable(frame, numFramesReady()));
}

VisemeStage::VisemeStage(const VisemeModel& model, int lagFrames) : stream_(model, lagFrames) {}

void VisemeStage::accept(const SpeechFrame& frame) {
  if (finished_) throw Error("viseme stage: a speech frame after the end of the input");
  stream_.accept(frame.levelDb, frame.mfcc);
  take();
}

void VisemeStage::inputFinished() {
  if (finished_) return;
  finished_ = true;
  stream_.finish();
  take();
}

// The stream decides the class shown in order (a class keeps its hold), so its frames are taken as they come.
void VisemeStage::take() {
  VisemeFrame frame;
  while (stream_.next(frame)) ready_.push_back(frame);
}

void VisemeStage::getFrame(int frame, VisemeFrame& out) const {
  readHeld(ready_, frame, out, "viseme stage");
}

void VisemeStage::forgetBefore(int frame) {
  ready_.forgetBefore(forgettable(frame, numFramesReady()));
}

MouthNetworkStage::MouthNetworkStage(const MouthNetwork& model) : model_(model), stream_(model) {}

void MouthNetworkStage::accept(const SpeechFrame& subframe) {
  stream_.accept(subframe.levelDb, subframe.mfcc);
  take();
}

void MouthNetworkStage::inputFinished() {
  stream_.finish();
  take();
}

void MouthNetworkStage::take() {
  MouthNetworkFrame frame;
  while (stream_.next(frame)) ready_.push_back(frame);
}

void MouthNetworkStage::getFrame(int frame, MouthNetworkFrame& out) const {
  readHeld(ready_, frame, out, "mouth network stage");
}

void MouthNetworkStage::forgetBefore(int frame) {
  ready_.forgetBefore(forgettable(frame, numFramesReady()));
}

std::size_t MouthNetworkStage::framesHeld() const {
  return ready_.held() + stream_.subframesHeld() / kSubframesPerFrame;
}

ArticulationVisemeStage::ArticulationVisemeStage(const MouthNetwork& model, const ArticulationOptions& options,
                                                 int lagFrames)
    : evidenceScale_(options.evidenceScale),
      classes_(classHmm(model.sequence, checked(options).minHoldFrames)),
      logPriors_(model.classPriors.array().max(1e-12).log().matrix()) {
  if (lagFrames < 0) throw Error("articulation visemes: the lag must be >= 0 frames");
  stream_ = std::make_unique<VisemeStream>(classes_, options.minHoldFrames, lagFrames);
}

void ArticulationVisemeStage::accept(const MouthNetworkFrame& frame) {
  if (finished_) throw Error("articulation visemes: a frame after the end of the input");
  // The hybrid decoder's scaled likelihoods: P(class | speech) / P(class), counted evidenceScale times.
  stream_->acceptEvidence(evidenceScale_ * (frame.classes.array().max(1e-12).log().matrix() - logPriors_));
  take();
}

void ArticulationVisemeStage::inputFinished() {
  if (finished_) return;
  finished_ = true;
  stream_->finish();
  take();
}

void ArticulationVisemeStage::take() {
  VisemeFrame frame;
  while (stream_->next(frame)) ready_.push_back(frame);
}

void ArticulationVisemeStage::getFrame(int frame, VisemeFrame& out) const {
  readHeld(ready_, frame, out, "articulation visemes");
}

void ArticulationVisemeStage::forgetBefore(int frame) {
  ready_.forgetBefore(forgettable(frame, numFramesReady()));
}

}  // namespace th::animation
