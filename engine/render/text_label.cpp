#include "render/text_label.h"

#include <stb/stb_easy_font.h>

#include <algorithm>
#include <vector>

namespace th::render {
namespace {

void blendBox(Image& image, int x0, int y0, int x1, int y1, int value, float alpha) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, image.width), y1 = std::min(y1, image.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      for (int c = 0; c < 3; ++c)
        p[c] = static_cast<std::uint8_t>((1.0f - alpha) * static_cast<float>(p[c]) + alpha * static_cast<float>(value));
    }
}

}  // namespace

void drawLabel(Image& image, int left, int top, const std::string& text, int scale) {
  std::string printable = text;
  for (char& c : printable)
    if (c < 32 || c > 126) c = ' ';
  // stb_easy_font writes 4 vertices (x, y, z, colour: 16 bytes) per quad.
  struct Vertex {
    float x, y, z;
    unsigned char colour[4];
  };
  std::vector<Vertex> vertices(printable.size() * 70 * 4 + 4);
  const int quads = stb_easy_font_print(0.0f, 0.0f, printable.data(), nullptr, vertices.data(),
                                        static_cast<int>(vertices.size() * sizeof(Vertex)));
  const int width = stb_easy_font_width(printable.data()) * scale;
  blendBox(image, left - 4, top - 4, left + width + 4, top + 12 * scale + 2, 0, 0.55f);
  for (int q = 0; q < quads; ++q) {
    const Vertex& a = vertices[static_cast<std::size_t>(4 * q)];
    const Vertex& c = vertices[static_cast<std::size_t>(4 * q + 2)];
    blendBox(image, left + static_cast<int>(a.x) * scale, top + static_cast<int>(a.y) * scale,
             left + static_cast<int>(c.x) * scale, top + static_cast<int>(c.y) * scale, 255, 1.0f);
  }
}

}  // namespace th::render
