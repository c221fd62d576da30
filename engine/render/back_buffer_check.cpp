#include "render/back_buffer_check.h"

#include <glad/gl.h>

#include <algorithm>
#include <array>
#include <cstdint>

namespace th::render {
namespace {

// An unlikely colour: a panel's own pixel is not mistaken for the mark.
constexpr std::array<std::uint8_t, 3> kMark{17, 201, 83};

}  // namespace

void BackBufferCheck::tick() {
  if (state_ == State::kKept && std::chrono::steady_clock::now() - checkedAt_ > std::chrono::seconds(10))
    state_ = State::kToMark;
}

void BackBufferCheck::mark(std::pair<int, int> size) {
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, size.second - 1, 1, 1);
  glClearColor(kMark[0] / 255.0f, kMark[1] / 255.0f, kMark[2] / 255.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  state_ = State::kToRead;
}

bool BackBufferCheck::read(std::pair<int, int> size) {
  std::array<std::uint8_t, 4> pixel{};
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, size.second - 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel.data());
  const bool found = std::equal(kMark.begin(), kMark.end(), pixel.begin());
  checkedAt_ = std::chrono::steady_clock::now();
  const bool first = !reported_;
  reported_ = true;
  state_ = found ? State::kKept : State::kNotKept;
  return first || !found;
}

}  // namespace th::render
