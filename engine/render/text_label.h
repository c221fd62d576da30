// A one-line label burnt into an image (the contact sheet's captions), drawn with stb_easy_font's segment
// font: white text on a dark, translucent box, scaled by an integer factor. Only printable ASCII is drawn; other
// bytes (the ° of "20°") show as a space.
//
//   th::render::drawLabel(sheet, left + 8, top + 8, "jaw open", 2);
//
// Thread contract: a pure function of its arguments (it changes only the image).
#pragma once

#include <string>

#include "render/image.h"

namespace th::render {

void drawLabel(Image& image, int left, int top, const std::string& text, int scale);

}  // namespace th::render
