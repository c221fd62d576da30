#include "render/image.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <system_error>

#include "core/atomic_file.h"
#include "core/error.h"

namespace th::render {
namespace {

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::string*>(context);
  out->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

}  // namespace

void writePng(const std::filesystem::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw fileError(path, "cannot write an empty or inconsistent image as PNG");
  checkOutputTarget(path);
  // Encode in memory first: stb writes through a callback, and the file is written in one go.
  std::string encoded;
  if (stbi_write_png_to_func(appendBytes, &encoded, image.width, image.height, 3, image.pixels.data(),
                             image.width * 3) == 0)
    throw fileError(path, "PNG encoding failed");
  AtomicFile out(path);
  out.stream().write(encoded.data(), static_cast<std::streamsize>(encoded.size()));
  out.commit();
}

Image readPng(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) throw fileError(path, "no such file");
  // stb reads JPEG, BMP and more as well; this function promises PNG.
  char signature[8] = {};
  std::ifstream in(path, std::ios::binary);
  if (!in.read(signature, sizeof signature) || std::string_view(signature, 8) != "\x89PNG\r\n\x1a\n")
    throw fileError(path, "not a PNG file");
  in.close();
  int width = 0;
  int height = 0;
  int channels = 0;
  const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> data(
      stbi_load(path.c_str(), &width, &height, &channels, 3), &stbi_image_free);
  if (data == nullptr) {
    const char* reason = stbi_failure_reason();
    throw fileError(path, std::string("not a readable PNG (") + (reason != nullptr ? reason : "unknown") + ")");
  }
  Image image(width, height);
  std::copy(data.get(), data.get() + image.pixels.size(), image.pixels.begin());
  return image;
}

}  // namespace th::render
