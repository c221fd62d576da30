// render::Head: what every program holds, our face or a character behind one interface. makeHead picks the kind;
// drawing through the interface gives the pictures the kinds give themselves; every kind resizes, reads back
// and finishes a frame for the video encoder alike.
#include "render/head.h"

#include <gtest/gtest.h>

#include <memory>

#include "avatar/avatar_model.h"
#include "core/data_path.h"
#include "face/face_model.h"
#include "face/fap.h"
#include "face/fap_track.h"
#include "render/animated_avatar.h"
#include "render/animated_face.h"
#include "render/gl_context.h"
#include "render/image.h"

namespace {

th::face::FapTrack openingJaw() {
  th::face::FapTrack track;
  track.faps = {3, 48, 49};
  track.values.resize(3, 10);
  for (int f = 0; f < 10; ++f) {
    track.values(0, f) = 100.0 * f;    // the jaw opens
    track.values(1, f) = 2000.0 * f;   // the head nods
    track.values(2, f) = -1500.0 * f;  // and turns
  }
  return track;
}

void expectSameImage(const th::render::Image& a, const th::render::Image& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  EXPECT_TRUE(a.pixels == b.pixels);
}

TEST(Head, OurFaceWhereThereIsNoCharacter) {
  th::render::OffscreenContext context;
  const th::face::FaceModel model = th::face::FaceModel::buildDefault();
  const std::unique_ptr<th::render::Head> head = th::render::makeHead(nullptr, context, {.width = 96, .height = 80});
  EXPECT_NE(dynamic_cast<th::render::AnimatedFace*>(head.get()), nullptr);
  EXPECT_EQ(head->description(), "");
  th::render::AnimatedFace face(model, context, {.width = 96, .height = 80});
  const th::face::FapTrack animation = openingJaw();
  const th::render::Image atRest = head->draw(animation, 0.0);
  const th::render::Image opened = head->draw(animation, 0.3);
  expectSameImage(opened, face.draw(animation.frame(9)));
  EXPECT_FALSE(opened.pixels == atRest.pixels);  // the animation moves it
}

TEST(Head, TheCharacterWhereThereIsOne) {
  const th::avatar::Avatar avatar = th::avatar::loadAvatar(th::sharedDataPath("face/avatars") / "brunette-t.glb");
  th::render::OffscreenContext context;
  const std::unique_ptr<th::render::Head> head =
      th::render::makeHead(&avatar, context, {.width = 96, .height = 80, .samples = 1, .fxaa = true});
  EXPECT_NE(dynamic_cast<th::render::AnimatedAvatar*>(head.get()), nullptr);
  EXPECT_EQ(head->description().rfind(avatar.name + " (", 0), 0u) << head->description();
  EXPECT_EQ(head->samples(), 1);
  th::render::AnimatedAvatar character(avatar, context, {.width = 96, .height = 80, .samples = 1, .fxaa = true});
  const th::face::FapTrack animation = openingJaw();
  expectSameImage(head->draw(animation, 0.3), character.draw(animation, 0.3));
}

TEST(Head, ResizesAndFinishesFramesForTheEncoder) {
  th::render::OffscreenContext context;
  const std::unique_ptr<th::render::Head> head =
      th::render::makeHead(nullptr, context, {.width = 64, .height = 48, .samples = 1, .fxaa = true});
  head->resize(80, 40);
  const th::render::Image& image = head->draw(openingJaw(), 0.1);
  EXPECT_EQ(image.width, 80);
  EXPECT_EQ(image.height, 40);
  th::render::RawFrame raw;
  head->readRaw(raw);
  th::render::Yuv420Image yuv;
  head->finish(raw, yuv, true);
  EXPECT_EQ(yuv.width, 80);
  EXPECT_EQ(yuv.height, 40);
  EXPECT_EQ(yuv.y.size(), 80u * 40u);
}

}  // namespace
