#include <atomic>
#include <cstring>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "trueaxis/store/bounded_queue.hpp"
#include "trueaxis/store/history_record.hpp"
#include "trueaxis/store/time_text.hpp"

namespace trueaxis::store {
namespace {

TEST(BoundedQueue, FifoAndFullAndEmpty) {
  BoundedQueue<int> q(5);
  EXPECT_EQ(q.capacity(), 8u);
  int v;
  EXPECT_FALSE(q.TryPop(v));
  for (int i = 0; i < 8; ++i) EXPECT_TRUE(q.TryPush(i));
  EXPECT_FALSE(q.TryPush(99));  // full: refused, not blocked
  for (int i = 0; i < 8; ++i) {
    ASSERT_TRUE(q.TryPop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(q.TryPop(v));
  // Wraps around many times.
  for (int i = 0; i < 1000; ++i) {
    ASSERT_TRUE(q.TryPush(i));
    ASSERT_TRUE(q.TryPop(v));
    ASSERT_EQ(v, i);
  }
}

TEST(BoundedQueue, ConcurrentProducersLoseNothingAndDuplicateNothing) {
  constexpr int kProducers = 4, kPerProducer = 50000;
  BoundedQueue<std::uint64_t> q(256);  // small: producers hit "full" often and retry
  std::vector<std::atomic<int>> seen(kProducers * kPerProducer);
  std::atomic<int> done{0};
  std::thread consumer([&] {
    std::uint64_t v;
    int received = 0;
    while (received < kProducers * kPerProducer) {
      if (q.TryPop(v)) {
        seen[v].fetch_add(1);
        ++received;
      } else {
        std::this_thread::yield();
      }
    }
  });
  std::vector<std::thread> producers;
  for (int p = 0; p < kProducers; ++p)
    producers.emplace_back([&, p] {
      for (int i = 0; i < kPerProducer; ++i) {
        const std::uint64_t v = static_cast<std::uint64_t>(p) * kPerProducer + i;
        while (!q.TryPush(v)) std::this_thread::yield();
      }
      done.fetch_add(1);
    });
  for (auto& t : producers) t.join();
  consumer.join();
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << i;
}

TEST(HistoryRecord, TruncatesWithoutSplittingUtf8) {
  char buf[6];
  CopyTruncated(buf, "abcdefgh");
  EXPECT_STREQ(buf, "abcde");
  CopyTruncated(buf, "ab°°");  // ° is 2 bytes: "ab" + "°" = 4 bytes, the next ° does not fit
  EXPECT_STREQ(buf, "ab°");
  CopyTruncated(buf, "abcd°");  // would need 6 bytes + NUL
  EXPECT_STREQ(buf, "abcd");
  const auto r = HistoryRecord::Temperature(12.5, "x_nut", 24.1, 24.05, "ok");
  EXPECT_EQ(r.kind, RecordKind::kTemperature);
  EXPECT_STREQ(r.name, "x_nut");
  EXPECT_STREQ(r.word, "ok");
  EXPECT_DOUBLE_EQ(r.a, 24.1);
  const std::string long_msg(500, 'm');
  const auto a = HistoryRecord::Alarm(1, "fault", "x_nut", long_msg);
  EXPECT_EQ(std::strlen(a.text), sizeof(a.text) - 1);
  static_assert(std::is_trivially_copyable_v<HistoryRecord>);
}

TEST(TimeText, FormatsAndParsesUtc) {
  EXPECT_EQ(FormatUtc(0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(FormatUtc(1795373107.25), "2026-11-22T18:45:07.250Z");
  EXPECT_EQ(ParseTimeText("1795373107.25"), 1795373107.25);
  EXPECT_EQ(ParseTimeText("2026-11-22T18:45:07.25Z"), 1795373107.25);
  EXPECT_EQ(ParseTimeText("2026-11-22 18:45:07"), 1795373107.0);
  EXPECT_EQ(ParseTimeText("2026-11-22T18:45"), 1795373100.0);
  EXPECT_EQ(ParseTimeText("2026-11-22"), 1795305600.0);
  EXPECT_EQ(ParseTimeText(" -3 "), -3.0);
  EXPECT_EQ(ParseTimeText("2026-11-23T02:45:07.25+08:00"), 1795373107.25);  // Beijing time
  EXPECT_EQ(ParseTimeText("2026-11-22T13:45:07-05:00"), 1795373107.0);
  EXPECT_FALSE(ParseTimeText("2026-11-22T13:45:07+25:00"));
  EXPECT_FALSE(ParseTimeText("yesterday"));
  EXPECT_FALSE(ParseTimeText("2026-02-31"));
  EXPECT_FALSE(ParseTimeText("2026-13-01"));
  EXPECT_FALSE(ParseTimeText("2026-11-22T25:00"));
  EXPECT_FALSE(ParseTimeText("2026-11-22X10:00"));
  EXPECT_FALSE(ParseTimeText(""));
  EXPECT_FALSE(ParseTimeText("nan"));
}

}  // namespace
}  // namespace trueaxis::store
