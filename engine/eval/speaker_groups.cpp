#include "eval/speaker_groups.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "core/parallel_for.h"
#include "features/online_features.h"
#include "tracking/track.h"
#include "tracking/video_reader.h"
#include "tracking/video_training.h"

namespace th::eval {
namespace {

// The landmarks kept for the face's shape: the jaw line's upper parts (0-4, 12-16), the brows (17-26), the nose
// (27-35) and the eyes (36-47); the chin and the mouth move as the person speaks.
std::vector<int> shapePoints() {
  std::vector<int> points;
  for (int i = 0; i < 48; ++i)
    if (i < 5 || i > 11) points.push_back(i);
  return points;
}

Eigen::VectorXd faceShapeOf(const tracking::Track& track) {
  const std::vector<int> points = shapePoints();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(points.size()));
  int frames = 0;
  for (const tracking::TrackedFrame& frame : track.frames) {
    if (!frame.found) continue;
    const auto& l = frame.landmarks;  // 2 x 68
    const Eigen::Vector2d left = l.middleCols(36, 6).rowwise().mean();
    const Eigen::Vector2d right = l.middleCols(42, 6).rowwise().mean();
    const Eigen::Vector2d centre = 0.5 * (left + right);
    const Eigen::Vector2d axis = right - left;
    const double distance = axis.norm();
    if (distance <= 0.0) continue;
    const double c = axis.x() / distance, s = axis.y() / distance;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Eigen::Vector2d p = l.col(points[k]) - centre;
      sum[2 * static_cast<Eigen::Index>(k)] += (c * p.x() + s * p.y()) / distance;
      sum[2 * static_cast<Eigen::Index>(k) + 1] += (-s * p.x() + c * p.y()) / distance;
    }
    ++frames;
  }
  if (frames == 0) throw Error("no frame with a face");
  return sum / frames;
}

Eigen::VectorXd coloursOf(const std::filesystem::path& video) {
  tracking::VideoReader reader(video);
  cv::Mat frame, kept;
  double seconds = 0.0;
  for (int f = 0; f < 9 && reader.read(frame, seconds); ++f) kept = frame;
  Eigen::VectorXd colours(27);
  const int rows = kept.rows / 3, cols = kept.cols / 3;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const cv::Scalar mean = cv::mean(kept(cv::Rect(j * cols, i * rows, cols, rows)));
      for (int c = 0; c < 3; ++c) colours[(i * 3 + j) * 3 + c] = mean[c];
    }
  return colours;
}

void voiceOf(const TalkingClip& clip, ClipIdentity& identity) {
  const audio::AudioClip sound = tracking::readClipSound(clip.clip.video);
  const features::FeatureMatrix rows = features::computeFeatures(sound.samples);
  std::vector<double> pitch, level;
  for (int t = 0; t < rows.numFrames(); ++t) {
    const double f0 = rows.row(t)[features::FeatureLayout::kF0Hz];
    if (f0 > 0.0) pitch.push_back(std::log(f0));
    level.push_back(rows.levelDb[static_cast<std::size_t>(t)]);
  }
  identity.logPitch = std::numeric_limits<double>::quiet_NaN();
  if (!pitch.empty()) {
    std::nth_element(pitch.begin(), pitch.begin() + static_cast<long>(pitch.size() / 2), pitch.end());
    identity.logPitch = pitch[pitch.size() / 2];
  }
  std::vector<double> sorted = level;
  std::sort(sorted.begin(), sorted.end());
  const double loud = sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(0.3 * static_cast<double>(sorted.size()))];
  identity.spectrum = Eigen::VectorXd::Zero(rows.layout.numMfcc);
  int count = 0;
  for (int t = 0; t < rows.numFrames(); ++t) {
    if (level[static_cast<std::size_t>(t)] < loud) continue;
    for (int k = 0; k < rows.layout.numMfcc; ++k)
      identity.spectrum[k] += rows.row(t)[static_cast<std::size_t>(features::FeatureLayout::kMfccBegin + k)];
    ++count;
  }
  if (count > 0) identity.spectrum /= count;
}

