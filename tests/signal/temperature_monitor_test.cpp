#include "trueaxis/signal/temperature_monitor.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "synthetic.hpp"

namespace trueaxis::signal {
namespace {

using hw::RawTemperature;

// Drives a monitor at a fixed period with a per-channel generator.
struct Rig {
  explicit Rig(std::vector<std::string> names, MonitorOptions o = {}) : mon(names, o), raw(names.size()) {}
  TemperatureMonitor mon;
  std::vector<RawTemperature> raw;
  double t = 0;
  double dt = 0.1;
  // Runs n samples; gen(channel, time) -> RawTemperature. Returns how many
  // times channel `watch` changed status.
  template <class Gen>
  int Run(int n, Gen gen, std::size_t watch = 0) {
    int changes = 0;
    for (int i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < raw.size(); ++c) raw[c] = gen(c, t);
      mon.Update(t, raw);
      changes += mon.reading(watch).status_changed;
      t += dt;
    }
    return changes;
  }
};

RawTemperature Ok(double c) { return {c, false}; }

TEST(TemperatureMonitor, CleanChannelsAreOkAndFilteredNearTruth) {
  Rig rig({"ambient", "x_nut", "x_bearing"});
  testing::NoisySensor noise[3];
  for (int i = 0; i < 3; ++i) noise[i].rng.seed(100 + i);
  rig.Run(3000, [&](std::size_t c, double t) { return Ok(noise[c].Sample(20.0 + c + 0.001 * t)); });
  for (std::size_t c = 0; c < 3; ++c) {
    const auto& r = rig.mon.reading(c);
    EXPECT_EQ(r.status, ChannelStatus::kOk) << c;
    EXPECT_TRUE(r.usable());
    EXPECT_NEAR(r.filtered_c, 20.0 + c + 0.001 * (rig.t - rig.dt), 0.1) << c;
    EXPECT_DOUBLE_EQ(r.last_good_c, r.filtered_c);
    EXPECT_GT(rig.mon.SpikeCount(c), 20u);
  }
  EXPECT_TRUE(rig.mon.AllUsable());
  EXPECT_NE(rig.mon.BriefReport().find("x_bearing"), std::string::npos);
}

TEST(TemperatureMonitor, HardwareFaultRaisedAfterConfirmAndRecoversAfterCleanRun) {
  MonitorOptions o;
  Rig rig({"a", "b"}, o);
  bool fault = false;
  auto gen = [&](std::size_t c, double) { return c == 0 && fault ? RawTemperature{0.0, true} : Ok(25.0); };
  rig.Run(50, gen);
  ASSERT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
  fault = true;
  rig.Run(o.faults.confirm_samples - 1, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);  // not yet confirmed
  rig.Run(1, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kHardwareFault);
  EXPECT_TRUE(rig.mon.reading(0).status_changed);
  EXPECT_FALSE(rig.mon.reading(0).usable());
  EXPECT_DOUBLE_EQ(rig.mon.reading(0).last_good_c, 25.0);  // held for fallback
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kOk);
  fault = false;
  rig.Run(o.faults.recover_samples - 1, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kHardwareFault);
  rig.Run(1, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, IntermittentFaultDoesNotChatter) {
  Rig rig({"a"});
  rig.Run(50, [](std::size_t, double) { return Ok(25.0); });
  // A loose connector: every 4th sample flagged. Never 3 in a row, so never
  // confirmed; and no status change at all.
  int i = 0;
  const int changes = rig.Run(1000, [&](std::size_t, double) { return (i++ % 4 == 0) ? RawTemperature{0, true} : Ok(25.0); });
  EXPECT_EQ(changes, 0);
  // Three out of four flagged: confirmed once, then it stays faulty (never
  // 20 clean in a row) instead of toggling every few samples.
  i = 0;
  const int changes2 = rig.Run(1000, [&](std::size_t, double) { return (i++ % 4 != 0) ? RawTemperature{0, true} : Ok(25.0); });
  EXPECT_LE(changes2, 1);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kHardwareFault);
}

