// The ARKit scale measured on a face: apart from the weights (arkit_format.cpp) because it needs the face's
// geometry, which a build that only animates (web/) does not compile.
#include "face/face_model.h"
#include "formats/arkit_format.h"

namespace th::formats {

ArkitScale arkitScaleFor(const face::FaceModel& face) {
  ArkitScale scale;
  // The FAP 3 value whose jaw angle is the jawOpen shape's: invert jawAngleFor by bisection.
  const double target = face.jaw().shapeAngle;
  double low = 0.0, high = 8192.0;
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (low + high);
    (face.jawAngleFor(middle) < target ? low : high) = middle;
  }
  scale.jawOpen = 0.5 * (low + high);
  return scale;
}

}  // namespace th::formats
