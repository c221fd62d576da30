// A diagnostic, not a test: our face rendered with the jaw alone opening (0 to 400 MNS, the head still),
// tracked and fitted four ways (all FAPs; the jaw alone; without the inner lips' points; the jaw alone without
// them), printing the jaw each gives, and a picture of the widest frame with dlib's landmarks (red) and the
// model's at the truth (green).
//
//   build/tools/diagnostics/jaw_sweep [picture.png]
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "face/face_model.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"
#include "render/image.h"
#include "tracking/track.h"

int main(int argc, char** argv) {
  const th::face::FaceModel face = th::face::FaceModel::buildDefault();
  constexpr int kWidth = 640, kHeight = 480;
  th::render::OffscreenContext context;
  th::render::FaceRenderer renderer(context, face.mesh(), {.width = kWidth, .height = kHeight});
  renderer.setMouthOpening(face.innerLipVertices());
  const th::render::OrbitCamera camera = th::render::frameHead(face.mesh().positions, double(kWidth) / kHeight);
  const double focal = 0.5 * kHeight / std::tan(0.5 * camera.fovYDegrees * std::numbers::pi / 180.0);
  th::tracking::LandmarkDetector detector;
  th::tracking::Track track;
  track.width = kWidth;  // the camera's axis at the frame's centre
  track.height = kHeight;
  std::vector<double> jaws;
  th::render::Image widest;
  for (double jaw = 0.0; jaw <= 400.0; jaw += 50.0) {
    th::face::FapFrame faps{};
    faps[3] = jaw;
    renderer.setPositions(face.deform(faps));
    th::render::Image image = renderer.renderImage(camera);
    cv::Mat bgr;
    cv::cvtColor(cv::Mat(kHeight, kWidth, CV_8UC3, image.pixels.data()), bgr, cv::COLOR_RGB2BGR);
    th::tracking::TrackedFrame frame;
    frame.seconds = jaw / 1000.0;
    frame.found = detector.find(bgr, frame.landmarks);
    if (!frame.found) {
      std::cout << "jaw " << jaw << ": no face\n";
      return 1;
    }
    track.frames.push_back(frame);
    jaws.push_back(jaw);
    widest = image;
  }
  const auto fitWith = [&](th::tracking::FitOptions options, const char* name) {
    options.focalLengthPixels = focal;
    th::tracking::Track copy = track;
    th::tracking::fitTrack(copy, face, options, 0);
    std::cout << name << ":";
    for (std::size_t f = 0; f < copy.frames.size(); ++f)
      std::cout << "  " << jaws[f] << "->" << std::lround(copy.frames[f].fit.faps[3]) << " ("
                << std::round(copy.frames[f].fit.residualPixels * 10) / 10 << " px)";
    std::cout << "\n";
    return copy;
  };
  const th::tracking::Track all = fitWith({}, "all FAPs");
  th::tracking::FitOptions jawOnly;
  jawOnly.faps = {3};
  fitWith(jawOnly, "jaw alone");
  th::tracking::FitOptions outer;
  outer.landmarks = {8};
  for (int i = 17; i < 60; ++i) outer.landmarks.push_back(i);
  fitWith(outer, "without the inner lips");
  th::tracking::FitOptions outerJaw = outer;
  outerJaw.faps = {3};
  fitWith(outerJaw, "jaw alone, without the inner lips");
  // The mouth's opening as dlib sees it and as the model has it at the truth.
  th::tracking::FitOptions rigid;
  rigid.focalLengthPixels = focal;
  th::tracking::FaceFitter fitter(face, rigid);
  const th::tracking::FaceFit rest = fitter.calibrate(track.frames.front().landmarks);
  std::cout << "lips' opening, dlib / model at the truth:";
  for (std::size_t f = 0; f < track.frames.size(); ++f) {
    th::tracking::FaceFit truth = rest;
    truth.faps[3] = jaws[f];
    std::cout << "  " << jaws[f] << ": "
              << std::round(1000 * th::tracking::mouthOpening(track.frames[f].landmarks)) / 1000 << " / "
              << std::round(1000 * th::tracking::mouthOpening(fitter.project(truth))) / 1000;
  }
  std::cout << "\n";
  if (argc > 1) {
    th::tracking::FaceFit truth = rest;
    truth.faps[3] = jaws.back();
    const th::tracking::Landmarks model = fitter.project(truth);
    const auto dot = [&](double x, double y, std::uint8_t r, std::uint8_t g) {
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int px = static_cast<int>(std::lround(x)) + dx, py = static_cast<int>(std::lround(y)) + dy;
          if (px < 0 || py < 0 || px >= kWidth || py >= kHeight) continue;
          std::uint8_t* p = widest.pixels.data() + 3 * (py * kWidth + px);
          p[0] = r, p[1] = g, p[2] = 0;
        }
    };
    for (int i = 0; i < th::tracking::kNumLandmarks; ++i) {
      dot(track.frames.back().landmarks(0, i), track.frames.back().landmarks(1, i), 255, 0);
      dot(model(0, i), model(1, i), 0, 255);
    }
    th::render::writePng(argv[1], widest);
  }
  (void)all;
  return 0;
}