TEST(TemperatureMonitor, UnderAndOverRangeWithHysteresis) {
  MonitorOptions o;
  Rig rig({"a"}, o);
  double value = 25;
  auto gen = [&](std::size_t, double) { return Ok(value); };
  rig.Run(50, gen);
  value = -30;  // shorted Pt100 through the transmitter
  rig.Run(5, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kUnderRange);
  value = 200;  // open Pt100, up-scale burn-out
  rig.Run(5, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOverRange);
  // Just back inside the limit, but not by the hysteresis band: still over range.
  value = o.faults.max_plausible_c - 0.1;
  rig.Run(100, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOverRange);
  value = 25;
  rig.Run(200, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
  EXPECT_NEAR(rig.mon.reading(0).filtered_c, 25.0, 0.01);
}

TEST(TemperatureMonitor, ImplausibleRateOfChangeDetectedThenRecovers) {
  Rig rig({"a", "b"});
  double jump = 0;
  auto gen = [&](std::size_t c, double) { return Ok(c == 0 ? 25.0 + jump : 24.0); };
  rig.Run(100, gen);
  jump = 10;  // sensor fell off onto a hot motor housing: +10 °C in one sample
  bool seen = false;
  for (int i = 0; i < 100 && !seen; ++i) {
    rig.Run(1, gen);
    seen = rig.mon.reading(0).status == ChannelStatus::kRateOfChange;
  }
  EXPECT_TRUE(seen);
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kOk);
  rig.Run(600, gen);  // the filter settles on the new level; the rate falls
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
  EXPECT_NEAR(rig.mon.reading(0).filtered_c, 35.0, 0.01);
  // A real thermal drift of 2 °C/min is never flagged.
  Rig slow({"a"});
  testing::NoisySensor n;
  const int changes = slow.Run(6000, [&](std::size_t, double t) { return Ok(n.Sample(20.0 + t / 30.0)); });
  EXPECT_EQ(changes, 1);  // no_data -> ok at the first sample only
  EXPECT_EQ(slow.mon.reading(0).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, StuckChannelWhileOthersMove) {
  MonitorOptions o;
  o.faults.stuck_window_s = 30;
  Rig rig({"frozen", "moving"}, o);
  bool frozen = true;
  testing::NoisySensor n;
  n.spike_probability = 0;
  auto gen = [&](std::size_t c, double t) {
    if (c == 0 && frozen) return Ok(24.25);  // register no longer updated
    return Ok(n.Sample(22.0 + t / 60.0));    // 1 °C/min warm-up
  };
  rig.Run(static_cast<int>(2.5 * o.faults.stuck_window_s / rig.dt), gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kStuck);
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kOk);
  frozen = false;
  rig.Run(o.faults.recover_samples + 50, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, QuietRoomIsNotStuck) {
  MonitorOptions o;
  o.faults.stuck_window_s = 30;
  Rig rig({"a", "b"}, o);
  rig.Run(3000, [](std::size_t c, double) { return Ok(20.0 + c); });  // nobody moves
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, DisagreementWithNeighbourGroup) {
  MonitorOptions o;
  o.neighbour_groups = {{"amb1", "amb2", "amb3"}};
  Rig rig({"amb1", "amb2", "amb3", "motor"}, o);
  double offset = 0;
  auto gen = [&](std::size_t c, double) { return Ok(c == 3 ? 40.0 : (c == 1 ? 21.0 + offset : 21.0 + 0.2 * c)); };
  rig.Run(100, gen);
  for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(rig.mon.reading(c).status, ChannelStatus::kOk) << c;
  offset = 5;  // amb2 drifts away from its neighbours; the motor is not in the group
  rig.Run(1000, gen);
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kDisagreement);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
  EXPECT_EQ(rig.mon.reading(2).status, ChannelStatus::kOk);
  EXPECT_EQ(rig.mon.reading(3).status, ChannelStatus::kOk);
  offset = 2.5;  // inside the limit but not inside the hysteresis band (0.7 * 3 °C)
  rig.Run(1000, gen);
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kDisagreement);
  offset = 0;
  rig.Run(1000, gen);
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, PairThatDisagreesFlagsBoth) {
  MonitorOptions o;
  o.neighbour_groups = {{"a", "b"}};
  Rig rig({"a", "b"}, o);
  rig.Run(500, [](std::size_t c, double) { return Ok(c == 0 ? 20.0 : 25.0); });
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kDisagreement);
  EXPECT_EQ(rig.mon.reading(1).status, ChannelStatus::kDisagreement);
}

TEST(TemperatureMonitor, SourceFailureBecomesNoDataAfterStaleTime) {
  MonitorOptions o;
  Rig rig({"a"}, o);
  rig.Run(10, [](std::size_t, double) { return Ok(25.0); });
  rig.mon.MarkSourceFailed(rig.t);  // a single failed read is tolerated
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
  rig.mon.MarkSourceFailed(rig.t + o.faults.stale_after_s + 0.1);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kNoData);
  EXPECT_TRUE(rig.mon.reading(0).status_changed);
  EXPECT_DOUBLE_EQ(rig.mon.reading(0).last_good_c, 25.0);
  rig.t += o.faults.stale_after_s + 0.2;
  rig.Run(1, [](std::size_t, double) { return Ok(25.0); });
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, CalibrationIsApplied) {
  Rig rig({"ref", "x_nut"});
  CalibrationSet set;
  set.reference = "ref";
  set.sensors["x_nut"].calibration = {1.02, -0.4};
  set.sensors["unknown"].calibration = {1.0, 0.0};
  const auto unknown = rig.mon.SetCalibration(set);
  ASSERT_EQ(unknown.size(), 1u);
  EXPECT_EQ(unknown[0], "unknown");
  rig.Run(200, [](std::size_t, double) { return Ok(30.0); });
  EXPECT_DOUBLE_EQ(rig.mon.reading(0).calibrated_c, 30.0);
  EXPECT_DOUBLE_EQ(rig.mon.reading(1).calibrated_c, 1.02 * 30.0 - 0.4);
  EXPECT_NEAR(rig.mon.reading(1).filtered_c, 30.2, 1e-9);
  EXPECT_DOUBLE_EQ(rig.mon.reading(1).raw_c, 30.0);
}

