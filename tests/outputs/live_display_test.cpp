// The display side every live path shares: the idle motion laid over the frames (blinks, gaze, the head at
// rest in pauses), the head angles kept with the head FAPs, and each frame sent once to the outputs.
#include "outputs/live_display.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace th::outputs {
namespace {

struct CountingOutput final : LiveOutput {
  explicit CountingOutput(std::vector<AvatarFrame>* received) : received_(received) {}
  void send(const AvatarFrame& frame) override { received_->push_back(frame); }
  OutputStatus status() const override {
    OutputStatus status;
    status.name = "counting";
    return status;
  }
  std::vector<AvatarFrame>* received_;
};

pipeline::AnimationFrame frameAt(int index, double levelDb, double yawDegrees) {
  pipeline::AnimationFrame frame;
  frame.index = index;
  frame.timeSeconds = index / 30.0;
  frame.levelDb = levelDb;
  frame.faps[49] = yawDegrees * M_PI / 180.0 * 1e5;  // FAP 49, the yaw, in 1e-5 rad
  return frame;
}

TEST(LiveDisplay, BlinksLooksAroundRestsTheHeadInPausesAndSendsEachFrameOnce) {
  std::vector<AvatarFrame> received;
  LiveDisplay display(pipeline::IdleOptions{}, true, true);
  std::vector<std::unique_ptr<LiveOutput>> outputs;
  outputs.push_back(std::make_unique<CountingOutput>(&received));
  display.setOutputs(std::move(outputs));
  float mostClosed = 0.0f;
  double lastYaw = 0.0;
  bool gazeMoved = false;
  for (int i = 0; i < 600; ++i) {  // 10 s of speech, then 10 s of silence, every frame shown twice (60 Hz)
    const bool speech = i < 300;
    for (int shown = 0; shown < 2; ++shown) {
      pipeline::AnimationFrame frame = frameAt(i, speech ? -20.0 : -90.0, 10.0);
      display.present(frame, (2 * i + shown) / 60.0);
      mostClosed = std::max(mostClosed, static_cast<float>(frame.faps[19]));
      gazeMoved = gazeMoved || frame.faps[23] != 0.0;
      lastYaw = face::headDegreesOf(frame.faps)[1];
      if (shown == 0) {
        ASSERT_EQ(received.back().headDegrees, face::headDegreesOf(frame.faps)) << "the outputs get the head drawn";
      }
    }
  }
  EXPECT_GT(mostClosed, 0.0f) << "the lids closed at least once in 20 s";
  EXPECT_TRUE(gazeMoved);
  EXPECT_LT(std::abs(lastYaw), 1.0) << "the head came to rest in the pause";
  ASSERT_EQ(received.size(), 600U) << "each frame sent once, not at the display's rate";
  const auto blinkSent = std::max_element(received.begin(), received.end(),
                                          [](const auto& a, const auto& b) { return a.blinkLeft() < b.blinkLeft(); });
  EXPECT_GT(blinkSent->blinkLeft(), 0.5f) << "the outputs see the blinks the face shows";
  // A stream that starts again (frame 0, its clock from 0) is sent again, its clock continuing.
  pipeline::AnimationFrame again = frameAt(0, -20.0, 0.0);
  display.present(again, 0.0);
  EXPECT_EQ(received.size(), 601U);
}

TEST(LiveDisplay, IdleOffLeavesTheFramesAsDecoded) {
  pipeline::IdleOptions off;
  off.idle = false;
  LiveDisplay display(off, true, true);
  for (int i = 0; i < 300; ++i) {
    pipeline::AnimationFrame frame = frameAt(i, -90.0, 10.0);
    const pipeline::AnimationFrame decoded = frame;
    display.present(frame, i / 30.0);
    ASSERT_EQ(frame.faps, decoded.faps);
  }
}

}  // namespace
}  // namespace th::outputs
