// The studio backdrop behind the head, composited under the rendered frame instead of being drawn with it.
//
// The head is drawn over a transparent clear (premultiplied alpha: 0 where nothing was drawn, partial on the
// silhouette's anti-aliased edges and under the lashes); the backdrop goes underneath afterwards. On the
// off-screen path (readPixels) that is a CPU pass over the frame it copies anyway, about half a millisecond
// at 1280x720, where llvmpipe spends several to shade a full-screen backdrop triangle; in a window
// (present), shaders/background.frag adds the same backdrop under the head with GL's "under" blending. Both
// compute the same gradient (tests/render/render_test.cpp compares them).
//
//   std::vector<std::uint8_t> backdrop = backdropPixels(1280, 720, top, bottom);   // RGB, bottom row first
//   compositeUnder(rgba.data(), backdrop.data(), 1280 * 720);                     // rgba: glReadPixels' frame
//
// Internal to the renderer (public for its tests). Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace th::render {

// The backdrop (colours in sRGB, 0..1) as RGB bytes, GL's row order (bottom row first): a vertical gradient
// from `bottom` to `top`, a soft pool of light behind the head and darker corners.
std::vector<std::uint8_t> backdropPixels(int width, int height, const Eigen::Vector3f& top,
                                         const Eigen::Vector3f& bottom);

// rgba = rgba + (1 - alpha) * backdrop, alpha becomes opaque. `rgba` is premultiplied, 4 bytes a pixel;
// `backdropRgb` 3 bytes a pixel, the same number of pixels in the same order.
void compositeUnder(std::uint8_t* rgba, const std::uint8_t* backdropRgb, std::size_t pixels);

}  // namespace th::render
