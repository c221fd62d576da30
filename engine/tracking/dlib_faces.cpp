#include "tracking/dlib_faces.h"

#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_processing/shape_predictor.h>
#include <dlib/opencv/cv_image.h>
#include <dlib/serialize.h>

namespace th::tracking {

struct DlibFaces::Models {
  // mutable: dlib's detector and predictor calls are not const (scratch space), ours are.
  mutable dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
  dlib::shape_predictor predictor;
};

DlibFaces::DlibFaces(const std::filesystem::path& shapePredictor) : models_(std::make_unique<Models>()) {
  dlib::deserialize(shapePredictor.string()) >> models_->predictor;
}

DlibFaces::~DlibFaces() = default;

unsigned long DlibFaces::numParts() const {
  return models_->predictor.num_parts();
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
      models_->predictor(image, dlib::rectangle(face.x, face.y, face.x + face.width - 1, face.y + face.height - 1));
  std::vector<cv::Point> points;
  for (unsigned long i = 0; i < detection.num_parts(); ++i)
    points.emplace_back(static_cast<int>(detection.part(i).x()), static_cast<int>(detection.part(i).y()));
  return points;
}

}  // namespace th::tracking
