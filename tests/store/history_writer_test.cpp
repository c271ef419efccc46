#include "trueaxis/store/history_writer.hpp"

#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "test_dir.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/store/history_db.hpp"

namespace trueaxis::store {
namespace {

using HistoryWriterTest = testing::TempDirTest;

TEST_F(HistoryWriterTest, ConcurrentProducersStoreEverythingUnderTheQueueBound) {
  constexpr int kProducers = 4, kPerProducer = 25000;
  HistoryWriterOptions o;
  o.queue_capacity = 1 << 17;  // holds everything: no drop is allowed
  {
    HistoryWriter writer(Path("h.db"), o);
    std::vector<std::thread> producers;
    for (int p = 0; p < kProducers; ++p)
      producers.emplace_back([&, p] {
        const std::string channel = "ch" + std::to_string(p);
        for (int i = 0; i < kPerProducer; ++i)
          ASSERT_TRUE(writer.PushTemperature(i * 0.01, channel, 20 + p, 20 + p + i * 1e-5, "ok"));
      });
    // Meanwhile another thread logs compensation values.
    std::thread comp([&] {
      for (int i = 0; i < 1000; ++i) writer.PushCompensation(i * 0.01, "X", i, -i * 0.1, "active");
    });
    for (auto& t : producers) t.join();
    comp.join();
    writer.PushAlarm(5, "warning", "x_nut", "stuck");
    writer.PushModelChange(6, std::string(64, 'f'), "r1", "first model");
    writer.Flush();
    const auto s = writer.Stats();
    EXPECT_EQ(s.dropped, 0u);
    EXPECT_EQ(s.failed, 0u) << s.last_error;
    EXPECT_EQ(s.accepted, kProducers * kPerProducer + 1002u);
    EXPECT_EQ(s.written, s.accepted);
    EXPECT_GT(s.batches, 0u);
    EXPECT_NE(s.BriefReport().find("0 dropped"), std::string::npos);
  }
  HistoryDb db(Path("h.db"), HistoryDb::Mode::kReadOnly);
  const auto summary = db.Summary();
  EXPECT_EQ(summary.temperature.rows, kProducers * kPerProducer);
  for (const auto& [name, n] : summary.readings_per_channel) EXPECT_EQ(n, kPerProducer) << name;
  EXPECT_EQ(summary.compensation.rows, 1000);
  EXPECT_EQ(summary.alarm.rows, 1);
  EXPECT_EQ(summary.model_change.rows, 1);
  // Per channel, every sample is there with its own values.
  const auto ch2 = db.QueryTemperatures({}, {"ch2"});
  ASSERT_EQ(ch2.size(), static_cast<std::size_t>(kPerProducer));
  for (int i = 0; i < kPerProducer; i += 997) EXPECT_DOUBLE_EQ(ch2[i].filtered_c, 22 + i * 1e-5);
}

TEST_F(HistoryWriterTest, FullQueueDropsAndCountsButNeverLosesAcceptedRecords) {
  HistoryWriterOptions o;
  o.queue_capacity = 16;
  o.idle_wait_ms = 200;  // the writer is asleep while we burst
  HistoryWriter writer(Path("h.db"), o);
  writer.Flush();
  int ok = 0;
  for (int i = 0; i < 5000; ++i) ok += writer.PushTemperature(i, "a", 20, 20, "ok");
  writer.Flush();
  const auto s = writer.Stats();
  EXPECT_EQ(s.accepted + s.dropped, 5000u);
  EXPECT_EQ(s.accepted, static_cast<std::uint64_t>(ok));
  EXPECT_GT(s.dropped, 0u);
  EXPECT_EQ(s.written, s.accepted);
  writer.Close();
  HistoryDb db(Path("h.db"), HistoryDb::Mode::kReadOnly);
  EXPECT_EQ(static_cast<std::uint64_t>(db.Summary().temperature.rows), s.accepted);
}

TEST_F(HistoryWriterTest, CloseDrainsTheQueue) {
  {
    HistoryWriter writer(Path("h.db"));
    for (int i = 0; i < 3000; ++i) writer.PushTemperature(i, "a", 20, 20, "ok");
  }  // destructor: drain + commit
  HistoryDb db(Path("h.db"), HistoryDb::Mode::kReadOnly);
  EXPECT_EQ(db.Summary().temperature.rows, 3000);
}

TEST_F(HistoryWriterTest, RefusesForeignFileAndBadOptions) {
  WriteTextFile(Path("notes.db"), "shopping list: bearings, coolant\n");
  EXPECT_THROW(HistoryWriter(Path("notes.db")), InputError);
  EXPECT_EQ(ReadTextFile(Path("notes.db")), "shopping list: bearings, coolant\n");
  HistoryWriterOptions o;
  o.max_batch = 0;
  EXPECT_THROW(HistoryWriter(Path("h.db"), o), std::invalid_argument);
  std::string why;
  o = {};
  o.queue_capacity = 1;
  EXPECT_FALSE(o.IsValid(&why));
}

}  // namespace
}  // namespace trueaxis::store
