// An 8-bit RGB image (top row first), as the renderer reads it back, and PNG files of it.
//
//   th::render::Image image = renderer.renderImage(camera);
//   th::render::writePng("/tmp/face.png", image);           // atomic: the file is complete or absent
//   th::render::Image back = th::render::readPng("/tmp/face.png");
//   const std::uint8_t* centre = image.pixel(image.width / 2, image.height / 2);   // {r, g, b}
//
// Errors are th::Error naming the file. Thread contract: an Image is a value; the functions are reentrant.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace th::render {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 3 bytes, row by row from the top, RGB

  Image() = default;
  Image(int w, int h) : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3) {}

  // Keeps the allocation when the size does not change (the renderer's per-frame path).
  void resize(int w, int h) {
    width = w;
    height = h;
    pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  }
  std::uint8_t* pixel(int x, int y) { return pixels.data() + offset(x, y); }
  const std::uint8_t* pixel(int x, int y) const { return pixels.data() + offset(x, y); }
  bool operator==(const Image&) const = default;

 private:
  std::size_t offset(int x, int y) const {
    return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
  }
};

// Writes an 8-bit RGB PNG through a temporary file renamed into place; on failure nothing is left at `path`.
void writePng(const std::filesystem::path& path, const Image& image);

// Reads any PNG (grey, palette, alpha are converted to RGB; 16-bit is reduced to 8).
Image readPng(const std::filesystem::path& path);

}  // namespace th::render
