// Fast approximate anti-aliasing (after Timothy Lottes' FXAA, its compact "console" form) on the CPU, on a
// single-sample frame as GL's read-back gives it. Where the local contrast is high it blends along the edge's
// direction; flat regions (most pixels, found by a vectorised test of four neighbours) are left alone.
// llvmpipe runs the same filter as a full-screen shader several times slower than this loop (its texture
// sampling dominates). Internal to the renderer (public for its tests).
//
//   fxaaInPlace(rgba.data(), width, height, scratch);   // rgba: GL's rows, bottom-up, 4 bytes a pixel
//   copyToImage(rgba.data(), width, height, image);     // top-down RGB
//
// Thread contract: pure functions; the scratch belongs to one call at a time.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "render/image.h"

namespace th::render {

// Working space, kept between frames so that filtering allocates nothing once it has seen a frame.
struct FxaaScratch {
  std::vector<std::uint8_t> luma;
  std::vector<std::uint8_t> edges;
  std::vector<std::pair<std::uint32_t, std::array<std::uint8_t, 3>>> fixes;  // pixel, its filtered colour
};

// Filters `rgba` (width * height pixels, 4 bytes each, any row order) in place; alpha is kept.
void fxaaInPlace(std::uint8_t* rgba, int width, int height, FxaaScratch& scratch);

// The filter in two steps, for a caller that already passes over the frame (the renderer composites the
// backdrop): the luma of `pixels` RGBA pixels as the filter sees it (BT.601 weights, in bytes), computed
// where the pixels are in cache; then the filter, with scratch.luma holding the whole frame's luma.
void fxaaLuma(const std::uint8_t* rgba, std::size_t pixels, std::uint8_t* luma);
void fxaaWithLuma(std::uint8_t* rgba, int width, int height, FxaaScratch& scratch);

// `rgba` (bottom row first, as glReadPixels gives it) into `out`, top row first, RGB (resized only if its size
// differs).
void copyToImage(const std::uint8_t* rgba, int width, int height, Image& out);

}  // namespace th::render
