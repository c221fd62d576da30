#include "tracking/dlib_faces.h"

#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>
#include <dlib/serialize.h>

#include <mutex>

namespace th::tracking {
namespace {

// What every instance reads and none changes: the detector as dlib unpacks it (from a compressed string in its
// header: a third of a second) and the shape predictor (a 100 MB file: a fifth of a second more). A video corpus
// makes a detector per clip; the last pair read is kept, so a process reads them once.
struct LoadedModels {
  dlib::frontal_face_detector detector;
  dlib::shape_predictor predictor;
};

std::shared_ptr<const LoadedModels> loadedModels(const std::filesystem::path& shapePredictor) {
  static std::mutex mutex;
  static std::filesystem::path lastPath;
  static std::shared_ptr<const LoadedModels> last;
  const std::lock_guard lock(mutex);
  if (last && lastPath == shapePredictor) return last;
  auto models = std::make_shared<LoadedModels>();
  models->detector = dlib::get_frontal_face_detector();
  dlib::deserialize(shapePredictor.string()) >> models->predictor;
  last = std::move(models);
  lastPath = shapePredictor;
  return last;
}

}  // namespace

struct DlibFaces::Models {
  std::shared_ptr<const LoadedModels> shared;
  // mutable: dlib's detector keeps scratch space, so each instance has a copy of its own (the copy is cheap).
  mutable dlib::frontal_face_detector detector;
  const dlib::shape_predictor& predictor() const { return shared->predictor; }
};

DlibFaces::DlibFaces(const std::filesystem::path& shapePredictor) : models_(std::make_unique<Models>()) {
  models_->shared = loadedModels(shapePredictor);
  models_->detector = models_->shared->detector;
}

DlibFaces::~DlibFaces() = default;

unsigned long DlibFaces::numParts() const {
  return models_->predictor().num_parts();
}

std::vector<cv::Rect> DlibFaces::detect(const cv::Mat& gray) const {
  const dlib::cv_image<unsigned char> image(gray);
  std::vector<cv::Rect> faces;
  for (const dlib::rectangle& r : models_->detector(image))
    faces.emplace_back(static_cast<int>(r.left()), static_cast<int>(r.top()), static_cast<int>(r.width()),
                       static_cast<int>(r.height()));
  return faces;
}

std::vector<cv::Point> DlibFaces::shape(const cv::Mat& gray, const cv::Rect& face) const {
  const dlib::cv_image<unsigned char> image(gray);
  const dlib::full_object_detection detection =
      models_->predictor()(image, dlib::rectangle(face.x, face.y, face.x + face.width - 1, face.y + face.height - 1));
  std::vector<cv::Point> points;
  for (unsigned long i = 0; i < detection.num_parts(); ++i)
    points.emplace_back(static_cast<int>(detection.part(i).x()), static_cast<int>(detection.part(i).y()));
  return points;
}

}  // namespace th::tracking
