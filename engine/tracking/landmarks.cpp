#include "tracking/landmarks.h"

#include <algorithm>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <system_error>

#include "core/error.h"
#include "tracking/dlib_faces.h"

namespace th::tracking {
namespace {

constexpr const char* kDebianShapePredictor = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";

// A face found in a frame: its detector box, in the frame's pixels.
struct Box {
  double left = 0, top = 0, right = 0, bottom = 0;
  double width() const { return right - left; }
  double height() const { return bottom - top; }
  double centreX() const { return 0.5 * (left + right); }
  double centreY() const { return 0.5 * (top + bottom); }
};

}  // namespace

std::filesystem::path shapePredictorPath(const std::filesystem::path& given) {
  if (!given.empty()) return given;
  if (const char* variable = std::getenv("TALKINGHEAD_SHAPE_PREDICTOR"); variable != nullptr && *variable != '\0')
    return variable;
  return kDebianShapePredictor;
}

struct LandmarkDetector::Dlib {
  explicit Dlib(const std::filesystem::path& shapePredictor) : faces(shapePredictor) {}
  DlibFaces faces;
  cv::Mat gray;    // the frame
  cv::Mat scaled;  // the searched region, enlarged where the face is small
  bool haveFace = false;
  Box lastFace;
  double lastScale = 1.0;     // the enlargement that found the last face
  int framesWithoutFace = 0;  // in a row, up to this frame

  // Searches `region` of `gray` enlarged `scale` times; picks the face nearest `near` (or the largest without
  // it) and puts its landmarks in `out`.
  bool search(const cv::Rect& region, double scale, const Box* near, Landmarks& out) {
    if (region.width <= 0 || region.height <= 0) return false;
    const cv::Mat crop = gray(region);
    if (scale != 1.0)
      cv::resize(crop, scaled, cv::Size(), scale, scale, cv::INTER_LINEAR);
    else
      scaled = crop;
    const std::vector<cv::Rect> found = faces.detect(scaled);
    if (found.empty()) return false;
    const auto toFrame = [&](const cv::Rect& r) {
      return Box{region.x + static_cast<double>(r.x) / scale, region.y + static_cast<double>(r.y) / scale,
                 region.x + static_cast<double>(r.x + r.width) / scale,
                 region.y + static_cast<double>(r.y + r.height) / scale};
    };
    std::size_t best = 0;
    double bestScore = -1e300;
    for (std::size_t i = 0; i < found.size(); ++i) {
      const Box box = toFrame(found[i]);
      const double score = near == nullptr
                               ? box.width() * box.height()
                               : -std::hypot(box.centreX() - near->centreX(), box.centreY() - near->centreY());
      if (score > bestScore) {
        bestScore = score;
        best = i;
      }
    }
    const std::vector<cv::Point> shape = faces.shape(scaled, found[best]);
    if (shape.size() != static_cast<std::size_t>(kNumLandmarks)) return false;
    for (int i = 0; i < kNumLandmarks; ++i) {
      const cv::Point& p = shape[static_cast<std::size_t>(i)];
      // dlib's points are pixel indices; +0.5 and back puts them on pixel centres in the frame's coordinates.
      out(0, i) = region.x + (static_cast<double>(p.x) + 0.5) / scale - 0.5;
      out(1, i) = region.y + (static_cast<double>(p.y) + 0.5) / scale - 0.5;
    }
    lastFace = toFrame(found[best]);
    lastScale = scale;
    haveFace = true;
    return true;
  }
};

LandmarkDetector::LandmarkDetector(const LandmarkOptions& options) : options_(options) {
  const std::filesystem::path path = shapePredictorPath(options.shapePredictor);
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw fileError(path,
                    "no such file (dlib's 68-landmark shape predictor: Debian's libdlib-data, or set "
                    "TALKINGHEAD_SHAPE_PREDICTOR)");
  try {
    dlib_ = std::make_unique<Dlib>(path);
  } catch (const std::exception& e) {
    // dlib's message runs over several lines: its first says what went wrong.
    const std::string message = e.what();
    throw fileError(
        path, "not a dlib shape predictor (" + message.substr(0, std::min<std::size_t>(message.find('\n'), 120)) + ")");
  }
  if (dlib_->faces.numParts() != static_cast<unsigned long>(kNumLandmarks))
    throw fileError(
        path, "a shape predictor of " + std::to_string(dlib_->faces.numParts()) + " points, not the 68 iBUG landmarks");
}

LandmarkDetector::~LandmarkDetector() = default;

void LandmarkDetector::reset() {
  dlib_->haveFace = false;
  dlib_->framesWithoutFace = 0;
}

bool LandmarkDetector::find(const cv::Mat& bgr, Landmarks& out) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw Error("LandmarkDetector: frames must be 8-bit BGR images");
  Dlib& d = *dlib_;
  cv::cvtColor(bgr, d.gray, cv::COLOR_BGR2GRAY);
  const cv::Rect frame(0, 0, d.gray.cols, d.gray.rows);
  if (d.haveFace) {
    const Box last = d.lastFace;
    const double marginX = options_.searchMargin * last.width();
    const double marginY = options_.searchMargin * last.height();
    const cv::Rect region = cv::Rect(cv::Point(static_cast<int>(std::floor(last.left - marginX)),
                                               static_cast<int>(std::floor(last.top - marginY))),
                                     cv::Point(static_cast<int>(std::ceil(last.right + marginX)),
                                               static_cast<int>(std::ceil(last.bottom + marginY)))) &
                            frame;
    if (d.search(region, d.lastScale, &last, out)) return true;
  }
  ++fullSearches_;
  // The enlarged search costs four times the plain one: while no face is found, it is tried on every tenth
  // frame only (a small face does not come and go from one frame to the next).
  const bool enlarge = d.framesWithoutFace % 10 == 0;
  if (d.search(frame, 1.0, nullptr, out) || (enlarge && d.search(frame, 2.0, nullptr, out))) {
    d.framesWithoutFace = 0;
    return true;
  }
  d.haveFace = false;
  ++d.framesWithoutFace;
  return false;
}

void smoothLandmarks(std::vector<Landmarks>& frames, const std::vector<bool>& found) {
  if (found.size() != frames.size()) throw Error("smoothLandmarks: one 'found' flag per frame is needed");
  // Savitzky-Golay, quadratic over 5 points: (-3, 12, 17, 12, -3) / 35.
  constexpr double kWeights[5] = {-3.0 / 35.0, 12.0 / 35.0, 17.0 / 35.0, 12.0 / 35.0, -3.0 / 35.0};
  const std::vector<Landmarks> original = frames;
  const std::size_t n = frames.size();
  for (std::size_t f = 2; f + 2 < n; ++f) {
    bool inRun = true;
    for (std::size_t k = f - 2; k <= f + 2; ++k) inRun = inRun && found[k];
    if (!inRun) continue;
    Landmarks sum = Landmarks::Zero();
    for (int k = 0; k < 5; ++k) sum += kWeights[k] * original[f - 2 + static_cast<std::size_t>(k)];
    frames[f] = sum;
  }
}

}  // namespace th::tracking
