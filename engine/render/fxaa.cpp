#include "render/fxaa.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>

#include "core/error.h"

namespace th::render {
namespace {

struct Rgb {
  float r = 0.0f;
  float g = 0.0f;
  float b = 0.0f;
};

float lumaOf(const Rgb& c) {
  return 0.299f * c.r + 0.587f * c.g + 0.114f * c.b;
}

// Bilinear sample at (x + ox, y + oy) in pixels, clamped to the frame's edges; GL's orientation. The whole
// and fractional parts are taken from the offsets alone, so that the result does not depend on where in a
// larger image the frame lies (float rounding of x + ox would).
Rgb sample(const std::uint8_t* rgba, int width, int height, int x, int y, float ox, float oy) {
  const float floorX = std::floor(ox);
  const float floorY = std::floor(oy);
  int x0 = x + static_cast<int>(floorX);
  int y0 = y + static_cast<int>(floorY);
  float fx = ox - floorX;
  float fy = oy - floorY;
  // Beyond an edge: the edge pixel itself.
  if (x0 < 0 || x0 >= width - 1) {
    x0 = std::clamp(x0, 0, width - 1);
    fx = 0.0f;
  }
  if (y0 < 0 || y0 >= height - 1) {
    y0 = std::clamp(y0, 0, height - 1);
    fy = 0.0f;
  }
  const int x1 = std::min(x0 + 1, width - 1);
  const int y1 = std::min(y0 + 1, height - 1);
  const auto at = [&](int px, int py) {
    return rgba + (static_cast<std::size_t>(py) * static_cast<std::size_t>(width) + static_cast<std::size_t>(px)) * 4;
  };
  const std::uint8_t* a = at(x0, y0);
  const std::uint8_t* b = at(x1, y0);
  const std::uint8_t* c = at(x0, y1);
  const std::uint8_t* d = at(x1, y1);
  const float wa = (1.0f - fx) * (1.0f - fy);
  const float wb = fx * (1.0f - fy);
  const float wc = (1.0f - fx) * fy;
  const float wd = fx * fy;
  const float scale = 1.0f / 255.0f;
  return {(wa * a[0] + wb * b[0] + wc * c[0] + wd * d[0]) * scale,
          (wa * a[1] + wb * b[1] + wc * c[1] + wd * d[1]) * scale,
          (wa * a[2] + wb * b[2] + wc * c[2] + wd * d[2]) * scale};
}

std::uint8_t toByte(float v) {
  return static_cast<std::uint8_t>(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f));
}

}  // namespace

void copyToImage(const std::uint8_t* rgba, int width, int height, Image& out) {
  if (out.width != width || out.height != height) out.resize(width, height);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* in = rgba + static_cast<std::size_t>(height - 1 - y) * static_cast<std::size_t>(width) * 4;
    std::uint8_t* o = out.pixel(0, y);
    for (int x = 0; x < width; ++x, in += 4, o += 3) {
      o[0] = in[0];
      o[1] = in[1];
      o[2] = in[2];
    }
  }
}

void fxaaLuma(const std::uint8_t* rgba, std::size_t pixels, std::uint8_t* luma) {
  // BT.601 weights, /256, in a loop the compiler vectorises.
  for (std::size_t i = 0; i < pixels; ++i)
    luma[i] = static_cast<std::uint8_t>((77U * rgba[4 * i] + 150U * rgba[4 * i + 1] + 29U * rgba[4 * i + 2]) >> 8);
}

void fxaaInPlace(std::uint8_t* rgba, int width, int height, FxaaScratch& scratch) {
  if (width < 3 || height < 3) return;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  scratch.luma.resize(pixels);
  fxaaLuma(rgba, pixels, scratch.luma.data());
  fxaaWithLuma(rgba, width, height, scratch);
}

