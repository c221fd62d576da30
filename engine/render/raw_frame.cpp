#include "render/raw_frame.h"

#include <algorithm>

#include "core/error.h"
#include "render/backdrop.h"

namespace th::render {
namespace {

// Over the frame's region: the backdrop under it, then FXAA if asked (single-sample targets only). FXAA's
// luma is taken row by row as the row is composited, while it is in cache.
void prepare(RawFrame& frame, const FrameBackdrop& backdrop, bool fxaa, const std::string& who) {
  const PixelRegion& r = frame.region;
  const std::size_t regionPixels = static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height);
  const std::size_t pixels = static_cast<std::size_t>(backdrop.width) * static_cast<std::size_t>(backdrop.height);
  if (frame.width != backdrop.width || frame.height != backdrop.height || r.left < 0 || r.top < 0 || r.width < 0 ||
      r.height < 0 || r.left + r.width > frame.width || r.top + r.height > frame.height ||
      frame.rgba.size() != regionPixels * 4 || backdrop.rgb.size() != pixels * 3)
    throw Error(who + "::finish: the frame is not one of this renderer's (" + std::to_string(frame.width) + "x" +
                std::to_string(frame.height) + ")");
  if (fxaa) frame.fxaa.luma.resize(regionPixels);
  const std::size_t w = static_cast<std::size_t>(r.width);
  const int bottomRow = frame.height - r.top - r.height;  // the region's first row in GL's order
  for (int y = 0; y < r.height; ++y) {
    std::uint8_t* row = frame.rgba.data() + static_cast<std::size_t>(y) * w * 4;
    const std::uint8_t* under =
        backdrop.rgb.data() + (static_cast<std::size_t>(bottomRow + y) * static_cast<std::size_t>(frame.width) +
                               static_cast<std::size_t>(r.left)) *
                                  3;
    compositeUnder(row, under, w);
    if (fxaa) fxaaLuma(row, w, frame.fxaa.luma.data() + static_cast<std::size_t>(y) * w);
  }
  if (fxaa) fxaaWithLuma(frame.rgba.data(), r.width, r.height, frame.fxaa);
}

}  // namespace

FrameBackdrop makeBackdrop(int width, int height, const Eigen::Vector3f& top, const Eigen::Vector3f& bottom) {
  FrameBackdrop backdrop;
  backdrop.width = width;
  backdrop.height = height;
  backdrop.rgb = backdropPixels(width, height, top, bottom);
  std::vector<std::uint8_t> opaque(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 255);
  for (std::size_t i = 0; i * 3 < backdrop.rgb.size(); ++i) std::copy_n(&backdrop.rgb[3 * i], 3, &opaque[4 * i]);
  rgbaToYuv420(opaque.data(), width, height, false, backdrop.yuv[0]);
  rgbaToYuv420(opaque.data(), width, height, true, backdrop.yuv[1]);
  return backdrop;
}

void finishFrame(RawFrame& frame, const FrameBackdrop& backdrop, bool fxaa, Image& image, const std::string& who) {
  prepare(frame, backdrop, fxaa, who);
  if (image.width != frame.width || image.height != frame.height) image.resize(frame.width, frame.height);
  // Rows top-down (GL's run bottom-up): the backdrop, with the region's pixels in their place.
  const PixelRegion& r = frame.region;
  const std::size_t rowBytes = static_cast<std::size_t>(frame.width) * 3;
  for (int y = 0; y < frame.height; ++y) {
    std::uint8_t* out = image.pixel(0, y);
    std::copy_n(backdrop.rgb.data() + static_cast<std::size_t>(frame.height - 1 - y) * rowBytes, rowBytes, out);
    if (y < r.top || y >= r.top + r.height) continue;
    const std::uint8_t* in =
        frame.rgba.data() + static_cast<std::size_t>(r.top + r.height - 1 - y) * static_cast<std::size_t>(r.width) * 4;
    out += static_cast<std::size_t>(r.left) * 3;
    for (int x = 0; x < r.width; ++x, in += 4, out += 3) {
      out[0] = in[0];
      out[1] = in[1];
      out[2] = in[2];
    }
  }
}

void finishFrame(RawFrame& frame, const FrameBackdrop& backdrop, bool fxaa, Yuv420Image& image, bool bt709,
                 const std::string& who) {
  prepare(frame, backdrop, fxaa, who);
  image = backdrop.yuv[bt709 ? 1 : 0];  // the same size every frame: a copy into the planes already there
  rgbaToYuv420(frame.rgba.data(), frame.region.width, frame.region.height, bt709, image, frame.region.left,
               frame.region.top);
}

}  // namespace th::render
