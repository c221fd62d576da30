// Fast approximate anti-aliasing (after Timothy Lottes' FXAA, its compact "console" form) on the CPU, applied
// while a single-sample frame is copied out of GL's read-back buffer. Where the local contrast is high it
// blends along the edge's direction; flat regions (most pixels) are copied after a look at four neighbours.
// llvmpipe runs the same filter as a full-screen shader several times slower than this loop (its texture
// sampling dominates). Internal to the renderer (public for its tests).
//
//   fxaaToImage(rgba.data(), width, height, image);   // rgba: GL's rows, bottom-up, 4 bytes a pixel
//
// Thread contract: a pure function; `luma` is scratch space, resized as needed.
#pragma once

#include <cstdint>
#include <vector>

#include "render/image.h"

namespace th::render {

// `rgba` holds width * height pixels, bottom row first (as glReadPixels gives them); `out` gets them top row
// first, RGB, filtered (resized only if its size differs).
// `luma` and `edges` are working space.
void fxaaToImage(const std::uint8_t* rgba, int width, int height, Image& out, std::vector<std::uint8_t>& luma,
                 std::vector<std::uint8_t>& edges);

// The same copy without filtering.
void copyToImage(const std::uint8_t* rgba, int width, int height, Image& out);

}  // namespace th::render
