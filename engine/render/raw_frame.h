// A rendered frame between GL and the CPU, and the CPU's share of finishing it: what a renderer reads back
// (premultiplied RGBA over a transparent background), the studio backdrop composited under it, FXAA where
// asked, and the result as RGB rows or Y'CbCr planes. The face's and the characters' renderers share it.
//
//   const th::render::FrameBackdrop backdrop = th::render::makeBackdrop(1280, 720, top, bottom);
//   renderer.readRaw(raw);                                  // on the GL thread
//   th::render::finishFrame(raw, backdrop, fxaa, image);    // on any thread
//
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "render/fxaa.h"
#include "render/image.h"
#include "render/yuv.h"

namespace th::render {

// A rectangle of an image: columns [left, left + width), rows [top, top + height), rows counted from the top.
struct PixelRegion {
  int left = 0;
  int top = 0;
  int width = 0;
  int height = 0;
  bool operator==(const PixelRegion&) const = default;
};

// A frame as GL gives it back (premultiplied RGBA over a transparent background, bottom row first), before
// the CPU finishes it: what a pipeline hands from the GL thread to another (see FaceRenderer::readRaw).
struct RawFrame {
  int width = 0;  // the whole frame's size
  int height = 0;
  PixelRegion region;              // the part GL drew in (RenderOptions::cropToHead); the backdrop elsewhere
  std::vector<std::uint8_t> rgba;  // the region's pixels, 4 bytes each, bottom row first
  FxaaScratch fxaa;  // working space, kept with the frame: finishing allocates nothing after the first time
};

// The backdrop of one frame size: RGB in GL's row order, and Y'CbCr ([0] BT.601, [1] BT.709).
struct FrameBackdrop {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
  std::array<Yuv420Image, 2> yuv;
};

// Colours in sRGB, 0..1 (render/backdrop.h's gradient).
FrameBackdrop makeBackdrop(int width, int height, const Eigen::Vector3f& top, const Eigen::Vector3f& bottom);

// The backdrop under the frame's region and FXAA if asked, then RGB rows top-down or Y'CbCr; throws th::Error
// (naming `who`) if the frame is not of the backdrop's size. The frame's pixels are changed in place.
void finishFrame(RawFrame& frame, const FrameBackdrop& backdrop, bool fxaa, Image& image, const std::string& who);
void finishFrame(RawFrame& frame, const FrameBackdrop& backdrop, bool fxaa, Yuv420Image& image, bool bt709,
                 const std::string& who);

}  // namespace th::render
