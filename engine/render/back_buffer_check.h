// Whether a window's back buffer keeps its pixels from one frame to the next, so that a part of the window that
// has not changed (the live window's panel column) need not be drawn again. GL leaves them undefined after a swap;
// Mesa's software path (llvmpipe under X) keeps them, a GPU's swap chain does not. So it is checked: a frame
// leaves a mark in the top-left pixel (for one frame), and the next reads it back before drawing anything.
// Found: kept; not found: not kept, from then on. Checked again after a resize (again()), and every 10 s while
// kept (a mark one pixel wide for one frame does not show).
//
//   check.tick();                                       // at the loop's top
//   if (check.reading()) reportIf(check.read(size));    // before drawing: was last frame's mark kept?
//   ... draw the column if !check.kept() or it changed ...
//   if (check.marking()) check.mark(size);              // after drawing it
//
// Thread contract: the thread whose GL context is current.
#pragma once

#include <chrono>
#include <utility>

namespace th::render {

class BackBufferCheck {
 public:
  void again() { state_ = State::kToMark; }
  bool reading() const { return state_ == State::kToRead; }
  bool kept() const { return state_ == State::kKept; }
  bool marking() const { return state_ == State::kToMark; }

  void tick();  // a kept buffer is checked again every 10 s
  void mark(std::pair<int, int> framebufferSize);
  // Reads the mark back from the default framebuffer's back buffer. True when the finding is news: the first
  // finding, and each time the buffer is found not to keep its pixels.
  bool read(std::pair<int, int> framebufferSize);

 private:
  enum class State { kToMark, kToRead, kKept, kNotKept };
  State state_ = State::kToMark;
  std::chrono::steady_clock::time_point checkedAt_;
  bool reported_ = false;
};

}  // namespace th::render
