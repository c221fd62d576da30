// Visemes: what the mouth shows of a speech sound, in the sets other programs animate with, and the mouth classes
// the viseme model tells apart (animation/viseme_model.h), from which every set is made.
//
//   const int c = th::face::mouthClassOfPhone("AH0");                 // kAh; -1 for a label that is no phone
//   th::face::oculusVisemeOf(c);                                      // 10, "aa"
//   th::face::rhubarbShapeOf(c);                                      // 'C'
//   Eigen::VectorXd oculus = th::face::oculusWeights(track.posteriors.col(t));   // 15 weights, sum 1
//
// The mouth classes are the Oculus/OpenXR 15 visemes with two split so that Rhubarb's shapes are a function of
// them too: "nn" into N (nn) and L (Rhubarb's H), and "aa" into the open AA/AW/AY (aa, Rhubarb's
// D) and the mid AE/AH (ah, Rhubarb's C). ARPAbet phones map to them as docs/visemes.md tabulates (after the
// Oculus viseme reference and Rhubarb's shape descriptions); HH, whose mouth is the next vowel's, is kk.
// VRM's five vowels are weights made from the classes (vrmWeights): a vowel class is its vowel, a consonant
// leans to the vowel its lips resemble (SS and CH spread or round, RR rounds).
// Thread contract: pure functions and constants.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string_view>
#include <vector>

namespace th::face {

enum MouthClass : int {
  kSilence,
  kPp,  // B M P
  kFf,  // F V
  kTh,  // TH DH
  kDd,  // T D
  kKk,  // K G NG HH
  kCh,  // CH JH SH ZH
  kSs,  // S Z
  kNn,  // N
  kL,   // L
  kRr,  // R ER
  kAa,  // AA AW AY
  kAh,  // AE AH
  kE,   // EH EY
  kIh,  // IH IY Y
  kOh,  // AO OW OY
  kOu,  // UH UW W
};
inline constexpr int kNumMouthClasses = 17;
inline constexpr std::array<std::string_view, kNumMouthClasses> kMouthClassNames{
    "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "L", "RR", "aa", "ah", "E", "ih", "oh", "ou"};

// An ARPAbet phone (stress digits ignored, any case) or a silence label ("", "SIL", "SP", "SPN", "NSN") to its
// class; -1 for anything else.
int mouthClassOfPhone(std::string_view phone);

// Oculus/OpenXR LipSync's 15 visemes, in their order.
inline constexpr int kNumOculusVisemes = 15;
inline constexpr std::array<std::string_view, kNumOculusVisemes> kOculusVisemeNames{
    "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "ih", "oh", "ou"};
int oculusVisemeOf(int mouthClass);
// Class probabilities (kNumMouthClasses) to the 15 visemes' weights (the split classes summed).
Eigen::VectorXd oculusWeights(const Eigen::Ref<const Eigen::VectorXd>& classProbabilities);

// VRM's five vowel blendshapes.
inline constexpr std::array<std::string_view, 5> kVrmVowelNames{"A", "I", "U", "E", "O"};
Eigen::VectorXd vrmWeights(const Eigen::Ref<const Eigen::VectorXd>& classProbabilities);  // 5, each in [0, 1]

// Rhubarb Lip Sync's mouth shapes: A-F, and the extended G (F/V), H (L) and X (rest).
inline constexpr std::string_view kRhubarbShapes = "ABCDEFGHX";
char rhubarbShapeOf(int mouthClass);

// The mouth classes of a recording's frames: each frame's probabilities, and the sequence of classes shown (the
// decoder's path, each class held for at least the model's minimum hold).
struct VisemeTrack {
  double framesPerSecond = 30.0;
  Eigen::MatrixXd posteriors;  // kNumMouthClasses x T, each column sums to 1
  std::vector<int> classes;    // T
  bool empty() const { return classes.empty(); }
  int numFrames() const { return static_cast<int>(classes.size()); }
};

// Runs of equal values: (first frame, length) in order.
struct Run {
  int first = 0;
  int length = 0;
  int value = 0;
};
std::vector<Run> runsOf(const std::vector<int>& values);

}  // namespace th::face
