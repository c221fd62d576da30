#include "core/slot_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <thread>
#include <vector>

namespace th {
namespace {

struct Item {
  int value = -1;
  std::vector<int> payload;  // touched by both threads in turn: TSan sees any missing hand-off
};

TEST(SlotQueue, DeliversEveryItemInOrderAcrossThreadsAndReusesItsSlots) {
  SlotQueue<Item> queue(3);
  constexpr int kItems = 2000;
  std::vector<int> received;
  std::set<const Item*> slotsSeen;
  std::thread consumer([&] {
    while (Item* item = queue.takePublished()) {
      EXPECT_EQ(item->payload.size(), 16U);
      EXPECT_EQ(item->payload[15], item->value * 2);
      received.push_back(item->value);
      slotsSeen.insert(item);
      item->payload.clear();
      queue.release(item);
    }
  });
  for (int i = 0; i < kItems; ++i) {
    Item* item = queue.takeFree();
    ASSERT_NE(item, nullptr);
    EXPECT_TRUE(item->payload.empty());  // the consumer finished with it before it came back
    item->value = i;
    item->payload.assign(16, i * 2);
    queue.publish(item);
  }
  queue.close();
  consumer.join();
  ASSERT_EQ(received.size(), static_cast<std::size_t>(kItems));
  for (int i = 0; i < kItems; ++i) EXPECT_EQ(received[static_cast<std::size_t>(i)], i);
  EXPECT_LE(slotsSeen.size(), 3U);
  EXPECT_EQ(queue.takeFree(), nullptr);  // closed
}

TEST(SlotQueue, TheProducerWaitsWhileEverySlotIsInUse) {
  SlotQueue<Item> queue(2);
  Item* a = queue.takeFree();
  Item* b = queue.takeFree();
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  EXPECT_NE(a, b);
  queue.publish(a);
  queue.publish(b);
  std::atomic<bool> gotThird{false};
  std::thread producer([&] {
    Item* c = queue.takeFree();  // blocks until the consumer releases one
    gotThird.store(c != nullptr);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(gotThird.load());
  Item* first = queue.takePublished();
  EXPECT_EQ(first, a);
  queue.release(first);
  producer.join();
  EXPECT_TRUE(gotThird.load());
}

TEST(SlotQueue, AbortWakesBothSidesAndDropsWhatWasPublished) {
  SlotQueue<Item> queue(1);
  Item* only = queue.takeFree();
  ASSERT_NE(only, nullptr);
  queue.publish(only);
  std::thread producer([&] { EXPECT_EQ(queue.takeFree(), nullptr); });  // waits: the one slot is published
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  queue.abort();
  producer.join();
  EXPECT_EQ(queue.takePublished(), nullptr);
}

TEST(SlotQueue, CloseLetsTheConsumerDrainThenEnds) {
  SlotQueue<Item> queue(4);
  for (int i = 0; i < 3; ++i) {
    Item* item = queue.takeFree();
    item->value = i;
    queue.publish(item);
  }
  queue.close();
  for (int i = 0; i < 3; ++i) {
    Item* item = queue.takePublished();
    ASSERT_NE(item, nullptr);
    EXPECT_EQ(item->value, i);
    queue.release(item);
  }
  EXPECT_EQ(queue.takePublished(), nullptr);
  EXPECT_THROW(SlotQueue<Item>(0), Error);
}

}  // namespace
}  // namespace th
