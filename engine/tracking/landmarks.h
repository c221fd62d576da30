// The 68 iBUG face landmarks of a video frame, with dlib: its HOG face detector finds the face, its shape
// predictor (an ensemble of regression trees, Kazemi & Sullivan 2014, trained on iBUG 300-W; Debian's
// libdlib-data) places the points.
//
//   th::tracking::LandmarkDetector detector;            // loads the shape predictor (about a second)
//   th::tracking::Landmarks points;
//   while (video.read(frame, seconds))
//     if (detector.find(frame, points)) use(points);      // points.col(i): landmark i (0-based iBUG order)
//
// Video, not photos: the detector searches the whole frame only when it has no face; while it has one, it
// searches the region round the last face (1.6 times its size), which is several times cheaper and keeps to
// the same person when there are several. Where it finds no face there, the whole frame is searched again;
// if that fails too, find() returns false (and the next frame starts afresh). Faces smaller than the HOG
// detector's 80-pixel window are found by searching the frame enlarged twice, only when the plain search
// found nothing (and, while no face is found, on every tenth frame: it costs four plain searches).
//
// The predictor's file: LandmarkOptions::shapePredictor, else $TALKINGHEAD_SHAPE_PREDICTOR, else Debian's
// /usr/share/dlib/shape_predictor_68_face_landmarks.dat; a missing or unreadable file is a th::Error naming it.
//
// Thread contract: one thread per detector (dlib's detector keeps scratch space).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <vector>

namespace th::tracking {

inline constexpr int kNumLandmarks = 68;

// Pixels, x to the right and y down from the image's top-left corner; column i is iBUG landmark i (0-based:
// 0-16 jaw line, 17-26 brows, 27-35 nose, 36-47 eyes, 48-59 outer lips, 60-67 inner lips).
using Landmarks = Eigen::Matrix<double, 2, kNumLandmarks>;

struct LandmarkOptions {
  std::filesystem::path shapePredictor;  // empty: $TALKINGHEAD_SHAPE_PREDICTOR, else Debian's file
  double searchMargin = 0.3;             // round the last face, on each side, as a share of its size
};

// The predictor file LandmarkOptions would use for `given`.
std::filesystem::path shapePredictorPath(const std::filesystem::path& given = {});

class LandmarkDetector {
 public:
  explicit LandmarkDetector(const LandmarkOptions& options = {});
  ~LandmarkDetector();
  LandmarkDetector(const LandmarkDetector&) = delete;
  LandmarkDetector& operator=(const LandmarkDetector&) = delete;

  // The face in `bgr` (8-bit, 3 channels), followed from the last call; false when there is none.
  bool find(const cv::Mat& bgr, Landmarks& out);
  // Forget the last face (a new video).
  void reset();

  // How many find() calls searched the whole frame (the rest searched round the last face).
  int fullSearches() const { return fullSearches_; }

 private:
  struct Dlib;
  std::unique_ptr<Dlib> dlib_;
  LandmarkOptions options_;
  int fullSearches_ = 0;
};

// Landmark trajectories smoothed over time with a Savitzky-Golay filter (quadratic, 5 frames: it keeps a
// lip's quick closing, where a plain average would round it off), separately over each run of frames in which
// the face was found (`found[f]`); the first and last two frames of a run keep their values. `frames` is
// changed in place; `found` has one entry per frame.
void smoothLandmarks(std::vector<Landmarks>& frames, const std::vector<bool>& found);

}  // namespace th::tracking