// Rows: clips; the first `components` principal components of the columns, each scaled to unit variance.
Eigen::MatrixXd whitened(const Eigen::MatrixXd& data, int components) {
  const Eigen::MatrixXd centred = data.rowwise() - data.colwise().mean();
  const Eigen::MatrixXd covariance = centred.transpose() * centred / std::max<double>(1.0, double(data.rows() - 1));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
  const int k = std::min<int>(components, static_cast<int>(data.cols()));
  Eigen::MatrixXd out(data.rows(), k);
  for (int c = 0; c < k; ++c) {
    const Eigen::Index column = data.cols() - 1 - c;  // eigenvalues ascend
    const double deviation = std::sqrt(std::max(solver.eigenvalues()[column], 1e-12));
    out.col(c) = centred * solver.eigenvectors().col(column) / deviation;
  }
  return out;
}

Eigen::MatrixXd zScores(const Eigen::MatrixXd& data) {
  const Eigen::RowVectorXd mean = data.colwise().mean();
  Eigen::MatrixXd centred = data.rowwise() - mean;
  for (Eigen::Index c = 0; c < data.cols(); ++c) {
    const double deviation = std::sqrt(centred.col(c).squaredNorm() / std::max<double>(1.0, double(data.rows())));
    if (deviation > 1e-12) centred.col(c) /= deviation;
  }
  return centred;
}

// Ward's linkage over the rows of x: merge the two clusters whose union adds the least within-cluster variance
// (Lance-Williams update on squared distances), until `clusters` are left; labels numbered by first appearance.
// Ward keeps clusters of like sizes (average linkage leaves one cluster holding nearly everything at a coarse
// cut). O(n³) for n rows: a second for a thousand clips.
std::vector<int> wardClusters(const Eigen::MatrixXd& x, int clusters) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd distance(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) distance(i, j) = (x.row(i) - x.row(j)).squaredNorm();
  std::vector<double> size(static_cast<std::size_t>(n), 1.0);
  std::vector<bool> active(static_cast<std::size_t>(n), true);
  std::vector<Eigen::Index> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  for (Eigen::Index step = 0; step < n - clusters; ++step) {
    double best = std::numeric_limits<double>::infinity();
    Eigen::Index a = -1, b = -1;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!active[static_cast<std::size_t>(i)]) continue;
      for (Eigen::Index j = i + 1; j < n; ++j)
        if (active[static_cast<std::size_t>(j)] && distance(i, j) < best) best = distance(i, j), a = i, b = j;
    }
    const double sa = size[static_cast<std::size_t>(a)], sb = size[static_cast<std::size_t>(b)];
    for (Eigen::Index k = 0; k < n; ++k) {
      if (!active[static_cast<std::size_t>(k)] || k == a || k == b) continue;
      const double sk = size[static_cast<std::size_t>(k)];
      distance(a, k) = distance(k, a) =
          ((sa + sk) * distance(a, k) + (sb + sk) * distance(b, k) - sk * distance(a, b)) / (sa + sb + sk);
    }
    size[static_cast<std::size_t>(a)] = sa + sb;
    active[static_cast<std::size_t>(b)] = false;
    parent[static_cast<std::size_t>(b)] = a;
  }
  const auto root = [&](Eigen::Index i) {
    while (parent[static_cast<std::size_t>(i)] != i) i = parent[static_cast<std::size_t>(i)];
    return i;
  };
  std::vector<int> label(static_cast<std::size_t>(n)), number(static_cast<std::size_t>(n), -1);
  int next = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    int& assigned = number[static_cast<std::size_t>(root(i))];
    if (assigned < 0) assigned = next++;
    label[static_cast<std::size_t>(i)] = assigned;
  }
  return label;
}

}  // namespace

