#include "formats/arkit_format.h"

#include <algorithm>
#include <cstdio>
#include <ostream>

#include "core/error.h"
#include "formats/weight_tables.h"

namespace th::formats {
int arkitIndex(std::string_view name) {
  for (std::size_t i = 0; i < kArkitNames.size(); ++i)
    if (kArkitNames[i] == name) return static_cast<int>(i);
  throw Error("ARKit: no shape named " + std::string(name));
}

Eigen::MatrixXd arkitWeights(const face::FapTrack& track, const ArkitScale& scale) {
  Eigen::MatrixXd weights = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(kArkitNames.size()), track.numFrames());
  for (int t = 0; t < track.numFrames(); ++t) {
    const auto fap = [&](int number) {
      const int row = track.rowOf(number);
      return row >= 0 ? track.values(row, t) : 0.0;
    };
    const auto pair = [&](int inner, int outer) { return 0.5 * (fap(inner) + fap(outer)); };
    const auto set = [&](std::string_view name, double value, double full) {
      weights(arkitIndex(name), t) = std::clamp(value / full, 0.0, 1.0);
    };
    set("jawOpen", fap(3), scale.jawOpen);
    set("jawForward", fap(14), scale.jaw);
    set("jawRight", fap(15), scale.jaw);  // FAP 15 is positive to the face's right
    set("jawLeft", -fap(15), scale.jaw);
    for (const bool left : {true, false}) {
      const std::string_view side = left ? "Left" : "Right";
      const auto name = [&](std::string_view stem) { return std::string(stem) + std::string(side); };
      set(name("eyeBlink"), fap(left ? 19 : 20), scale.blink);
      set(name("eyeWide"), -fap(left ? 19 : 20), 0.5 * scale.blink);
      set(name("eyeSquint"), fap(left ? 21 : 22), 0.5 * scale.blink);
      // Yaw is positive towards the face's left: outwards for the left eye, inwards for the right.
      const double yaw = fap(left ? 23 : 24), pitch = fap(left ? 25 : 26);
      set(name("eyeLookOut"), left ? yaw : -yaw, scale.lookSideways);
      set(name("eyeLookIn"), left ? -yaw : yaw, scale.lookSideways);
      set(name("eyeLookDown"), pitch, scale.lookVertical);
      set(name("eyeLookUp"), -pitch, scale.lookVertical);
      const double cornerUp = pair(left ? 12 : 13, left ? 59 : 60);
      set(name("mouthSmile"), cornerUp, scale.lip);
      set(name("mouthFrown"), -cornerUp, scale.lip);
      set(name("mouthStretch"), pair(left ? 6 : 7, left ? 53 : 54), scale.lip);
      set(name("mouthLowerDown"), -pair(left ? 10 : 11, left ? 57 : 58), scale.lip);
      set(name("mouthUpperUp"), -pair(left ? 8 : 9, left ? 55 : 56), scale.lip);
      set(name("browDown"), -(fap(left ? 31 : 32) + fap(left ? 33 : 34) + fap(left ? 35 : 36)) / 3.0, scale.brow);
      set(name("browOuterUp"), fap(left ? 35 : 36), scale.brow);
      set(name("cheekSquint"), fap(left ? 41 : 42), scale.cheek);
      set(name("noseSneer"), fap(left ? 61 : 62), scale.nose);
    }
    set("browInnerUp", 0.5 * (fap(31) + fap(32)), scale.brow);
    set("cheekPuff", 0.5 * (fap(39) + fap(40)), scale.cheek);
    // Both corners moving towards one side of the face moves the mouth there; stretch is positive outwards.
    const double towardsLeft = 0.5 * (pair(6, 53) - pair(7, 54));
    set("mouthLeft", towardsLeft, scale.lip);
    set("mouthRight", -towardsLeft, scale.lip);
    // Narrowing corners pucker; lips pushed forward funnel; lips pressed together against an open jaw close.
    const double pucker = -0.5 * (pair(6, 53) + pair(7, 54));
    const double upperDown = pair(4, 51), lowerUp = pair(5, 52);
    const double closing = 0.5 * (upperDown + lowerUp);
    set("mouthPucker", pucker, scale.lip);
    set("mouthClose", closing, scale.lip);
    // The shapes the lips make without protrusion FAPs (16, 17), read from the lip FAPs the face moves: narrowed
    // corners with the lips apart round into a funnel (on BEAT2's speaker mostly on /u o w/); one lip moving
    // past the other rolls it in (the lower lip raised to the upper teeth: mostly /f v/). How often, measured:
    // docs/results.md, "Formats". No press: a closure is not told from lips at rest.
    const double apart = std::max(0.0, fap(3) / scale.jawOpen - closing / scale.lip);
    set("mouthFunnel", std::max(0.5 * (fap(16) + fap(17)), std::min(pucker, apart * scale.lip)), scale.lip);
    set("mouthRollLower", lowerUp - upperDown, scale.lip);
    set("mouthRollUpper", upperDown - lowerUp, scale.lip);
  }
  return weights;
}

void ArkitFormat::write(std::ostream& out, const face::FapTrack& track) const {
  writeWeightsCsv(out, kArkitNames, arkitWeights(track, scale_), track.framesPerSecond);
}

const AnimationFormat& arkitFormat() {
  static const ArkitFormat format;
  return format;
}

}  // namespace th::formats
