// Named key poses of the face as FAP values: the golden-image tests, the contact sheet and the viewer's
// presets use the same ones.
//
//   for (const th::face::Pose& pose : th::face::keyPoses()) render(face.deform(pose.faps));
//
// Thread contract: pure functions.
#pragma once

#include <string>
#include <vector>

#include "face/face_model.h"

namespace th::face {

struct Pose {
  std::string name;   // file-name friendly: "neutral", "jaw_open", ...
  std::string title;  // for people: "jaw open (FAP 3 = 600)"
  FapFrame faps{};
};

// neutral, jaw open, smile, blink, head yaw 20° (the golden images), then brows up, pucker, look left, and a
// spoken "ah" with a nod (for the contact sheet).
std::vector<Pose> keyPoses();

// The first five: the poses the golden-image tests hold to their references (tests/render/golden).
std::vector<Pose> goldenPoses();

}  // namespace th::face
