// A bounded hand-off of reusable buffers from one producer thread to one consumer thread: the producer fills
// a free slot and publishes it; the consumer takes published slots in order and releases them back. The
// slots are made once, so a pipeline of big buffers (video frames) allocates nothing per item, and the
// producer can run at most `slots` items ahead. Blocking (mutex + condition variable): for worker threads,
// not for an audio callback.
//
//   th::SlotQueue<Frame> queue(3);
//   std::thread consumer([&] {
//     while (Frame* frame = queue.takePublished()) { use(*frame); queue.release(frame); }
//   });
//   for (...) { Frame* frame = queue.takeFree(); if (!frame) break; fill(*frame); queue.publish(frame); }
//   queue.close();        // the consumer drains what was published, then takePublished() returns nullptr
//   consumer.join();
//
// abort() (either side, e.g. on an error) makes every waiting and later take return nullptr at once.
// Thread contract: one producer thread (takeFree, publish), one consumer thread (takePublished, release);
// close() and abort() from any thread. The queue must outlive both threads' use of it.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <vector>

#include "core/error.h"

namespace th {

template <typename T>
class SlotQueue {
 public:
  explicit SlotQueue(std::size_t slots) : storage_(slots), free_(slots), published_(slots) {
    if (slots == 0) throw Error("SlotQueue: needs at least one slot");
    for (T& slot : storage_) free_.push(&slot);
  }
  SlotQueue(const SlotQueue&) = delete;
  SlotQueue& operator=(const SlotQueue&) = delete;

  // Producer: a slot to fill (waits while all are in use); nullptr after close() or abort().
  T* takeFree() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !free_.empty() || closed_ || aborted_; });
    return closed_ || aborted_ ? nullptr : free_.pop();
  }
  // Producer: hands a filled slot to the consumer.
  void publish(T* slot) {
    {
      std::lock_guard lock(mutex_);
      published_.push(slot);
    }
    changed_.notify_all();
  }
  // Consumer: the next published slot, in order (waits for one); nullptr once closed and drained, or aborted.
  T* takePublished() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !published_.empty() || closed_ || aborted_; });
    return aborted_ || published_.empty() ? nullptr : published_.pop();
  }
  // Consumer: gives a used slot back to the producer.
  void release(T* slot) {
    {
      std::lock_guard lock(mutex_);
      free_.push(slot);
    }
    changed_.notify_all();
  }
  // No more slots will be published; the consumer still gets those that were.
  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    changed_.notify_all();
  }
  // Stop now: both sides' takes return nullptr, published slots are dropped.
  void abort() {
    {
      std::lock_guard lock(mutex_);
      aborted_ = true;
    }
    changed_.notify_all();
  }

 private:
  // A fixed-capacity FIFO of slot pointers (never more than the number of slots: no allocation after
  // construction).
  class Ring {
   public:
    explicit Ring(std::size_t capacity) : items_(capacity) {}
    bool empty() const { return size_ == 0; }
    void push(T* item) {
      items_[(head_ + size_) % items_.size()] = item;
      ++size_;
    }
    T* pop() {
      T* item = items_[head_];
      head_ = (head_ + 1) % items_.size();
      --size_;
      return item;
    }

   private:
    std::vector<T*> items_;
    std::size_t head_ = 0;
    std::size_t size_ = 0;
  };

  std::vector<T> storage_;
  std::mutex mutex_;
  std::condition_variable changed_;
  Ring free_;
  Ring published_;
  bool closed_ = false;
  bool aborted_ = false;
};

}  // namespace th
