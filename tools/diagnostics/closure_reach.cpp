// How far the articulation's closure shuts the face's lips (docs/mouth.md, "The phones' mouth"): each mouth
// class's typical shape (the articulation model's class shapes about its FAPs' mean), as it is and made 3 and 6
// times as wide, closed as a frame shown as PP is closed (animation::articulateLips), then measured on the
// default face as the tracker measures a speaker's lips (track.h mouthOpening: the inner-lip gaps over the eye
// corners' distance; 0.04 counts as shut).
//
//   build/tools/diagnostics/closure_reach models/articulation.json
#include <cstdio>
#include <exception>

#include "animation/articulation.h"
#include "animation/mouth_network.h"
#include "eval/mouth_scores.h"
#include "face/face_model.h"
#include "face/visemes.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: closure_reach ARTICULATION.json\n");
    return 2;
  }
  try {
    using namespace th;
    const animation::MouthNetwork model = animation::loadMouthNetwork(argv[1]);
    const face::FaceModel drawn = face::FaceModel::buildDefault();
    const eval::MouthShapes face(drawn);  // keeps a reference to the face
    const std::vector<int>& faps = model.visualFaps;
    std::printf("%-6s %5s | %-23s | %s\n", "class", "width", "opening: typical shape", "closed as PP");
    for (const double scale : {1.0, 3.0, 6.0})
      for (int mouthClass = 0; mouthClass < face::kNumMouthClasses; ++mouthClass) {
        const Eigen::MatrixXd shape = scale * (model.basis.mean() + model.classShapes.col(mouthClass));
        Eigen::MatrixXd closed = shape;
        animation::articulateLips(model, {face::kPp}, faps, closed, {});
        std::printf("%-6d %4.0fx | %23.3f | %.3f\n", mouthClass, scale, face.of(shape, faps)(0, 0),
                    face.of(closed, faps)(0, 0));
      }
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "closure_reach: %s\n", error.what());
    return 1;
  }
}
