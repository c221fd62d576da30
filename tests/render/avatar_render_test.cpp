// The user's characters drawn: both test avatars framed on the head, textured, opening the mouth, blinking and
// turning the head in the picture; their images written to TALKINGHEAD_AVATAR_PNG (a folder) when set, to look at.
#include <glad/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "avatar/avatar_model.h"
#include "core/data_path.h"
#include "face/fap.h"
#include "render/animated_avatar.h"
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

const th::avatar::Avatar& character(const std::string& file) {
  static std::map<std::string, th::avatar::Avatar> loaded;
  if (!loaded.count(file)) loaded.emplace(file, th::avatar::loadAvatar(th::sharedDataPath("face/avatars") / file));
  return loaded.at(file);
}

// Speaking, the head turned and nodded: what a frame of speech shows.
th::face::FapFrame speaking() {
  th::face::FapFrame faps{};
  faps[3] = 800.0;                         // the jaw half open
  faps[48] = 6.0 * M_PI / 180.0 / 1e-5;    // pitch
  faps[49] = -15.0 * M_PI / 180.0 / 1e-5;  // yaw
  return faps;
}

// The pixels whose largest difference in a colour channel is over `tolerance`, and that largest difference.
std::pair<int, int> differingPixels(const Image& a, const Image& b, int tolerance) {
  int count = 0, largest = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      int difference = 0;
      for (int c = 0; c < 3; ++c) difference = std::max(difference, std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c]));
      count += difference > tolerance ? 1 : 0;
      largest = std::max(largest, difference);
    }
  return {count, largest};
}

// Only what the camera sees, the opaque surfaces nearest first after a depth pass, what never moves kept from
// the frame before, the frame read back only where it was drawn: the same picture as every triangle in the
// file's order, in both the export's settings (one sample, FXAA) and MSAA's.
TEST(AvatarRender, CullingAndTheDepthPassDrawTheSamePicture) {
  for (const std::string file : {"brunette-t.glb", "vroid.glb"}) {
    for (const int samples : {1, 4}) {
      SCOPED_TRACE(file + ", samples " + std::to_string(samples));
      th::render::OffscreenContext context;
      th::render::AnimatedAvatar culled(character(file), context,
                                        {.width = 480, .height = 270, .samples = samples, .fxaa = samples == 1});
      th::render::AnimatedAvatar everything(
          character(file), context,
          {.width = 480, .height = 270, .samples = samples, .fxaa = samples == 1, .cull = false});
      culled.draw(th::face::FapFrame{}, nullptr);  // a frame before: the still layer kept from it
      const Image fast = culled.draw(speaking(), nullptr);
      const Image reference = everything.draw(speaking(), nullptr);
      const auto [count, largest] = differingPixels(fast, reference, 2);
      EXPECT_EQ(count, 0) << "largest difference " << largest;
      // Most of a whole-body character framed on its head is off-screen and not drawn.
      int triangles = 0;
      for (const auto& mesh : character(file).meshes)
        for (const auto& primitive : mesh.primitives) triangles += static_cast<int>(primitive.indices.size() / 3);
      EXPECT_EQ(everything.renderer().trianglesDrawn(), triangles);
      EXPECT_LT(culled.renderer().trianglesDrawn(), triangles);
      EXPECT_GT(culled.renderer().trianglesDrawn(), 0);
      save(std::filesystem::path(file).stem().string() + "_culled_" + std::to_string(samples) + ".png", fast);
    }
  }
}

// The window's framebuffer 0 of an OffscreenContext read back: `width` x `height`, top row first, RGB.
Image readWindow(int width, int height) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  Image image;
  image.resize(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.pixel(x, y)[c] = rgba[static_cast<std::size_t>(((height - 1 - y) * width + x) * 4 + c)];  // bottom-up
  return image;
}

// Straight into the window (no target of its own, no copy) beside a panel: the same picture as render() +
// readPixels() from column `left` on, the panel's columns kept, and the renderer's own target left as it was.
TEST(AvatarRender, DrawingStraightIntoTheWindowShowsTheSamePicture) {
  for (const std::string file : {"brunette-t.glb", "vroid.glb"}) {
    SCOPED_TRACE(file);
    constexpr int kLeft = 24, kWidth = 120, kHeight = 96;
    th::render::OffscreenContext context(kLeft + kWidth, kHeight);
    th::render::AnimatedAvatar animated(character(file), context, {.width = kWidth, .height = kHeight, .samples = 1});
    const Image picture = animated.draw(speaking(), nullptr);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, kLeft + kWidth, kHeight);
    glClearColor(1.0f, 0.0f, 1.0f, 1.0f);  // magenta: what a panel left there
    glClear(GL_COLOR_BUFFER_BIT);
    animated.renderToWindow(kLeft);
    const Image window = readWindow(kLeft + kWidth, kHeight);
    int panelKept = 0, largest = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kLeft + kWidth; ++x) {
        const std::uint8_t* shown = window.pixel(x, y);
        if (x < kLeft) {
          panelKept += shown[0] == 255 && shown[1] == 0 && shown[2] == 255 ? 1 : 0;
          continue;
        }
        for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(shown[c] - picture.pixel(x - kLeft, y)[c]));
      }
    EXPECT_EQ(panelKept, kLeft * kHeight);
    EXPECT_LE(largest, 2);  // 8-bit rounding of the blend, once or twice
    Image again;
    animated.renderer().readPixels(again);
    EXPECT_TRUE(again == picture);
  }
}

}  // namespace
