// ARKit-named blendshape weights from MPEG-4 FAPs, for engines that animate faces with Apple's 52 shapes; as an
// animation format (animation_format.h), a CSV of time_s and the 52 weights per frame.
//
//   th::face::FapTrack track = th::formats::readAnimation("speech.fap");
//   th::formats::ArkitScale scale = th::formats::arkitScaleFor(faceModel);   // or ArkitScale{} for the defaults
//   Eigen::MatrixXd weights = th::formats::arkitWeights(track, scale);       // 52 x frames, each in [0, 1]
//   th::formats::writeAnimation("speech_arkit.csv", track, th::formats::ArkitFormat(scale));
//
// Each weight is a FAP (or the mean of a FAP pair: inner and outer lip contour) divided by the FAP value at
// which the shape is fully on, clamped to [0, 1]; a FAP that can go both ways feeds the shape of each
// direction. "Left" is the face's own left, as in ARKit. The full-on values (ArkitScale):
//   jawOpen       FAP 3 at the reference face's jawOpen shape (the artist's full opening; arkitScaleFor)
//   eyeBlink      FAP 19/20 = 1024 (one IRISD: the upper lid meets the lower)
//   eyeLook*      FAPs 23–26 = 30° (sideways) and 25° (up, down)
//   lips, brows, cheeks, nose, jaw thrust/shift: `lip`, `brow`, ... FAPU counts below (about 6 mm of lip
//                 motion and 12 mm of brow motion on a human-sized face)
// Shapes no FAP describes (mouthRoll*, mouthShrug*, mouthPress*, mouthDimple*, tongueOut) are 0.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string_view>

#include "face/fap_track.h"
#include "formats/animation_format.h"

namespace th::face {
class FaceModel;
}

namespace th::formats {

inline constexpr std::array<std::string_view, 52> kArkitNames{
    "eyeBlinkLeft",      "eyeLookDownLeft",    "eyeLookInLeft",
    "eyeLookOutLeft",    "eyeLookUpLeft",      "eyeSquintLeft",
    "eyeWideLeft",       "eyeBlinkRight",      "eyeLookDownRight",
    "eyeLookInRight",    "eyeLookOutRight",    "eyeLookUpRight",
    "eyeSquintRight",    "eyeWideRight",       "jawForward",
    "jawLeft",           "jawRight",           "jawOpen",
    "mouthClose",        "mouthFunnel",        "mouthPucker",
    "mouthLeft",         "mouthRight",         "mouthSmileLeft",
    "mouthSmileRight",   "mouthFrownLeft",     "mouthFrownRight",
    "mouthDimpleLeft",   "mouthDimpleRight",   "mouthStretchLeft",
    "mouthStretchRight", "mouthRollLower",     "mouthRollUpper",
    "mouthShrugLower",   "mouthShrugUpper",    "mouthPressLeft",
    "mouthPressRight",   "mouthLowerDownLeft", "mouthLowerDownRight",
    "mouthUpperUpLeft",  "mouthUpperUpRight",  "browDownLeft",
    "browDownRight",     "browInnerUp",        "browOuterUpLeft",
    "browOuterUpRight",  "cheekPuff",          "cheekSquintLeft",
    "cheekSquintRight",  "noseSneerLeft",      "noseSneerRight",
    "tongueOut"};

// The FAP values at which shapes are fully on.
struct ArkitScale {
  double jawOpen = 1200.0;                                       // FAP 3 (MNS); arkitScaleFor measures it on the face
  double blink = 1024.0;                                         // FAPs 19–22 (IRISD)
  double lookSideways = 30.0 * 3.14159265358979 / 180.0 / 1e-5;  // FAPs 23/24 (AU)
  double lookVertical = 25.0 * 3.14159265358979 / 180.0 / 1e-5;  // FAPs 25/26 (AU)
  double lip = 300.0;                                            // lip FAPs (MNS, MW)
  double jaw = 200.0;                                            // FAPs 14, 15
  double brow = 250.0;                                           // FAPs 31–38 (ENS, ES)
  double cheek = 250.0;                                          // FAPs 39–42
  double nose = 250.0;                                           // FAPs 61–64
};

// The defaults with jawOpen measured on `face`: the FAP 3 value of its jawOpen shape's angle.
ArkitScale arkitScaleFor(const face::FaceModel& face);

// 52 x numFrames weights, a row per shape in kArkitNames order; FAPs the track lacks count as 0.
Eigen::MatrixXd arkitWeights(const face::FapTrack& track, const ArkitScale& scale = {});

// The row of a name in kArkitNames; throws th::Error for another name.
int arkitIndex(std::string_view name);

// The format: a header time_s and the 52 names, then a row per frame (times to 6 decimals, weights to 4).
// The registry's "arkit" (animationFormat) uses the default scale; export measures it on the face it renders.
class ArkitFormat final : public AnimationFormat {
 public:
  explicit ArkitFormat(const ArkitScale& scale = {}) : scale_(scale) {}
  std::string_view name() const override { return "arkit"; }
  std::string_view extension() const override { return ".csv"; }
  std::string_view description() const override { return "ARKit's 52 blendshape weights per frame, each in [0, 1]"; }
  void write(std::ostream& out, const face::FapTrack& track) const override;

 private:
  ArkitScale scale_;
};

}  // namespace th::formats
