#include "trueaxis/runtime/model_exchange.hpp"

#include <atomic>
#include <thread>

#include <gtest/gtest.h>

namespace trueaxis::runtime {
namespace {

std::atomic<int> g_alive{0};
std::atomic<int> g_freed_on_rt{0};
thread_local bool t_is_rt = false;

struct Tracked {
  explicit Tracked(int v) : value(v) { ++g_alive; }
  ~Tracked() {
    magic = 0;
    --g_alive;
    if (t_is_rt) ++g_freed_on_rt;
  }
  int value;
  int magic = 0x5eed;
};

TEST(ModelExchange, AcquireSeesNothingUntilPublished) {
  ModelExchange<Tracked> ex;
  EXPECT_EQ(ex.Acquire(), nullptr);
  ex.Publish(std::make_unique<Tracked>(1));
  EXPECT_TRUE(ex.Pending());
  ASSERT_NE(ex.Acquire(), nullptr);
  EXPECT_EQ(ex.Acquire()->value, 1);
  EXPECT_FALSE(ex.Pending());
}

TEST(ModelExchange, OldModelIsRetiredNotFreedByTheRtSide) {
  g_alive = 0;
  {
    ModelExchange<Tracked> ex;
    ex.Publish(std::make_unique<Tracked>(1));
    ex.Acquire();
    ex.Publish(std::make_unique<Tracked>(2));
    EXPECT_EQ(ex.Acquire()->value, 2);
    EXPECT_EQ(g_alive.load(), 2);  // 1 is retired, still alive
    EXPECT_TRUE(ex.CollectRetired());
    EXPECT_EQ(g_alive.load(), 1);
    EXPECT_FALSE(ex.CollectRetired());
  }
  EXPECT_EQ(g_alive.load(), 0);
}

TEST(ModelExchange, UnpickedModelIsReplacedByANewerOne) {
  g_alive = 0;
  ModelExchange<Tracked> ex;
  ex.Publish(std::make_unique<Tracked>(1));
  ex.Publish(std::make_unique<Tracked>(2));
  EXPECT_EQ(g_alive.load(), 1);
  EXPECT_EQ(ex.Acquire()->value, 2);
}

TEST(ModelExchange, SwitchWaitsWhileTheRetiredSlotIsFull) {
  ModelExchange<Tracked> ex;
  ex.Publish(std::make_unique<Tracked>(1));
  ex.Acquire();
  ex.Publish(std::make_unique<Tracked>(2));
  ex.Acquire();  // 1 retired, not collected
  // Publishing collects the retired one first, so the next model always gets through.
  ex.Publish(std::make_unique<Tracked>(3));
  EXPECT_EQ(ex.Acquire()->value, 3);
}

TEST(ModelExchange, ConcurrentPublishingNeverHandsOutAFreedModelNorFreesOnTheRtThread) {
  g_alive = 0;
  g_freed_on_rt = 0;
  {
    ModelExchange<Tracked> ex;
    ex.Publish(std::make_unique<Tracked>(0));
    std::atomic<bool> done{false};
    std::atomic<long> bad{0};
    std::atomic<long> switches{0};
    std::thread rt([&] {
      t_is_rt = true;
      int last = -1;
      while (!done.load()) {
        const Tracked* m = ex.Acquire();
        if (!m || m->magic != 0x5eed) ++bad;
        else if (m->value != last) {
          if (m->value < last) ++bad;  // models only move forward
          last = m->value;
          ++switches;
        }
      }
      t_is_rt = false;
    });
    for (int i = 1; i <= 20000; ++i) {
      ex.Publish(std::make_unique<Tracked>(i));
      if (i % 3 == 0) ex.CollectRetired();
      if (i % 64 == 0) std::this_thread::yield();
    }
    while (ex.Pending()) {  // the last one may wait for the retired slot to be collected
      ex.CollectRetired();
      std::this_thread::yield();
    }
    done = true;
    rt.join();
    EXPECT_EQ(bad.load(), 0);
    EXPECT_GE(switches.load(), 1);
    EXPECT_EQ(ex.Acquire()->value, 20000);
  }
  EXPECT_EQ(g_freed_on_rt.load(), 0);
  EXPECT_EQ(g_alive.load(), 0);
}

}  // namespace
}  // namespace trueaxis::runtime
