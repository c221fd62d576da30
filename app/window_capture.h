// The pixels of a GLFW window's back buffer (face and panel), for screenshots: `show` and `live` save one under
// Xvfb in the tests. Thread contract: the window's context current on the calling thread.
#pragma once

#include <utility>

#include "render/image.h"

namespace th::app {

render::Image grabWindow(std::pair<int, int> framebufferSize);  // RGB, top row first

}  // namespace th::app
