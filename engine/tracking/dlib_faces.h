// dlib's HOG face detector and 68-point shape predictor behind plain types, in a translation unit of their own
// (internal to engine/tracking; landmarks.h is the API). dlib's detection code is header templates, compiled
// into whichever file includes it; keeping it here lets the sanitizer build leave third-party code
// uninstrumented (engine/tracking/CMakeLists.txt says why) while our own tracking code is checked.
// Thread contract: one thread per instance (dlib's detector keeps scratch space).
#pragma once

#include <filesystem>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>
#include <vector>

namespace th::tracking {

class DlibFaces {
 public:
  // Reads the shape predictor; throws std::exception with dlib's message if it cannot.
  explicit DlibFaces(const std::filesystem::path& shapePredictor);
  ~DlibFaces();
  DlibFaces(const DlibFaces&) = delete;
  DlibFaces& operator=(const DlibFaces&) = delete;

  unsigned long numParts() const;
  // Faces in an 8-bit grey image: left, top, right + 1, bottom + 1 of each (pixels).
  std::vector<cv::Rect> detect(const cv::Mat& gray) const;
  // The predictor's points for `face` in `gray`, as pixel indices: x0, y0, x1, y1, ... (numParts() pairs).
  std::vector<cv::Point> shape(const cv::Mat& gray, const cv::Rect& face) const;

 private:
  struct Models;
  std::unique_ptr<Models> models_;
};

}  // namespace th::tracking
