#include "tracking/face_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.h"
#include "face/fap.h"

namespace th::tracking {
namespace {

// Parameters: scale, offset x, offset y, pitch, yaw, roll (AU), then the FAPs of FitOptions::faps.
constexpr int kRigid = 6;

std::vector<int> defaultLandmarks() {
  std::vector<int> used{8};
  for (int i = 17; i < kNumLandmarks; ++i) used.push_back(i);
  return used;
}

double eyeDistance(const Landmarks& points) {
  return (points.col(36) - points.col(45)).norm();
}

}  // namespace

FaceFitter::FaceFitter(const face::FaceModel& face, FitOptions options) : face_(face), options_(std::move(options)) {
  if (face.landmarkVertices().size() != static_cast<std::size_t>(kNumLandmarks))
    throw Error("FaceFitter: the face model has no 68 landmark vertices");
  if (options_.landmarks.empty()) options_.landmarks = defaultLandmarks();
  for (int i : options_.landmarks)
    if (i < 0 || i >= kNumLandmarks) throw Error("FaceFitter: landmark " + std::to_string(i) + " is not one of the 68");
  for (int fap : options_.faps)
    if (fap < 3 || fap > face::kNumFaps || fap == 48 || fap == 49 || fap == 50 || !face.supports(fap))
      throw Error("FaceFitter: FAP " + std::to_string(fap) + " cannot be fitted");
  selection_ = face.select(face.landmarkVertices());
  for (int v : face.landmarkVertices()) shares_.push_back(face.headShare(v));
}

FaceFit FaceFitter::fitOf(const Eigen::VectorXd& parameters) const {
  FaceFit fit;
  fit.scale = parameters[0];
  fit.offset = parameters.segment<2>(1);
  fit.faps[48] = parameters[3];
  fit.faps[49] = parameters[4];
  fit.faps[50] = parameters[5];
  for (std::size_t k = 0; k < options_.faps.size(); ++k)
    fit.faps[static_cast<std::size_t>(options_.faps[k])] = parameters[kRigid + static_cast<Eigen::Index>(k)];
  return fit;
}

Eigen::VectorXd FaceFitter::parametersOf(const FaceFit& fit) const {
  Eigen::VectorXd parameters(kRigid + static_cast<Eigen::Index>(options_.faps.size()));
  parameters[0] = fit.scale;
  parameters[1] = fit.offset.x();
  parameters[2] = fit.offset.y();
  parameters[3] = fit.faps[48];
  parameters[4] = fit.faps[49];
  parameters[5] = fit.faps[50];
  for (std::size_t k = 0; k < options_.faps.size(); ++k)
    parameters[kRigid + static_cast<Eigen::Index>(k)] = fit.faps[static_cast<std::size_t>(options_.faps[k])];
  return parameters;
}

Landmarks FaceFitter::project(const FaceFit& fit) const {
  // The face's own motion first (jaw, lips; the head's turn left out), the speaker's rest shape added, then
  // the turn about the neck pivot, each landmark by its share of it (as FaceModel::deform turns them: the
  // chin and the jaw line sit where the turn starts to fade into the neck).
  face::FapFrame still = fit.faps;
  still[48] = still[49] = still[50] = 0.0;
  Eigen::Matrix3Xd model = face_.deform(still, selection_);
  model.topRows<2>() += calibration_;
  const double pitch = fit.faps[48] * face::kAngleUnit, yaw = fit.faps[49] * face::kAngleUnit,
               roll = fit.faps[50] * face::kAngleUnit;
  const Eigen::Matrix3d turn = face::headRotation(pitch, yaw, roll);
  const Eigen::Vector3d& pivot = face_.neckPivot();
  // Perspective: the camera's distance in model units at this scale (infinite: orthographic).
  const double distance = options_.focalLengthPixels > 0.0 ? options_.focalLengthPixels / fit.scale : 0.0;
  // The model's origin off the camera's axis, in model units at its depth (0 without a principal point): a
  // point's sideways place is enlarged from the axis, not from the origin.
  const Eigen::Vector2d offAxis = distance > 0.0 && options_.principalPoint.allFinite()
                                      ? Eigen::Vector2d((fit.offset.x() - options_.principalPoint.x()) / fit.scale,
                                                        -(fit.offset.y() - options_.principalPoint.y()) / fit.scale)
                                      : Eigen::Vector2d::Zero();
  Landmarks image;
  for (int i = 0; i < kNumLandmarks; ++i) {
    const double share = shares_[static_cast<std::size_t>(i)];
    const Eigen::Vector3d p =
        pivot + restRotation_ * ((share >= 1.0 ? turn : face::headRotation(share * pitch, share * yaw, share * roll)) *
                                 (model.col(i) - pivot));
    const double enlarge = distance > 0.0 ? distance / std::max(distance - p.z(), 1e-3 * distance) : 1.0;
    image(0, i) = fit.scale * (enlarge * (p.x() + offAxis.x()) - offAxis.x()) + fit.offset.x();
    image(1, i) = -fit.scale * (enlarge * (p.y() + offAxis.y()) - offAxis.y()) + fit.offset.y();
  }
  return image;
}

Eigen::VectorXd FaceFitter::residuals(const Landmarks& points, const Eigen::VectorXd& parameters) const {
  const Landmarks projected = project(fitOf(parameters));
  const Eigen::Index used = static_cast<Eigen::Index>(options_.landmarks.size());
  const Eigen::Index numFaps = static_cast<Eigen::Index>(options_.faps.size());
  Eigen::VectorXd r(2 * used + numFaps);
  for (Eigen::Index j = 0; j < used; ++j) {
    const int i = options_.landmarks[static_cast<std::size_t>(j)];
    r.segment<2>(2 * j) = projected.col(i) - points.col(i);
  }
  // The prior, in pixels: a FAP at its typical range costs fapPrior (jawPrior) eye distances.
  const double perUnit = eyeDistance(points) / options_.typicalFapRange;
  for (Eigen::Index k = 0; k < numFaps; ++k)
    r[2 * used + k] = (options_.faps[static_cast<std::size_t>(k)] == 3 ? options_.jawPrior : options_.fapPrior) *
                      perUnit * parameters[kRigid + k];
  return r;
}

FaceFit FaceFitter::rigidStart(const Landmarks& points) const {
  // Scale and offset from the neutral model's landmarks seen from the front: match the spread and the mean.
  FaceFit fit;
  fit.scale = 1.0;
  const Landmarks model = project(fit);  // at scale 1, offset 0: (X, -Y)
  Eigen::Vector2d modelMean = Eigen::Vector2d::Zero(), pointMean = Eigen::Vector2d::Zero();
  for (int i : options_.landmarks) {
    modelMean += model.col(i);
    pointMean += points.col(i);
  }
  modelMean /= static_cast<double>(options_.landmarks.size());
  pointMean /= static_cast<double>(options_.landmarks.size());
  double modelSpread = 0.0, pointSpread = 0.0;
  for (int i : options_.landmarks) {
    modelSpread += (model.col(i) - modelMean).squaredNorm();
    pointSpread += (points.col(i) - pointMean).squaredNorm();
  }
  fit.scale = std::sqrt(pointSpread / modelSpread);
  fit.offset = pointMean - fit.scale * modelMean;
  return fit;
}

FaceFit FaceFitter::fit(const Landmarks& points, const FaceFit* start) const {
  if (!points.allFinite()) throw Error("FaceFitter: landmarks must be finite");
  Eigen::VectorXd x = parametersOf(start ? *start : rigidStart(points));
  const Eigen::Index n = x.size();
  // Finite-difference steps: a thousandth of the scale, a tenth of a pixel, a milliradian, one FAP unit.
  const std::array<double, kRigid> rigidStep{
      1e-3 * x[0], 0.1, 0.1, 1e-3 / face::kAngleUnit, 1e-3 / face::kAngleUnit, 1e-3 / face::kAngleUnit};
  std::vector<Eigen::Index> free;  // the parameters that move: all of them
  for (Eigen::Index k = 0; k < n; ++k) free.push_back(k);
  const Eigen::Index m = static_cast<Eigen::Index>(free.size());
  Eigen::VectorXd r = residuals(points, x);
  double cost = r.squaredNorm();
  double damping = 1e-3;
  int iteration = 0;
  bool converged = false;
  while (iteration < options_.iterations && !converged) {
    ++iteration;
    Eigen::MatrixXd jacobian(r.size(), m);
    for (Eigen::Index j = 0; j < m; ++j) {
      const Eigen::Index k = free[static_cast<std::size_t>(j)];
      Eigen::VectorXd moved = x;
      const double h = k < kRigid ? rigidStep[static_cast<std::size_t>(k)] : 1.0;
      moved[k] += h;
      jacobian.col(j) = (residuals(points, moved) - r) / h;
    }
    const Eigen::MatrixXd normal = jacobian.transpose() * jacobian;
    const Eigen::VectorXd gradient = jacobian.transpose() * r;
    bool improved = false;
    for (int attempt = 0; attempt < 10 && !improved; ++attempt) {
      Eigen::MatrixXd damped = normal;
      damped.diagonal() += damping * normal.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd delta = damped.ldlt().solve(-gradient);
      Eigen::VectorXd candidate = x;
      for (Eigen::Index j = 0; j < m; ++j) candidate[free[static_cast<std::size_t>(j)]] += delta[j];
      // The jaw opens only (the model does not close it past rest): below 0 it would have no gradient to come
      // back by, so it stops at 0.
      for (std::size_t k = 0; k < options_.faps.size(); ++k)
        if (options_.faps[k] == 3)
          candidate[kRigid + static_cast<Eigen::Index>(k)] =
              std::max(0.0, candidate[kRigid + static_cast<Eigen::Index>(k)]);
      if (!(candidate[0] > 0.0)) {
        damping *= 10.0;
        continue;
      }
      const Eigen::VectorXd candidateResiduals = residuals(points, candidate);
      const double candidateCost = candidateResiduals.squaredNorm();
      if (candidateCost < cost) {
        const double gain = cost - candidateCost;
        x = candidate;
        r = candidateResiduals;
        cost = candidateCost;
        damping = std::max(damping / 3.0, 1e-9);
        improved = true;
        converged = gain < 1e-6 * cost + 1e-9;
      } else {
        damping *= 10.0;
      }
    }
    if (!improved) break;
  }
  FaceFit fit = fitOf(x);
  fit.iterations = iteration;
  const Eigen::Index used = static_cast<Eigen::Index>(options_.landmarks.size());
  fit.residualPixels = std::sqrt(r.head(2 * used).squaredNorm() / static_cast<double>(used));
  return fit;
}

FaceFit FaceFitter::calibrate(const Landmarks& points) {
  calibration_.setZero();
  restRotation_.setIdentity();
  // The rest face: its scale, place and turn alone (no FAPs); the turn becomes the rest orientation, and what
  // is left, carried back into the model's frame (image y down, model y up), the speaker's own shape.
  FitOptions placeOnly = options_;
  placeOnly.faps.clear();
  const FaceFitter place(face_, placeOnly);
  FaceFit fit = place.fit(points);
  restRotation_ = face::headRotation(fit.faps[48] * face::kAngleUnit, fit.faps[49] * face::kAngleUnit,
                                     fit.faps[50] * face::kAngleUnit);
  fit.faps[48] = fit.faps[49] = fit.faps[50] = 0.0;
  const Landmarks projected = project(fit);
  const Eigen::Matrix3Xd model = face_.deform(face::FapFrame{}, selection_);
  const double distance = options_.focalLengthPixels > 0.0 ? options_.focalLengthPixels / fit.scale : 0.0;
  for (int i = 0; i < kNumLandmarks; ++i) {
    // Pixels to model units at this point's depth (as project() enlarges it), turned back into the model.
    const double depth = (restRotation_ * (model.col(i) - face_.neckPivot())).z() + face_.neckPivot().z();
    const double enlarge = distance > 0.0 ? distance / std::max(distance - depth, 1e-3 * distance) : 1.0;
    const Eigen::Vector2d image = (points.col(i) - projected.col(i)) / (fit.scale * enlarge);
    const Eigen::Vector3d inModel = restRotation_.transpose() * Eigen::Vector3d(image.x(), -image.y(), 0.0);
    calibration_.col(i) = inModel.head<2>();
  }
  fit.residualPixels = 0.0;
  const Landmarks calibrated = project(fit);
  for (int i : options_.landmarks) fit.residualPixels += (points.col(i) - calibrated.col(i)).squaredNorm();
  fit.residualPixels = std::sqrt(fit.residualPixels / static_cast<double>(options_.landmarks.size()));
  return fit;
}

}  // namespace th::tracking
