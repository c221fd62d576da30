// The face model fitted to a frame's 68 landmarks (Tao & Huang's tracker, with our FAP-driven mesh in place of
// their PBVD model): least squares over the head's rotation (FAPs 48-50), its scale and place in the image, and
// the jaw and lip FAPs, so that the model's landmark vertices (ICT FaceKit's iBUG annotation), deformed and
// projected, land on the tracked points.
//
//   const th::face::FaceModel face = th::face::FaceModel::buildDefault();
//   th::tracking::FaceFitter fitter(face);
//   th::tracking::FaceFit fit = fitter.fit(points);             // the first frame: a rigid start
//   fit = fitter.fit(nextPoints, &fit);                          // then each frame from the last
//   // fit.faps[3] (open_jaw, MNS), fit.faps[49] (yaw, AU), fit.residualPixels, ...
//
// Camera: scaled orthographic by default: image x = s·X + ox, image y = −s·Y + oy, for the deformed model point
// (X, Y, Z) (model y up, image y down; the face's left, +X, is the image's right). Where the camera's focal
// length f is known (FitOptions::focalLengthPixels), perspective about the model's origin: the camera is
// D = f / s model units away, and a point nearer by Z is enlarged by D / (D − Z); a face away from the
// camera's axis (FitOptions::principalPoint) is seen from the side by as much, as a lens sees it. Near cameras matter:
// seen orthographically, a turn of the head moves the nose further than the model expects, and the fitted yaw comes out
// too large (docs/results.md, "Tracking in detail"). Solved with Levenberg-Marquardt on numerical derivatives (the
// model deforms only the landmark vertices: face::VertexSelection, tens of microseconds). The FAPs are pulled towards 0
// (FitOptions::jawPrior, fapPrior, in eye distances per typical range): lightly the jaw, which the chin shows; more the
// lips, whose 20 FAPs would otherwise trade motion with the jaw and each other (on our rendered face the jaw's error
// fell by almost half with the lips' pull ten times the jaw's: docs/results.md, "Figures behind choices in the
// code").
//
// The jaw line's contour points (1-7, 9-15 and the ends 0, 16) slide over the cheek as the head turns and are
// not fixed vertices: only the chin (8) is used from it by default.
//
// Person and annotation differ from the model: call calibrate() on a frame of the speaker at rest (mouth
// closed). That frame is taken as the head's rest pose, with no FAPs: its scale, place and the way it faces the
// camera are fitted (a camera above the eyes, or a speaker who holds the head a little down, sees the rest face
// turned), and its residual, carried into the model's frame, is added to the model's landmarks from then on.
// So the head's angles (FAPs 48-50, about the head's own axes) and the FAPs measure change from that rest
// face, rather than the difference between two faces (or between dlib's idea of a landmark and the mesh's
// annotation), and a head that faces the camera at an angle at rest still turns about its own axes.
// (Our face rendered from 8° above, tracking_truth_test: with the rest face taken as square to the camera the
// rotations came back about twice as far off as with its orientation fitted: docs/results.md, "Tracking in
// detail".)
//
// Thread contract: fit() is const; a fitter may be shared by threads once calibrated.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "face/face_model.h"
#include "tracking/landmarks.h"

namespace th::tracking {

struct FitOptions {
  // The non-rigid part: the jaw (3) and the lips (inner 4-13, outer 51-60).
  std::vector<int> faps{3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60};
  std::vector<int> landmarks;  // which of the 68 to fit; empty: 8 and 17-67
  // Weight of each FAP's pull to 0, per (value / typical range): light on the jaw, which the chin shows well;
  // heavier on the lips, whose 20 FAPs could otherwise trade motion with the jaw and with each other.
  double jawPrior = 0.01;
  double fapPrior = 0.1;
  double typicalFapRange = 300.0;  // FAPU counts: a wide-open jaw is ~500 MNS, a lip movement ~100-300
  int iterations = 30;             // Levenberg-Marquardt steps at most
  double focalLengthPixels = 0.0;  // 0: orthographic; else the camera's focal length in pixels
  // With a focal length: where the camera's axis meets the image (pixels; NaN: on the model's origin, wherever
  // the face is). fitTrack puts it at the frame's centre, where a camera's usually is.
  Eigen::Vector2d principalPoint = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
};

struct FaceFit {
  face::FapFrame faps{};             // the fitted FAPs (3, lips, and 48-50 the head's pitch, yaw, roll in AU)
  double scale = 1.0;                // pixels per model unit
  Eigen::Vector2d offset{0.0, 0.0};  // pixels
  double residualPixels = 0.0;       // root mean square distance of the fitted landmarks to the tracked ones
  int iterations = 0;
};

class FaceFitter {
 public:
  explicit FaceFitter(const face::FaceModel& face, FitOptions options = {});

  FaceFit fit(const Landmarks& points, const FaceFit* start = nullptr) const;
  // The model's landmarks as a fit projects them (all 68).
  Landmarks project(const FaceFit& fit) const;
  // Takes `points` (a neutral frame) as the speaker's rest shape; returns its rigid fit.
  FaceFit calibrate(const Landmarks& points);

  const FitOptions& options() const { return options_; }

 private:
  Eigen::VectorXd residuals(const Landmarks& points, const Eigen::VectorXd& parameters) const;
  FaceFit fitOf(const Eigen::VectorXd& parameters) const;
  Eigen::VectorXd parametersOf(const FaceFit& fit) const;
  FaceFit rigidStart(const Landmarks& points) const;

  const face::FaceModel& face_;
  FitOptions options_;
  Eigen::Matrix3d restRotation_ = Eigen::Matrix3d::Identity();  // how the rest face faces the camera
  face::VertexSelection selection_;                             // the 68 landmark vertices
  std::vector<double> shares_;                                  // each one's share of the head's turn
  Eigen::Matrix<double, 2, kNumLandmarks> calibration_ = Eigen::Matrix<double, 2, kNumLandmarks>::Zero();  // model X, Y
};

}  // namespace th::tracking
