// The user's characters drawn: both test avatars framed on the head, textured, opening the mouth, blinking and
// turning the head in the picture; their images written to TALKINGHEAD_AVATAR_PNG (a folder) when set, to look at.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "avatar/avatar_model.h"
#include "core/data_path.h"
#include "face/fap.h"
#include "render/avatar_renderer.h"
#include "render/gl_context.h"
#include "render/image.h"

namespace {

using th::render::Image;

struct Shown {
  Image rest, open, blink, turned;
};

// The mean absolute difference of two images over a rectangle (fractions of the size), 0..255.
double meanDifference(const Image& a, const Image& b, double x0, double y0, double x1, double y1) {
  double sum = 0.0;
  int count = 0;
  for (int y = static_cast<int>(y0 * a.height); y < static_cast<int>(y1 * a.height); ++y)
    for (int x = static_cast<int>(x0 * a.width); x < static_cast<int>(x1 * a.width); ++x) {
      for (int c = 0; c < 3; ++c) sum += std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c]);
      count += 3;
    }
  return sum / count;
}

void save(const std::string& name, const Image& image) {
  if (const char* folder = std::getenv("TALKINGHEAD_AVATAR_PNG"))
    th::render::writePng(std::filesystem::path(folder) / name, image);
}

Shown show(const std::string& file) {
  const th::avatar::Avatar avatar = th::avatar::loadAvatar(th::sharedDataPath("face/avatars") / file);
  th::render::OffscreenContext context;
  th::render::AnimatedAvatar character(avatar, context, {.width = 320, .height = 320});
  Shown shown;
  th::face::FapFrame faps{};
  std::array<float, th::face::kNumMouthClasses> classes{};
  classes[0] = 1.0f;  // silence
  shown.rest = character.draw(faps, classes.data());
  faps[3] = 1200.0;  // the jaw fully open (ARKit's jawOpen)
  classes[0] = 0.0f;
  classes[11] = 1.0f;  // aa
  shown.open = character.draw(faps, classes.data());
  faps = {};
  classes = {};
  classes[0] = 1.0f;
  faps[19] = faps[20] = 1024.0;  // both eyelids shut
  shown.blink = character.draw(faps, classes.data());
  faps = {};
  faps[49] = 20.0 * M_PI / 180.0 / 1e-5;  // head yaw 20° to its left
  shown.turned = character.draw(faps, classes.data());
  const std::string stem = std::filesystem::path(file).stem().string();
  save(stem + "_rest.png", shown.rest);
  save(stem + "_open.png", shown.open);
  save(stem + "_blink.png", shown.blink);
  save(stem + "_turned.png", shown.turned);
  return shown;
}

TEST(AvatarRender, BothCharactersAreDrawnFramedOnTheHeadAndMoveWhereTheyShould) {
  for (const std::string file : {"brunette-t.glb", "vroid.glb"}) {
    SCOPED_TRACE(file);
    const Shown shown = show(file);
    // The head fills the middle of the picture: it differs there from the backdrop's corners.
    const Image& rest = shown.rest;
    const auto* centre = rest.pixel(rest.width / 2, rest.height / 2);
    const auto* corner = rest.pixel(2, 2);
    EXPECT_GT(std::abs(centre[0] - corner[0]) + std::abs(centre[1] - corner[1]) + std::abs(centre[2] - corner[2]), 40)
        << "something drawn in the middle";
    // The mouth (lower middle) changes when it opens, the eyes (upper middle) when they close; the turn moves
    // the whole face.
    EXPECT_GT(meanDifference(rest, shown.open, 0.35, 0.5, 0.65, 0.8), 2.0);
    EXPECT_GT(meanDifference(rest, shown.blink, 0.3, 0.3, 0.7, 0.55), 1.0);
    EXPECT_GT(meanDifference(rest, shown.turned, 0.2, 0.2, 0.8, 0.8), 5.0);
    // Opening the mouth leaves the top of the head as it was.
    EXPECT_LT(meanDifference(rest, shown.open, 0.0, 0.0, 1.0, 0.25), 0.5);
  }
}

}  // namespace
