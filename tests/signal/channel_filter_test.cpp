#include "trueaxis/signal/channel_filter.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "synthetic.hpp"

namespace trueaxis::signal {
namespace {

TEST(MedianOf, OddAndEvenCounts) {
  const double odd[] = {5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(MedianOf(odd, 5), 3);
  const double even[] = {10, 1, 4, 2};
  EXPECT_DOUBLE_EQ(MedianOf(even, 4), 3);
  const double one[] = {7};
  EXPECT_DOUBLE_EQ(MedianOf(one, 1), 7);
}

// Seed 000 asks for a stable reading to ±0.1 °C after filtering. 10 Hz, 30
// minutes of a slowly warming machine with 0.15 °C noise, 2 % spikes of 2-8 °C
// and 12-bit quantisation.
TEST(ChannelFilter, StableToTenthOfDegreeOnNoisySignalWithSpikes) {
  testing::NoisySensor sensor;
  ChannelFilter filter{FilterOptions{}};
  const double dt = 0.1;
  double worst_raw = 0, worst_filtered = 0;
  int spikes = 0;
  for (int i = 0; i < 18000; ++i) {
    const double t = i * dt;
    const double truth = 22.0 + 3.0 * (1 - std::exp(-t / 900.0)) + 0.2 * std::sin(2 * M_PI * t / 600.0);
    const double x = sensor.Sample(truth);
    const auto out = filter.Process(x, dt);
    spikes += out.spike_rejected;
    if (t < 20) continue;  // settling
    worst_raw = std::max(worst_raw, std::abs(x - truth));
    worst_filtered = std::max(worst_filtered, std::abs(out.value_c - truth));
  }
  EXPECT_GT(worst_raw, 2.0);        // the input really is bad
  EXPECT_LT(worst_filtered, 0.1);   // the output is stable to ±0.1 °C
  EXPECT_GT(spikes, 18000 * 0.015); // most of the 2 % spikes were caught
}

TEST(ChannelFilter, IsolatedSpikesNeverReachTheOutput) {
  ChannelFilter filter{FilterOptions{}};
  int rejected = 0;
  for (int i = 0; i < 500; ++i) {
    const double x = (i % 37 == 20) ? 35.0 : 25.0;
    const auto out = filter.Process(x, 0.1);
    rejected += out.spike_rejected;
    ASSERT_NEAR(out.value_c, 25.0, 1e-9) << i;
  }
  EXPECT_EQ(rejected, 500 / 37 + (500 % 37 > 20 ? 1 : 0));
}

TEST(ChannelFilter, StepPassesWithFirstOrderTimeConstant) {
  FilterOptions o;
  o.lowpass_time_constant_s = 2.0;
  ChannelFilter filter(o);
  const double dt = 0.01;
  for (int i = 0; i < 100; ++i) filter.Process(20.0, dt);
  // A lasting step is not a spike: once the Hampel and median windows are
  // half full of the new level, it passes; then the low-pass rises as 1-e^(-t/tau).
  int first_move = -1;
  double at_tau = 0;
  for (int i = 0; i < 3000; ++i) {
    const auto out = filter.Process(30.0, dt);
    if (first_move < 0 && out.value_c > 20.0 + 1e-9) first_move = i;
    if (first_move >= 0 && i == first_move + 200) at_tau = out.value_c;
  }
  ASSERT_GE(first_move, 0);
  EXPECT_LE(first_move, (o.hampel_window + o.median_window) / 2);  // delay of a few samples only
  EXPECT_NEAR((at_tau - 20.0) / 10.0, 1 - std::exp(-1.0), 0.01);
  EXPECT_NEAR(filter.value_c(), 30.0, 1e-4);
}

TEST(ChannelFilter, IrregularSamplePeriodsFilterConsistently) {
  // The same physical time with 10 ms and with 100 ms samples ends at the same value.
  FilterOptions o;
  o.hampel_window = 1;
  o.median_window = 1;
  o.lowpass_time_constant_s = 1.0;
  ChannelFilter fast(o), slow(o);
  fast.Process(0, 0);
  slow.Process(0, 0);
  for (int i = 0; i < 100; ++i) fast.Process(1.0, 0.01);
  for (int i = 0; i < 10; ++i) slow.Process(1.0, 0.1);
  EXPECT_NEAR(fast.value_c(), 1 - std::exp(-1.0), 1e-12);
  EXPECT_NEAR(slow.value_c(), fast.value_c(), 1e-12);
}

TEST(FilterOptions, Validation) {
  std::string why;
  EXPECT_TRUE(FilterOptions{}.IsValid(&why));
  FilterOptions o;
  o.median_window = 4;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("median_window"), std::string::npos);
  o = {};
  o.hampel_window = 33;
  EXPECT_FALSE(o.IsValid(&why));
  o = {};
  o.lowpass_time_constant_s = -1;
  EXPECT_FALSE(o.IsValid(&why));
  o = {};
  o.hampel_k = 0;
  EXPECT_FALSE(o.IsValid(&why));
}


// A filter copied or moved in mid-stream (as a monitor's channels are) carries on exactly as the
// original: its sample windows are its own, not the original's.
TEST(ChannelFilter, ACopyContinuesLikeTheOriginal) {
  FilterOptions o;
  o.hampel_window = 7;
  o.median_window = 5;
  ChannelFilter a(o), reference(o);
  auto sample = [](int i) { return 20.0 + 0.05 * i + (i % 9 == 0 ? 4.0 : 0.0) + 0.1 * (i % 3); };
  for (int i = 0; i < 20; ++i) {
    a.Process(sample(i), 0.1);
    reference.Process(sample(i), 0.1);
  }
  ChannelFilter b = a;                 // copied
  ChannelFilter c(o);
  c = a;                               // copy-assigned
  ChannelFilter d = ChannelFilter(a);  // moved from a temporary copy
  for (int i = 20; i < 60; ++i) {
    const double va = a.Process(sample(i), 0.1).value_c;
    ASSERT_EQ(b.Process(sample(i), 0.1).value_c, va) << i;
    ASSERT_EQ(c.Process(sample(i), 0.1).value_c, va) << i;
    ASSERT_EQ(d.Process(sample(i), 0.1).value_c, va) << i;
    reference.Process(sample(i), 0.1);
  }
  // The copies' windows are their own: what b is fed never reaches a.
  for (int i = 0; i < 10; ++i) b.Process(100.0, 0.1);
  for (int i = 60; i < 70; ++i) ASSERT_EQ(a.Process(sample(i), 0.1).value_c, reference.Process(sample(i), 0.1).value_c) << i;
  EXPECT_GT(b.value_c(), a.value_c() + 1.0);  // b took the step
}

}  // namespace
}  // namespace trueaxis::signal
