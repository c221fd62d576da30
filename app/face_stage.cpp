#include "face_stage.h"

#include <cstdio>

#include "core/error.h"

namespace th::app {

std::pair<int, int> parseSize(const std::string& text) {
  int width = 0, height = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &extra) != 3 || (x != 'x' && x != 'X'))
    throw Error("--size " + text + ": expected WIDTHxHEIGHT, e.g. 1280x720");
  if (width < 16 || height < 16 || width > 7680 || height > 4320)
    throw Error("--size " + text + ": each side must be 16..7680 x 16..4320 pixels");
  if (width % 2 != 0 || height % 2 != 0) throw Error("--size " + text + ": both sides must be even (H.264, 4:2:0)");
  return {width, height};
}

ProgressOptions progressAt(double framesPerSecond) {
  ProgressOptions options;
  options.unitsPerSecond = framesPerSecond;  // progress counts frames; the bar shows the real-time factor
  return options;
}

}  // namespace th::app
