#include "eval/mouth_sweep.h"

#include <chrono>
#include <mutex>

#include "animation/mouth_model.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parallel_for.h"
#include "eval/mouth_evaluation.h"

namespace th::eval {

std::vector<MouthSweepPoint> sweepMouthModels(const MouthSweepGrid& grid, const animation::MouthRecording& fit,
                                              const animation::MouthRecording& validation,
                                              const animation::MouthRecording& heldOut,
                                              const std::function<void(std::size_t, std::size_t)>& progress) {
  std::vector<MouthSweepPoint> points;
  for (hmm::CovarianceType covariance : grid.covariances)
    for (int tc : grid.contexts)
      for (int m : grid.mixtures)
        for (int n : grid.states) points.push_back({covariance, tc, m, n});
  std::mutex mutex;
  std::size_t done = 0;
  parallelFor(points.size(), 0, [&](std::size_t index) {
    MouthSweepPoint& point = points[index];
    const auto start = std::chrono::steady_clock::now();
    try {
      const animation::MouthModel model = animation::trainMouthModel({fit}, {.states = point.states,
                                                                             .mixtures = point.mixtures,
                                                                             .covariance = point.covariance,
                                                                             .contextFrames = point.contextFrames,
                                                                             .maxIterations = grid.iterations});
      const Eigen::MatrixXd validationTruth = model.basis.transform(validation.visual);
      const Eigen::MatrixXd validationEstimate = animation::synthesiseMouth(model, validation.speech);
      point.validationEpsilon = averageMse(validationEstimate, validationTruth);
      point.validationRho = averageCorrelation(validationEstimate, validationTruth);
      const Eigen::MatrixXd heldOutTruth = model.basis.transform(heldOut.visual);
      const Eigen::MatrixXd heldOutEstimate = animation::synthesiseMouth(model, heldOut.speech);
      point.heldOutEpsilon = averageMse(heldOutEstimate, heldOutTruth);
      point.heldOutRho = averageCorrelation(heldOutEstimate, heldOutTruth);
    } catch (const Error&) {
      point.failed = true;
    }
    point.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::lock_guard lock(mutex);
    ++done;
    if (progress) progress(done, points.size());
  });
  return points;
}

void writeMouthSweepCsv(const std::filesystem::path& path, const std::vector<MouthSweepPoint>& points) {
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "covariance_diag,tc,mixtures,states,validation_epsilon,validation_rho,seconds,heldout_epsilon,heldout_rho\n";
  for (const MouthSweepPoint& p : points) {
    if (p.failed) continue;
    out << (p.covariance == hmm::CovarianceType::kDiagonal) << ',' << p.contextFrames << ',' << p.mixtures << ','
        << p.states << ',' << p.validationEpsilon << ',' << p.validationRho << ',' << p.seconds << ','
        << p.heldOutEpsilon << ',' << p.heldOutRho << '\n';
  }
  file.commit();
}

const MouthSweepPoint* bestOnValidation(const std::vector<MouthSweepPoint>& points, hmm::CovarianceType covariance,
                                        int* failed) {
  const MouthSweepPoint* best = nullptr;
  int failures = 0;
  for (const MouthSweepPoint& p : points) {
    if (p.covariance != covariance) continue;
    if (p.failed) {
      ++failures;
      continue;
    }
    if (best == nullptr || p.validationRho > best->validationRho) best = &p;
  }
  if (failed != nullptr) *failed = failures;
  return best;
}

}  // namespace th::eval
