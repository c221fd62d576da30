// The articulated mouth: the mouth model's jaw and lips (mouth_model.h, the audio-visual inversion) told which
// sound each frame makes by the mouth network (mouth_network.h), so that the face, the visemes, Rhubarb's cues
// and the ARKit weights tell one story: a frame shown as PP has the lips meeting on the face, one shown as FF
// has the lower lip up at the teeth.
//
//   const th::animation::MouthNetworkOutput heard = th::animation::runMouthNetwork(network, subframes, &mean);
//   th::face::VisemeTrack visemes = th::animation::networkVisemes(network, heard.classes, {});
//   th::animation::blendPhoneMouth(network, visemes.posteriors, fapNumbers, faps, {});  // faps: the mouth model's
//   th::animation::articulateLips(network, visemes.classes, fapNumbers, faps, {});
//
// Why the two models: measured on speakers neither heard (docs/mouth.md), the network tells the sounds apart
// better (the mouth classes, /p b m/, rounding), the inversion follows the jaw's opening and the mouth's width
// better. Each does what it does best.
// - Visemes: the network's class posteriors over their training shares are scaled likelihoods (a hybrid
//   network/HMM decoder, as in speech recognition) decoded by the class HMM the network's training labels make
//   (viseme_model.h classHmm: each class held at least minHoldFrames, runs and bigrams as in the labels).
// - Closures: on a frame shown as PP, the lips are brought together: the inner lips' opening, linear in the FAPs
//   (MouthNetwork::openingGradient, measured on the face), is closed by the lips (the lower lip lowerLipShare of
//   it), and by raising the jaw if jawShare > 0 (never past rest). By default the jaw stays the mouth model's: a
//   jaw held shut for the class's hold after a /b p/ onset opened later (bench/latency_bench, docs/mouth.md). FF closes ffShare of the opening
//   with the lower lip alone.
// - Rounding and spreading: on a frame shown as oh or ou the mouth's corners (FAPs 6, 7, 53, 54) are drawn in
//   at least as far as the class's typical shape in the tracked training frames (MouthNetwork::classShapes,
//   about the training mean); on E and ih they are spread at least as far. Elsewhere the FAPs are the
//   inversion's.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "animation/mouth_network.h"
#include "face/visemes.h"

namespace th::animation {

struct ArticulationOptions {
  // The network's log posteriors over its class priors count this much as evidence (its 34 subframes of
  // context overlap from frame to frame, so each frame's evidence would otherwise be counted several times).
  double evidenceScale = 0.75;
  int minHoldFrames = 2;       // a class once shown stays this many frames (67 ms: a /p/'s closure is 50-100 ms)
  double jawShare = 0.0;       // of a closure, how much the jaw makes (the lips the rest; 0: the jaw untouched)
  double lowerLipShare = 0.6;  // of the lips' part, how much the lower lip makes
  double ffShare = 0.7;        // of the opening, how much the lower lip closes for F and V
  double shapeShare = 1.0;     // how far the corners go to a rounded or spread class's typical shape
  // How much of the jaw (FAP 3) and of the lips (the other FAPs) the heard sounds make (blendPhoneMouth): 0 keeps
  // the mouth model's, 1 takes the classes' shapes alone. Chosen on speakers neither model heard (docs/mouth.md).
  double phoneJawShare = 0.0;
  double phoneLipShare = 0.0;
  void check() const;  // throws th::Error naming the bad option
};

// classes: the network's P(class) (17 x T, MouthNetworkOutput::classes).
face::VisemeTrack networkVisemes(const MouthNetwork& model, const Eigen::MatrixXd& classes,
                                 const ArticulationOptions& options);

// The mouth the heard sounds make, blended into faps: each frame the classes' typical tracked shapes
// (MouthNetwork::classShapes, about the training FAPs' mean) weighted by the classes' probabilities — which
// overlap from frame to frame as a sound's dominance spreads over its neighbours in Cohen & Massaro's
// coarticulation — and mixed with faps as (1 - share) faps + share shapes, the jaw's share phoneJawShare and the
// lips' phoneLipShare. probabilities: 17 x T (a
// decoded track's posteriors, face::VisemeTrack); one column per column of faps (fewer leave the rest). Rows of
// faps are fapNumbers; FAPs the model has no shape for are left; the jaw (FAP 3) stays >= 0. Throws th::Error if
// the model has no class shapes.
void blendPhoneMouth(const MouthNetwork& model, const Eigen::MatrixXd& probabilities,
                     const std::vector<int>& fapNumbers, Eigen::MatrixXd& faps, const ArticulationOptions& options);

// The FAPs' inner-lip opening relative to rest (> 0: apart), by the model's opening gradient, for each frame.
// faps: rows are fapNumbers (FAPs the gradient does not know count 0). Throws th::Error if the model has no
// opening gradient.
Eigen::RowVectorXd lipOpeningOf(const MouthNetwork& model, const std::vector<int>& fapNumbers,
                                const Eigen::MatrixXd& faps);

// Closes the lips on the frames shown as PP, raises the lower lip on FF, rounds oh and ou and spreads E and
// ih (shown: one class per column of faps; a shorter list leaves the rest). Throws th::Error if the model has no
// opening gradient or faps has no jaw or lip FAP the gradient moves.
void articulateLips(const MouthNetwork& model, const std::vector<int>& shown, const std::vector<int>& fapNumbers,
                    Eigen::MatrixXd& faps, const ArticulationOptions& options);

}  // namespace th::animation
