// A frame in the form an H.264 encoder takes: 8-bit Y'CbCr 4:2:0, limited ("TV") range, BT.709 or BT.601,
// converted straight from GL's read-back (RGBA, bottom row first) in one pass. The export hands these planes
// to formats::Mp4Writer (Yuv420Planes), skipping libswscale's separate pass over the frame; a test holds the
// result to libswscale's own conversion.
//
//   th::render::Yuv420Image yuv;
//   th::render::rgbaToYuv420(rgba.data(), 1280, 720, /*bt709=*/true, yuv);
//   writer.addVideoFrame(yuv.planes());
//
// Thread contract: a pure function; an image is a value.
#pragma once

#include <cstdint>
#include <vector>

#include "formats/mp4_writer.h"

namespace th::render {

struct Yuv420Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> y;   // width x height
  std::vector<std::uint8_t> cb;  // (width + 1) / 2 x (height + 1) / 2
  std::vector<std::uint8_t> cr;

  int chromaWidth() const { return (width + 1) / 2; }
  formats::Yuv420Planes planes() const { return {y.data(), width, cb.data(), cr.data(), chromaWidth()}; }
};

// Y' of each pixel; Cb and Cr of each 2 x 2 block's mean colour (the MPEG-2/H.264 "centre" siting, as
// libswscale's default). Rows are flipped to top-down. `out` is resized only if its size differs.
void rgbaToYuv420(const std::uint8_t* rgba, int width, int height, bool bt709, Yuv420Image& out);

// The same for a block of a larger image: `rgba` (width x height, GL's rows) goes into `out`, which keeps its
// size and the rest of its planes, with its top-left pixel at (left, top) of the image. The block must cover
// whole 2 x 2 chroma blocks: left and top even, width and height even unless the block ends at the image's
// edge. Throws th::Error otherwise.
void rgbaToYuv420(const std::uint8_t* rgba, int width, int height, bool bt709, Yuv420Image& out, int left, int top);

}  // namespace th::render
