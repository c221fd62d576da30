#include "render/culling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.h"

namespace th::render {

namespace {

// A vertex's position in the frame's vertex data (6 floats a vertex: position, then normal).
Eigen::Map<const Eigen::Vector3f> positionOf(const float* vertexData, std::uint32_t v) {
  return Eigen::Map<const Eigen::Vector3f>(vertexData + 6 * std::size_t{v});
}

// A vertex in normalised device coordinates; false if it lies behind the camera.
bool project(const float* vertexData, const Eigen::Matrix4f& viewProjection, std::uint32_t v, Eigen::Array2f& ndc) {
  const Eigen::Vector4f clip = viewProjection * positionOf(vertexData, v).homogeneous();
  if (clip.w() <= 1e-6f) return false;
  ndc = clip.head<2>().array() / clip.w();
  return true;
}

// An opening's bounding rectangle, then ellipse, in normalised device coordinates.
struct Opening {
  bool valid = false;
  Eigen::Array2f low, high;             // the bounding rectangle
  Eigen::Array2f centre, inverseRadii;  // the ellipse
};

// The opening bounded by `line` on screen; none (not valid) if `wanted` is false, the line is empty or a
// vertex of it is behind the camera.
Opening openingOnScreen(const std::vector<int>& line, bool wanted, const float* vertexData,
                        const Eigen::Matrix4f& viewProjection, int width, int height) {
  Opening r;
  r.valid = wanted && !line.empty();
  r.low = Eigen::Array2f::Constant(1e30f);
  r.high = Eigen::Array2f::Constant(-1e30f);
  for (int v : line) {
    Eigen::Array2f ndc = Eigen::Array2f::Zero();
    if (!project(vertexData, viewProjection, static_cast<std::uint32_t>(v), ndc)) {
      r.valid = false;
      break;
    }
    r.low = r.low.min(ndc);
    r.high = r.high.max(ndc);
  }
  if (r.valid) {
    const Eigen::Array2f pixel(2.0f / static_cast<float>(width), 2.0f / static_cast<float>(height));
    const Eigen::Array2f radii = 0.5f * (r.high - r.low) * 1.25f + 8.0f * pixel;
    r.centre = 0.5f * (r.low + r.high);
    r.inverseRadii = radii.inverse();
    r.low = r.centre - radii;
    r.high = r.centre + radii;
  }
  return r;
}

// Whether a triangle's bounding box (in normalised device coordinates) reaches into the opening's ellipse:
// the box's point nearest the centre, in coordinates where the ellipse is a unit circle.
bool reaches(const Opening& r, const Eigen::Array2f& lo, const Eigen::Array2f& hi) {
  if ((hi < r.low).any() || (lo > r.high).any()) return false;
  const Eigen::Array2f nearest = r.centre.max(lo).min(hi);
  return ((nearest - r.centre) * r.inverseRadii).square().sum() <= 1.0f;
}

}  // namespace

Culling::Culling(const DrawList& list, int numVertices, bool onCpu)
    : numVertices_(numVertices), onCpu_(onCpu), indices_(list.indices.size()), spans_(list.draws.size()) {}

void Culling::checkVertices(const std::vector<int>& vertices, const char* what) const {
  for (int v : vertices)
    if (v < 0 || v >= numVertices_)
      throw Error(std::string("FaceRenderer: ") + what + " vertex " + std::to_string(v) + " is not one of the mesh's " +
                  std::to_string(numVertices_));
}

void Culling::setMouthOpening(std::vector<int> innerLipVertices) {
  checkVertices(innerLipVertices, "mouth opening");
  openings_[0] = std::move(innerLipVertices);
}

void Culling::setEyeOpenings(std::vector<int> leftLidVertices, std::vector<int> rightLidVertices) {
  checkVertices(leftLidVertices, "eye opening");
  checkVertices(rightLidVertices, "eye opening");
  openings_[1] = std::move(leftLidVertices);
  openings_[2] = std::move(rightLidVertices);
}

// llvmpipe pays for every triangle it is given (vertex fetch, assembly, set-up, binning) even when it culls it
// or the depth test hides all of it. Two kinds of triangles are dropped here, on the CPU, for less:
// - those facing away from the camera, with the test GL applies (a triangle faces the viewer when the eye lies
//   on the outer side of its plane); edge-on ones (they cover no pixel) are kept for GL to decide. Two-sided
//   surfaces keep every triangle.
// - the mouth's inside (teeth, gums and tongue) and the eyeballs (sclera, iris), where they lie outside their
//   opening on screen: they are enclosed by the lips and cheeks, or the lids and the socket, so any of them
//   that shows is seen through the opening, whose projection lies within the bounding rectangle of the
//   projected lip or lid line, and within the ellipse inscribed in it: the opening is an almond or an oval
//   through the line's extreme points (the eye's corners and lid middles), which lie on that rectangle's
//   sides, not in its corners. The ellipse is widened by a quarter and 8 pixels (the line curves between its
//   vertices). With the lips nearly closed this drops most of the teeth and gums; it always drops the
//   eyeballs' parts behind the lids.
// Both only drop what GL would not draw: tests compare the images with and without this.
void Culling::select(const DrawList& list, const std::vector<float>& vertexData, const Eigen::Vector3f& eye,
                     const Eigen::Matrix4f& viewProjection, int width, int height) {
  const float* vertex = vertexData.data();
  const auto at = [&](std::uint32_t v) { return positionOf(vertex, v); };
  const auto inNdc = [&](std::uint32_t v, Eigen::Array2f& ndc) { return project(vertex, viewProjection, v, ndc); };
  // Each opening on screen: the mouth's, the left and the right eye's.
  std::array<Opening, 3> openings;
  for (std::size_t o = 0; o < openings_.size(); ++o)
    openings[o] = openingOnScreen(openings_[o], onCpu_, vertex, viewProjection, width, height);
  std::size_t written = 0;
  numTriangles_ = 0;
  for (std::size_t d = 0; d < list.draws.size(); ++d) {
    const Draw& draw = list.draws[d];
    Span& span = spans_[d];
    span.first = written;
    const std::uint32_t* triangle = list.indices.data() + draw.firstIndex;
    const std::uint32_t* end = triangle + draw.count;
    // The opening this draw is seen through, if any: the mouth's, or its eye's.
    const Opening* opening = nullptr;
    if (draw.surface == Surface::kTeeth || draw.surface == Surface::kGums)
      opening = &openings[0];
    else if ((draw.surface == Surface::kSclera || draw.surface == Surface::kIris) && draw.eye >= 0)
      opening = &openings[1 + static_cast<std::size_t>(list.eyes[static_cast<std::size_t>(draw.eye)].side)];
    if (opening != nullptr && !opening->valid) opening = nullptr;
    if (isTwoSided(draw.surface) || !onCpu_) {
      std::copy(triangle, end, indices_.begin() + static_cast<std::ptrdiff_t>(written));
      written += static_cast<std::size_t>(draw.count);
    } else {
      for (; triangle != end; triangle += 3) {
        const Eigen::Vector3f a = at(triangle[0]);
        const Eigen::Vector3f ab = at(triangle[1]) - a;
        const Eigen::Vector3f ac = at(triangle[2]) - a;
        const Eigen::Vector3f toEye = eye - a;
        // Relative margin: rounding must never drop a triangle GL would draw.
        if (ab.cross(ac).dot(toEye) < -1e-4f * ab.norm() * ac.norm() * toEye.norm()) continue;
        if (opening != nullptr) {
          Eigen::Array2f p0 = Eigen::Array2f::Zero(), p1 = p0, p2 = p0;
          if (inNdc(triangle[0], p0) && inNdc(triangle[1], p1) && inNdc(triangle[2], p2)) {
            const Eigen::Array2f lo = p0.min(p1).min(p2);
            const Eigen::Array2f hi = p0.max(p1).max(p2);
            if (!reaches(*opening, lo, hi)) continue;
          }
        }
        std::copy(triangle, triangle + 3, indices_.begin() + static_cast<std::ptrdiff_t>(written));
        written += 3;
      }
    }
    span.count = static_cast<int>(written - span.first);
    numTriangles_ += span.count / 3;
  }
  numIndices_ = written;
}

// The head's projected vertices' bounding box, widened and aligned as RenderOptions::cropToHead says; the
// whole frame if a vertex is behind the camera. GL fills a pixel only if its centre lies in a triangle, so
// the box rounded outwards holds every pixel drawn.
PixelRegion headRegion(const std::vector<float>& vertexData, const Eigen::Matrix4f& viewProjection, int width,
                       int height) {
  const PixelRegion whole{0, 0, width, height};
  float lowX = 1e30f, highX = -1e30f, lowY = 1e30f, highY = -1e30f;
  const float* vertex = vertexData.data();
  for (std::size_t v = 0; v < vertexData.size() / 6; ++v, vertex += 6) {
    const Eigen::Vector4f clip = viewProjection * Eigen::Vector4f(vertex[0], vertex[1], vertex[2], 1.0f);
    if (clip.w() <= 1e-6f) return whole;
    const float x = clip.x() / clip.w();
    const float y = clip.y() / clip.w();
    lowX = std::min(lowX, x);
    highX = std::max(highX, x);
    lowY = std::min(lowY, y);
    highY = std::max(highY, y);
  }
  return pixelRegion(lowX, lowY, highX, highY, width, height);
}

PixelRegion pixelRegion(float lowX, float lowY, float highX, float highY, int width, int height) {
  constexpr int kMargin = 8;  // FXAA's reach: its edge pixels lie next to drawn ones, its samples 4.5 further
  // Normalised device coordinates to pixels, rows from the top; clamped first, so that the casts stay in range.
  const auto toPixels = [](float ndc, float size) { return std::clamp((ndc + 1.0f) * 0.5f * size, -1e6f, 1e6f); };
  const auto fw = static_cast<float>(width);
  const auto fh = static_cast<float>(height);
  const auto evenBelow = [](int v) { return v - (v % 2 + 2) % 2; };
  const int left = std::max(0, evenBelow(static_cast<int>(std::floor(toPixels(lowX, fw))) - kMargin));
  const int top = std::max(0, evenBelow(static_cast<int>(std::floor(fh - toPixels(highY, fh))) - kMargin));
  const int right = std::min(width, evenBelow(static_cast<int>(std::ceil(toPixels(highX, fw))) + kMargin + 1));
  const int bottom = std::min(height, evenBelow(static_cast<int>(std::ceil(fh - toPixels(lowY, fh))) + kMargin + 1));
  if (right <= left || bottom <= top) return {};  // the head is out of view
  return {left, top, right - left, bottom - top};
}

}  // namespace th::render