void fxaaWithLuma(std::uint8_t* rgba, int width, int height, FxaaScratch& scratch) {
  if (width < 3 || height < 3) return;
  const std::size_t w = static_cast<std::size_t>(width);
  const std::vector<std::uint8_t>& luma = scratch.luma;
  if (luma.size() != w * static_cast<std::size_t>(height))
    throw Error("fxaaWithLuma: the luma is not the frame's (" + std::to_string(luma.size()) + " values for " +
                std::to_string(width) + "x" + std::to_string(height) + ")");
  // The filtered colours are collected first and written at the end: the filter must read unfiltered
  // neighbours.
  scratch.fixes.clear();
  // Rows and columns of GL's orientation (y up); the border pixels are left as they are.
  scratch.edges.resize(w);
  std::uint8_t* const edge = scratch.edges.data();
  for (int y = 1; y + 1 < height; ++y) {
    const std::uint8_t* row = luma.data() + static_cast<std::size_t>(y) * w;
    const std::uint8_t* up = row + w;
    const std::uint8_t* down = row - w;
    // The first test, for a whole row in a loop the compiler vectorises: most pixels sit in flat regions,
    // where the contrast is below max(1/24, max/8), i.e. 8 * (max - min) < max(255/3, max).
    for (std::size_t x = 1; x + 1 < w; ++x) {
      const std::uint8_t low =
          std::min(std::min(row[x], up[x - 1]), std::min(std::min(up[x + 1], down[x - 1]), down[x + 1]));
      const std::uint8_t high =
          std::max(std::max(row[x], up[x - 1]), std::max(std::max(up[x + 1], down[x - 1]), down[x + 1]));
      // 8 * range >= max(85, high)  <=>  range >= ceil(max(85, high) / 8) = max(11, ceil(high / 8)).
      const std::uint8_t needed =
          std::max<std::uint8_t>(11, static_cast<std::uint8_t>((high >> 3) + ((high & 7) != 0)));
      edge[x] = static_cast<std::uint8_t>(high - low) >= needed ? 1 : 0;
    }
    for (std::size_t x = 1; x + 1 < w; ++x) {
      // Skip to the next edge pixel (memchr scans in SIMD).
      const void* next = std::memchr(edge + x, 1, w - 1 - x);
      if (next == nullptr) break;
      x = static_cast<std::size_t>(static_cast<const std::uint8_t*>(next) - edge);
      const unsigned nw = up[x - 1], ne = up[x + 1], sw = down[x - 1], se = down[x + 1];
      const unsigned low = std::min(std::min(static_cast<unsigned>(row[x]), nw), std::min(std::min(ne, sw), se));
      const unsigned high = std::max(std::max(static_cast<unsigned>(row[x]), nw), std::max(std::max(ne, sw), se));
      const float scaleLuma = 1.0f / 255.0f;
      const float lumaNW = static_cast<float>(nw) * scaleLuma;
      const float lumaNE = static_cast<float>(ne) * scaleLuma;
      const float lumaSW = static_cast<float>(sw) * scaleLuma;
      const float lumaSE = static_cast<float>(se) * scaleLuma;
      const float lumaMin = static_cast<float>(low) * scaleLuma;
      const float lumaMax = static_cast<float>(high) * scaleLuma;
      // The edge runs across the steepest luma change; step along it.
      float dx = -((lumaNW + lumaNE) - (lumaSW + lumaSE));
      float dy = (lumaNW + lumaSW) - (lumaNE + lumaSE);
      const float reduce = std::max((lumaNW + lumaNE + lumaSW + lumaSE) * (0.25f / 8.0f), 1.0f / 128.0f);
      const float scale = 1.0f / (std::min(std::abs(dx), std::abs(dy)) + reduce);
      dx = std::clamp(dx * scale, -8.0f, 8.0f);
      dy = std::clamp(dy * scale, -8.0f, 8.0f);
      const auto at = [&](float t) { return sample(rgba, width, height, static_cast<int>(x), y, dx * t, dy * t); };
      const Rgb a = at(1.0f / 3.0f - 0.5f);
      const Rgb b = at(2.0f / 3.0f - 0.5f);
      const Rgb near{0.5f * (a.r + b.r), 0.5f * (a.g + b.g), 0.5f * (a.b + b.b)};
      const Rgb c = at(-0.5f);
      const Rgb d = at(0.5f);
      const Rgb wide{0.5f * near.r + 0.25f * (c.r + d.r), 0.5f * near.g + 0.25f * (c.g + d.g),
                     0.5f * near.b + 0.25f * (c.b + d.b)};
      const float lumaWide = lumaOf(wide);
      // The wide blend may reach across another edge: then keep the near one.
      const Rgb& result = lumaWide < lumaMin || lumaWide > lumaMax ? near : wide;
      scratch.fixes.push_back({static_cast<std::uint32_t>(static_cast<std::size_t>(y) * w + x),
                               {toByte(result.r), toByte(result.g), toByte(result.b)}});
    }
  }
  for (const auto& [index, colour] : scratch.fixes)
    std::copy(colour.begin(), colour.end(), rgba + 4 * std::size_t{index});
}

}  // namespace th::render
