// A one-line label burnt into an image (the contact sheet's captions), drawn with stb_easy_font's segment
// font: white text on a dark, translucent box, scaled by an integer factor. Only printable ASCII is drawn; other
// bytes (the ° of "20°") show as a space.
#pragma once

#include <string>

#include "render/image.h"

namespace th::app {

void drawLabel(render::Image& image, int left, int top, const std::string& text, int scale);

}  // namespace th::app
