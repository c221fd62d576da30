// glad before GLFW: glad's header stands in for the system GL header.
#include "window_capture.h"

#include <glad/gl.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace th::app {

render::Image grabWindow(std::pair<int, int> size) {
  render::Image image(size.first, size.second);
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(size.first) * static_cast<std::size_t>(size.second) * 4);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, size.first, size.second, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  for (int y = 0; y < size.second; ++y)
    for (int x = 0; x < size.first; ++x) {
      const std::uint8_t* source =
          rgba.data() + (static_cast<std::size_t>(size.second - 1 - y) * static_cast<std::size_t>(size.first) +
                         static_cast<std::size_t>(x)) *
                            4;
      std::copy_n(source, 3, image.pixel(x, y));
    }
  return image;
}

}  // namespace th::app