std::vector<ClipIdentity> clipIdentities(const std::vector<const TalkingClip*>& clips, unsigned threads) {
  std::vector<ClipIdentity> identities(clips.size());
  parallelFor(clips.size(), threads, [&](std::size_t i) {
    const TalkingClip& clip = *clips[i];
    if (clip.trackFile.empty()) throw fileError(clip.clip.video, "has no kept track to read its face's shape from");
    try {
      identities[i].face = faceShapeOf(tracking::readTrackCsv(clip.trackFile));
    } catch (const Error& error) {
      const std::string what = error.what();
      throw what.rfind(clip.trackFile.string(), 0) == 0 ? error : fileError(clip.trackFile, what);
    }
    voiceOf(clip, identities[i]);
    identities[i].colours = coloursOf(clip.clip.video);
  });
  return identities;
}

SpeakerGroups groupSpeakers(const std::vector<ClipIdentity>& identities, const SpeakerGroupOptions& options) {
  const auto n = static_cast<Eigen::Index>(identities.size());
  if (options.families < 1 || options.speakers < options.families || options.speakers > n)
    throw Error("speaker groups: need 1 <= families <= speakers <= clips (" + std::to_string(n) + ")");
  // The descriptors on one scale.
  Eigen::MatrixXd face(n, identities.front().face.size()), colours(n, 27),
      spectrum(n, identities.front().spectrum.size());
  Eigen::MatrixXd pitch(n, 1);
  std::vector<double> knownPitch;
  for (Eigen::Index i = 0; i < n; ++i)
    if (std::isfinite(identities[static_cast<std::size_t>(i)].logPitch))
      knownPitch.push_back(identities[static_cast<std::size_t>(i)].logPitch);
  std::sort(knownPitch.begin(), knownPitch.end());
  const double medianPitch = knownPitch.empty() ? 0.0 : knownPitch[knownPitch.size() / 2];
  for (Eigen::Index i = 0; i < n; ++i) {
    const ClipIdentity& id = identities[static_cast<std::size_t>(i)];
    face.row(i) = id.face.transpose();
    colours.row(i) = id.colours.transpose();
    spectrum.row(i) = id.spectrum.transpose();
    pitch(i, 0) = std::isfinite(id.logPitch) ? id.logPitch : medianPitch;
  }
  const Eigen::MatrixXd f = options.faceWeight * whitened(face, options.faceComponents);
  const Eigen::MatrixXd c = options.colourWeight * whitened(colours, options.colourComponents);
  const Eigen::MatrixXd s = options.spectrumWeight * zScores(spectrum);
  const Eigen::MatrixXd p = options.pitchWeight * zScores(pitch);
  Eigen::MatrixXd x(n, f.cols() + c.cols() + s.cols() + p.cols());
  x << f, c, s, p;

  // Families by the voice's pitch alone: a person's pitch does not change with the studio or the camera, so
  // all of a person's clips fall in one family (with two families: men's and women's voices).
  SpeakerGroups groups;
  groups.family = wardClusters(zScores(pitch), options.families);
  // Speaker groups within each family, as many as its share of the clips, from everything known of them.
  groups.speaker.assign(static_cast<std::size_t>(n), -1);
  int next = 0;
  for (int family = 0; family < options.families; ++family) {
    std::vector<Eigen::Index> members;
    for (Eigen::Index i = 0; i < n; ++i)
      if (groups.family[static_cast<std::size_t>(i)] == family) members.push_back(i);
    if (members.empty()) continue;
    const int share =
        std::clamp(static_cast<int>(std::lround(static_cast<double>(options.speakers) *
                                                static_cast<double>(members.size()) / static_cast<double>(n))),
                   1, static_cast<int>(members.size()));
    Eigen::MatrixXd own(static_cast<Eigen::Index>(members.size()), x.cols());
    for (std::size_t k = 0; k < members.size(); ++k) own.row(static_cast<Eigen::Index>(k)) = x.row(members[k]);
    const std::vector<int> labels = wardClusters(own, share);
    for (std::size_t k = 0; k < members.size(); ++k)
      groups.speaker[static_cast<std::size_t>(members[k])] = next + labels[k];
    next += share;
  }
  return groups;
}

}  // namespace th::eval