TEST(TemperatureMonitor, UpdateAllocatesNothing) {
  MonitorOptions o;
  o.neighbour_groups = {{"c0", "c1", "c2"}, {"c3", "c4"}};
  o.faults.stuck_window_s = 5;  // exercise the stuck window evaluation too
  std::vector<std::string> names;
  for (int i = 0; i < 8; ++i) names.push_back("c" + std::to_string(i));
  TemperatureMonitor mon(names, o);
  std::vector<RawTemperature> raw(names.size());
  testing::NoisySensor n;
  std::vector<double> truth(names.size());
  double t = 0;
  auto step = [&](int i) {
    for (std::size_t c = 0; c < raw.size(); ++c) {
      raw[c] = Ok(n.Sample(20.0 + c + 0.01 * t));
      if (c == 5 && i % 500 < 50) raw[c] = {0, true};    // hardware faults
      if (c == 6 && i % 700 < 100) raw[c] = Ok(150.0);  // over range
      if (c == 7) raw[c] = Ok(23.0);                    // stuck
      if (c == 1 && i % 900 > 400) raw[c].temp_c += 6;  // disagreement
    }
    if (i % 1000 == 999) mon.MarkSourceFailed(t + 5);
    else mon.Update(t, raw);
    t += 0.1;
  };
  for (int i = 0; i < 100; ++i) step(i);
  const long before = trueaxis::testing::AllocationCount();
  for (int i = 100; i < 19990; ++i) step(i);
  const long after = trueaxis::testing::AllocationCount();
  EXPECT_EQ(after - before, 0);
  // ... and the run did exercise the fault paths.
  EXPECT_EQ(mon.reading(7).status, ChannelStatus::kStuck);
}

TEST(TemperatureMonitor, SlowSamplingStillFilters) {
  // 15 s per sample (a slow logger) is longer than reset_filter_after_s: the
  // filter must keep its state between regular samples and still reject spikes.
  Rig rig({"a"});
  rig.dt = 15.0;
  int i = 0;
  rig.Run(60, [&](std::size_t, double) { return Ok(i++ == 40 ? 30.0 : 25.0); });
  EXPECT_EQ(rig.mon.SpikeCount(0), 1u);
  EXPECT_NEAR(rig.mon.reading(0).filtered_c, 25.0, 1e-9);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, FilterRestartsAfterALongFault) {
  Rig rig({"a"});
  bool fault = false;
  double value = 25.0;
  auto gen = [&](std::size_t, double) { return fault ? RawTemperature{0, true} : Ok(value); };
  rig.Run(100, gen);
  fault = true;
  rig.Run(200, gen);  // 20 s without a usable sample
  fault = false;
  value = 31.0;       // the part warmed up meanwhile
  rig.Run(1, gen);
  // Restarted: the first sample after the outage is taken as it is, not
  // filtered against 20 s old state (which would also look like a rate fault).
  EXPECT_DOUBLE_EQ(rig.mon.reading(0).filtered_c, 31.0);
  rig.Run(30, gen);
  EXPECT_EQ(rig.mon.reading(0).status, ChannelStatus::kOk);
}

TEST(TemperatureMonitor, RejectsBadConfiguration) {
  MonitorOptions o;
  o.neighbour_groups = {{"a", "nope"}};
  EXPECT_THROW(TemperatureMonitor({"a", "b"}, o), std::invalid_argument);
  EXPECT_THROW(TemperatureMonitor({"a", "a"}), std::invalid_argument);
  MonitorOptions bad;
  bad.faults.confirm_samples = 0;
  EXPECT_THROW(TemperatureMonitor({"a"}, bad), std::invalid_argument);
  std::string why;
  bad = {};
  bad.neighbour_groups = {{"a"}};
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_EQ(ParseChannelStatus("stuck"), ChannelStatus::kStuck);
  EXPECT_FALSE(ParseChannelStatus("bogus").has_value());
  EXPECT_EQ(ChannelStatusName(ChannelStatus::kDisagreement), "disagreement");
}

}  // namespace
}  // namespace trueaxis::signal
