#include "render/backdrop.h"

#include <algorithm>
#include <cmath>

namespace th::render {
namespace {

float smoothstep01(float x) {
  const float t = std::clamp(x, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace

std::vector<std::uint8_t> backdropPixels(int width, int height, const Eigen::Vector3f& top,
                                         const Eigen::Vector3f& bottom) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(std::max(width, 0)) *
                                   static_cast<std::size_t>(std::max(height, 0)) * 3);
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  std::uint8_t* out = pixels.data();
  // As shaders/background.frag, at pixel centres: u, v in 0..1 from the bottom-left corner.
  for (int y = 0; y < height; ++y) {
    const float v = (static_cast<float>(y) + 0.5f) / static_cast<float>(height);
    const Eigen::Vector3f row = bottom + (top - bottom) * smoothstep01(v);
    const float dy = v - 0.6f;
    for (int x = 0; x < width; ++x, out += 3) {
      const float dx = ((static_cast<float>(x) + 0.5f) / static_cast<float>(width) - 0.5f) * aspect;
      const float pool = std::clamp(1.0f - (dx * dx + dy * dy) * 1.1f, 0.0f, 1.0f);
      const float light = 0.86f + 0.24f * pool * pool;
      for (int k = 0; k < 3; ++k)
        out[k] = static_cast<std::uint8_t>(std::clamp(row[k] * light * 255.0f + 0.5f, 0.0f, 255.0f));
    }
  }
  return pixels;
}

void compositeUnder(std::uint8_t* rgba, const std::uint8_t* backdropRgb, std::size_t pixels) {
  for (std::size_t i = 0; i < pixels; ++i, rgba += 4, backdropRgb += 3) {
    // Long runs of the head (opaque) and of the background (empty) take the two cheap branches.
    const unsigned alpha = rgba[3];
    if (alpha == 255) continue;
    if (alpha == 0) {
      rgba[0] = backdropRgb[0];
      rgba[1] = backdropRgb[1];
      rgba[2] = backdropRgb[2];
    } else {
      const unsigned uncovered = 255 - alpha;
      for (int k = 0; k < 3; ++k) {
        // Exact rounding of x / 255 for x < 65536: (x + 128 + ((x + 128) >> 8)) >> 8.
        const unsigned x = uncovered * backdropRgb[k] + 128;
        rgba[k] = static_cast<std::uint8_t>(std::min(255U, rgba[k] + ((x + (x >> 8)) >> 8)));
      }
    }
    rgba[3] = 255;
  }
}

}  // namespace th::render
