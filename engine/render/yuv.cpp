#include "render/yuv.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace th::render {
namespace {

// Limited-range coefficients, scaled by 2^14: Y' = 16 + 219/255 (Kr R + Kg G + Kb B), Cb and Cr = 128 +
// 224/255 of the scaled colour differences. Kr, Kb: 0.2126, 0.0722 (BT.709); 0.299, 0.114 (BT.601).
struct Coefficients {
  int yr, yg, yb, ur, ug, ub, vr, vg, vb;
};

constexpr Coefficients coefficientsFor(double kr, double kb) {
  const double kg = 1.0 - kr - kb;
  const double ys = 219.0 / 255.0 * 16384.0;
  const double cs = 224.0 / 255.0 * 16384.0;
  const auto round = [](double v) { return static_cast<int>(v < 0 ? v - 0.5 : v + 0.5); };
  return {round(kr * ys),
          round(kg * ys),
          round(kb * ys),
          round(-0.5 * kr / (1.0 - kb) * cs),
          round(-0.5 * kg / (1.0 - kb) * cs),
          round(0.5 * cs),
          round(0.5 * cs),
          round(-0.5 * kg / (1.0 - kr) * cs),
          round(-0.5 * kb / (1.0 - kr) * cs)};
}

constexpr Coefficients kBt709 = coefficientsFor(0.2126, 0.0722);
constexpr Coefficients kBt601 = coefficientsFor(0.299, 0.114);

std::uint8_t clampByte(int v) {
  return static_cast<std::uint8_t>(std::clamp(v, 0, 255));
}

}  // namespace

void rgbaToYuv420(const std::uint8_t* rgba, int width, int height, bool bt709, Yuv420Image& out) {
  if (out.width != width || out.height != height) {
    out.width = width;
    out.height = height;
    out.y.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    const std::size_t chroma = static_cast<std::size_t>(out.chromaWidth()) * static_cast<std::size_t>((height + 1) / 2);
    out.cb.resize(chroma);
    out.cr.resize(chroma);
  }
  rgbaToYuv420(rgba, width, height, bt709, out, 0, 0);
}

void rgbaToYuv420(const std::uint8_t* rgba, int width, int height, bool bt709, Yuv420Image& out, int left, int top) {
  const bool endsWell =
      (left + width == out.width || width % 2 == 0) && (top + height == out.height || height % 2 == 0);
  if (left < 0 || top < 0 || left % 2 != 0 || top % 2 != 0 || width < 0 || height < 0 || left + width > out.width ||
      top + height > out.height || !endsWell)
    throw Error("rgbaToYuv420: a " + std::to_string(width) + "x" + std::to_string(height) + " block at (" +
                std::to_string(left) + ", " + std::to_string(top) + ") does not fit the 2x2 blocks of a " +
                std::to_string(out.width) + "x" + std::to_string(out.height) + " image");
  const Coefficients& k = bt709 ? kBt709 : kBt601;
  constexpr int kHalf = 1 << 13;  // rounding of the 2^14 scale
  const std::size_t w = static_cast<std::size_t>(width);
  const std::size_t lumaStride = static_cast<std::size_t>(out.width);
  // Luma, row by row (GL's bottom-up rows into the image's top-down ones): a loop the compiler vectorises.
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* in = rgba + static_cast<std::size_t>(height - 1 - y) * w * 4;
    std::uint8_t* o = out.y.data() + static_cast<std::size_t>(top + y) * lumaStride + static_cast<std::size_t>(left);
    for (std::size_t x = 0; x < w; ++x)
      o[x] = static_cast<std::uint8_t>(
          ((k.yr * in[4 * x] + k.yg * in[4 * x + 1] + k.yb * in[4 * x + 2] + kHalf) >> 14) + 16);
  }
  // Chroma from each 2 x 2 block's sum (an odd last row or column repeats itself). The even part of a row is
  // a loop without branches, which the compiler vectorises.
  const std::size_t chromaStride = static_cast<std::size_t>(out.chromaWidth());
  const int pairs = width / 2;
  const auto convert = [&](int sumR, int sumG, int sumB, std::uint8_t& cb, std::uint8_t& cr) {
    // The sums are four times the block's mean: the mean's / 4 and the 2^14 scale come off in one shift.
    cb = clampByte(((k.ur * sumR + k.ug * sumG + k.ub * sumB + (1 << 15)) >> 16) + 128);
    cr = clampByte(((k.vr * sumR + k.vg * sumG + k.vb * sumB + (1 << 15)) >> 16) + 128);
  };
  for (int cy = 0; cy < (height + 1) / 2; ++cy) {
    const int first = 2 * cy;
    const int second = std::min(first + 1, height - 1);
    const std::uint8_t* a = rgba + static_cast<std::size_t>(height - 1 - first) * w * 4;
    const std::uint8_t* b = rgba + static_cast<std::size_t>(height - 1 - second) * w * 4;
    const std::size_t at = static_cast<std::size_t>(top / 2 + cy) * chromaStride + static_cast<std::size_t>(left / 2);
    std::uint8_t* cb = out.cb.data() + at;
    std::uint8_t* cr = out.cr.data() + at;
    for (int cx = 0; cx < pairs; ++cx) {
      const std::size_t i = 8 * static_cast<std::size_t>(cx);
      const int r = a[i] + a[i + 4] + b[i] + b[i + 4];
      const int g = a[i + 1] + a[i + 5] + b[i + 1] + b[i + 5];
      const int bl = a[i + 2] + a[i + 6] + b[i + 2] + b[i + 6];
      cb[cx] =
          static_cast<std::uint8_t>(std::clamp(((k.ur * r + k.ug * g + k.ub * bl + (1 << 15)) >> 16) + 128, 0, 255));
      cr[cx] =
          static_cast<std::uint8_t>(std::clamp(((k.vr * r + k.vg * g + k.vb * bl + (1 << 15)) >> 16) + 128, 0, 255));
    }
    if (width % 2 != 0) {
      const std::size_t i = 4 * static_cast<std::size_t>(width - 1);
      convert(2 * (a[i] + b[i]), 2 * (a[i + 1] + b[i + 1]), 2 * (a[i + 2] + b[i + 2]), cb[pairs], cr[pairs]);
    }
  }
}

}  // namespace th::render
