// Values indexed by frame number from the start of a stream, of which only the recent ones need be kept: the
// live pipeline runs for hours, and each stage looks back only a few frames. forgetBefore() drops the old ones;
// indices stay those of the whole stream, and size() counts the forgotten too.
//
//   th::FrameStore<float> f0;
//   f0.push_back(120.0f);                  // frame 0
//   f0.forgetBefore(0); f0[0];            // frames >= firstKept() can be read
//
// Thread contract: one thread, as a std::deque.
#pragma once

#include <cstddef>
#include <deque>

namespace th {

template <typename T>
class FrameStore {
 public:
  void push_back(const T& value) { items_.push_back(value); }
  std::size_t size() const { return base_ + items_.size(); }  // frames stored, forgotten ones included
  bool empty() const { return size() == 0; }
  std::size_t firstKept() const { return base_; }
  std::size_t held() const { return items_.size(); }                              // frames in memory
  const T& operator[](std::size_t frame) const { return items_[frame - base_]; }  // firstKept() <= frame < size()
  T& operator[](std::size_t frame) { return items_[frame - base_]; }
  const T& back() const { return items_.back(); }
  void forgetBefore(std::size_t frame) {
    while (base_ < frame && !items_.empty()) {
      items_.pop_front();
      ++base_;
    }
  }

 private:
  std::deque<T> items_;
  std::size_t base_ = 0;
};

}  // namespace th
