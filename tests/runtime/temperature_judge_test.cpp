// One temperature judge: every per-value rule (calibration, range, rate, stuck, disagreement) is
// applied once, by signal::TemperatureMonitor in front of the step; the step adds only the
// snapshot's freshness and how long a faulted channel's last good value is held (docs/runtime.md).
#include <cmath>
#include <type_traits>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/hw/no_temperature_source.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"
#include "trueaxis/station/machine_connection.hpp"
#include "trueaxis/station/site_config.hpp"

namespace trueaxis::runtime {
namespace {
using signal::ChannelStatus;
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestModel;

// No path feeds the loop unjudged temperatures: a raw source does not compile where the loop reads.
template <class S>
concept LoopCycleReads = requires(Compensator& c, hw::CncLink& link, S& source) { c.RunCycle(link, source, 0.0); };
template <class S>
concept SnapshotReads = requires(S& source, TemperatureSnapshot& out) { ReadTemperatures(source, 0.0, 1, out); };
static_assert(LoopCycleReads<signal::MonitoredTemperatureSource>);
static_assert(!LoopCycleReads<hw::TemperatureSource>);
static_assert(!LoopCycleReads<hw::NoTemperatureSource>);
static_assert(SnapshotReads<signal::JudgedTemperatureSource>);
static_assert(!SnapshotReads<hw::TemperatureSource>);
static_assert(std::is_constructible_v<LoopRunner, Compensator&, hw::CncLink&, signal::MonitoredTemperatureSource&, LoopOptions>);
static_assert(!std::is_constructible_v<LoopRunner, Compensator&, hw::CncLink&, hw::TemperatureSource&, LoopOptions>);

constexpr std::uint32_t kSensorAlarms = kAlarmSensorHeld | kAlarmSensorFallback | kAlarmTemperatureSource;

// The step on hand-made judged snapshots: it takes the verdict as it is.
struct StepRig {
  CompensatorOptions options;  // [sensor_fault] defaults: the judge's range −20…120 °C, 2 °C/s
  std::vector<AxisInterface> axes{AxisInterface{}};
  StepState state{1, 1, options};
  StepOutputs out{1, 1};
  TemperatureSnapshot temps{1};
  CncSnapshot cnc{1};
  void Cycle(double t_s, double value_c, ChannelStatus verdict) {
    ++temps.sequence;
    temps.sampled_at_s = t_s;
    temps.ok = true;
    temps.channels[0] = {verdict == ChannelStatus::kOk ? value_c : std::nan(""), value_c, verdict};
    ++cnc.sequence;
    cnc.sampled_at_s = t_s;
    cnc.read_ok = true;
    StepInputs in;
    in.now_s = t_s;
    in.temperatures = &temps;
    in.cnc = &cnc;
    Step(StepModel{options, axes, nullptr}, state, in, out);
  }
};

TEST(TemperatureJudge, TheStepTakesTheVerdictAndJudgesNoValueAgain) {
  StepRig rig;
  rig.Cycle(0.0, 20.0, ChannelStatus::kOk);
  // Judged ok at 150 °C, 130 °C up in 0.1 s (a judge configured for it): beyond the run config's
  // default range and rate, yet the step uses it — it has no range or rate rule of its own.
  rig.Cycle(0.1, 150.0, ChannelStatus::kOk);
  EXPECT_EQ(rig.out.channels[0].health, ChannelHealth::kOk);
  EXPECT_DOUBLE_EQ(rig.out.channels[0].value_c, 150.0);
  // Faulted by the judge at a harmless number: held at the last good value.
  rig.Cycle(0.2, 21.0, ChannelStatus::kRateOfChange);
  EXPECT_EQ(rig.out.channels[0].health, ChannelHealth::kHeld);
  EXPECT_DOUBLE_EQ(rig.out.channels[0].value_c, 150.0);
  EXPECT_DOUBLE_EQ(rig.out.channels[0].raw_c, 21.0);
  // Ok again by the judge's word: used at once (the recovery hysteresis is the judge's alone).
  rig.Cycle(0.3, 21.0, ChannelStatus::kOk);
  EXPECT_EQ(rig.out.channels[0].health, ChannelHealth::kOk);
  EXPECT_DOUBLE_EQ(rig.out.channels[0].value_c, 21.0);
}

// The judge in front of the compensator, with the limits of a run config: a range fault is judged
// once, with the judge's hysteresis, and held then lost by the step.
TEST(TemperatureJudge, ARunConfigsRangeIsJudgedOnceThenHeldThenLost) {
  const station::InstallationConfig c =
      station::ParseSiteConfig("[machine]\nkind = \"modbus\"\naxes = [\"X\"]\n[model]\nfile = \"/m.json\"\n"
                               "[sensor_fault]\nmax_valid_c = 40\nhold_last_good_s = 2\n",
                               "/etc/trueaxis/run.toml")
          .installation;
  MockTemperatures raw({"ambient", "nut", "bearing"}, 20.0);
  double now = 0;
  signal::MonitoredTemperatureSource judged(raw, station::TemperatureJudgeOptions(c), [&] { return now; });
  MockCnc cnc({"X"});
  cnc.axes[0] = {400, +1, true};
  auto comp = Compensator::ForHardware(c.compensator, cnc, judged, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  auto cycle = [&](int n) {
    for (int i = 0; i < n; ++i) comp->RunCycle(cnc, judged, now += 0.1);
    return comp->LastStatus();
  };
  raw.Set("nut", 30);
  CycleStatus s = cycle(300);  // 30 s: the low-pass has settled at 30 °C
  ASSERT_EQ(s.channels[1].health, ChannelHealth::kOk);
  EXPECT_NEAR(s.channels[1].value_c, 30.0, 0.05);

  // One sample at 45 °C (beyond max_valid_c = 40): fewer than confirm_samples, so the judge keeps
  // the channel ok at its filtered value — no alarm, nothing moves.
  raw.Set("nut", 45);
  s = cycle(1);
  EXPECT_EQ(s.alarms & kSensorAlarms, 0u);
  EXPECT_NEAR(s.channels[1].value_c, 30.0, 0.05);
  raw.Set("nut", 30);
  cycle(30);

  // 45 °C for good (an open RTD read as a temperature): over_range once confirmed, and exactly
  // one sensor alarm — the last good value held.
  raw.Set("nut", 45);
  s = cycle(5);
  EXPECT_EQ(judged.monitor().reading(1).status, ChannelStatus::kOverRange);
  EXPECT_EQ(s.channels[1].health, ChannelHealth::kHeld);
  EXPECT_NEAR(s.channels[1].value_c, 30.0, 0.05);
  EXPECT_DOUBLE_EQ(s.channels[1].raw_c, 45.0);
  EXPECT_EQ(s.alarms & kSensorAlarms, kAlarmSensorHeld);
  // hold_last_good_s (2 s) after the last good value: lost, the axis goes to its fallback.
  s = cycle(20);
  EXPECT_EQ(s.channels[1].health, ChannelHealth::kLost);
  EXPECT_TRUE(s.alarms & kAlarmSensorFallback);

  // Back in range: usable again only after the judge's recover_samples (20) clean samples.
  raw.Set("nut", 30);
  s = cycle(5);
  EXPECT_NE(s.channels[1].health, ChannelHealth::kOk);
  s = cycle(20);
  EXPECT_EQ(judged.monitor().reading(1).status, ChannelStatus::kOk);
  EXPECT_EQ(s.channels[1].health, ChannelHealth::kOk);
  EXPECT_EQ(s.alarms & kSensorAlarms, 0u);
}

// Freshness is the step's: a judged snapshot that is not renewed (the temperature worker stalls)
// is held, then lost, though the judge found every value good.
TEST(TemperatureJudge, AStaleJudgedSnapshotIsHeldThenLost) {
  MockTemperatures raw({"ambient", "nut", "bearing"}, 25.0);
  double now = 0;
  signal::MonitoredTemperatureSource judged(raw, signal::MonitorOptions{}, [&] { return now; });
  MockCnc cnc({"X"});
  cnc.axes[0] = {400, +1, true};
  CompensatorOptions o;
  o.sensor.stale_after_s = 0.5;
  o.sensor.hold_last_good_s = 2.0;
  auto comp = Compensator::ForHardware(o, cnc, judged, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  TemperatureSnapshot ts = comp->MakeTemperatureSnapshot();
  CncSnapshot cs = comp->MakeCncSnapshot();
  ReadTemperatures(judged, 0.0, 1, ts);  // delivered once, then the worker stalls
  ASSERT_TRUE(ts.channels[1].usable());
  auto at = [&](double t) {
    ReadCnc(cnc, t, static_cast<std::uint64_t>(std::llround(t * 100)), cs);
    const CycleStatus& s = comp->Cycle(ts, cs, t);
    comp->CommitWrite(true);
    return s;
  };
  CycleStatus s = at(0.4);
  EXPECT_EQ(s.channels[1].health, ChannelHealth::kOk);
  EXPECT_EQ(s.alarms & (kSensorAlarms | kAlarmStaleInput), 0u);
  s = at(1.0);  // stale: held at the judged value, the source alarm and stale_input
  EXPECT_EQ(s.channels[1].health, ChannelHealth::kHeld);
  EXPECT_DOUBLE_EQ(s.channels[1].value_c, 25.0);
  EXPECT_TRUE(s.alarms & kAlarmStaleInput);
  EXPECT_TRUE(s.alarms & kAlarmTemperatureSource);
  s = at(1.9);
  EXPECT_EQ(s.channels[1].health, ChannelHealth::kHeld);
  s = at(2.4);  // beyond hold_last_good_s of the last good value
  EXPECT_EQ(s.channels[1].health, ChannelHealth::kLost);
  EXPECT_TRUE(s.alarms & kAlarmSensorFallback);
}

// The judge's options are built in one place from the installation's config: the fault limits of
// [sensor_fault] and [signal] max_disagreement_c, the redundant groups, the filter on or off.
TEST(TemperatureJudge, ItsOptionsComeFromTheConfigThroughOneFunction) {
  station::InstallationConfig c =
      station::ParseSiteConfig("[machine]\nkind = \"modbus\"\naxes = [\"X\"]\n[model]\nfile = \"/m.json\"\n"
                               "[sensor_fault]\nmax_valid_c = 45\nmax_rate_c_per_s = 0.5\n"
                               "[signal]\ngroups = [[\"nut\", \"nut_b\"]]\nmax_disagreement_c = 2\n",
                               "/etc/trueaxis/run.toml")
          .installation;
  const signal::MonitorOptions on = station::TemperatureJudgeOptions(c);
  EXPECT_DOUBLE_EQ(on.faults.max_plausible_c, 45);
  EXPECT_DOUBLE_EQ(on.faults.max_rate_c_per_s, 0.5);
  EXPECT_DOUBLE_EQ(on.faults.max_disagreement_c, 2);
  EXPECT_EQ(on.neighbour_groups, (std::vector<std::vector<std::string>>{{"nut", "nut_b"}}));
  EXPECT_GT(on.filter.median_window, 1) << "the filter is on by default";
  c.signal_processing = false;  // [signal] enabled = false (no groups then): judged all the same
  c.redundant_groups.clear();
  const signal::MonitorOptions off = station::TemperatureJudgeOptions(c);
  EXPECT_EQ(off.filter.hampel_window, 1);
  EXPECT_EQ(off.filter.median_window, 1);
  EXPECT_DOUBLE_EQ(off.filter.lowpass_time_constant_s, 0);
  EXPECT_DOUBLE_EQ(off.faults.max_plausible_c, 45);
  EXPECT_DOUBLE_EQ(off.faults.max_rate_c_per_s, 0.5);
}

// The machine's wiring always puts the judge in front: [signal] enabled = false switches off only
// its filter, the run config's fault limits still apply.
TEST(TemperatureJudge, TheMachinesTemperaturesAreJudgedWithTheFilterOffToo) {
  const std::string machine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml";
  const station::SiteConfig c = station::ParseSiteConfig("[machine]\nkind = \"virtual\"\nfile = \"" + machine +
                                                             "\"\n[model]\nfile = \"m.json\"\n[sensor_fault]\nmax_valid_c = 45\n"
                                                             "[signal]\nenabled = false\n",
                                                         "/etc/trueaxis/run.toml");
  station::Machine m = station::OpenMachine(c);
  ASSERT_NE(m.monitored, nullptr);
  const signal::MonitorOptions& judge = m.monitored->monitor().options();
  EXPECT_EQ(judge.filter.hampel_window, 1);
  EXPECT_EQ(judge.filter.median_window, 1);
  EXPECT_DOUBLE_EQ(judge.filter.lowpass_time_constant_s, 0);
  EXPECT_DOUBLE_EQ(judge.faults.max_plausible_c, 45);
  EXPECT_DOUBLE_EQ(judge.faults.min_plausible_c, -20);
  std::vector<signal::JudgedTemperature> out(m.monitored->ChannelCount());
  ASSERT_FALSE(out.empty());
  EXPECT_TRUE(m.monitored->Read(out));
  EXPECT_TRUE(out[0].usable());
  m.Close();
}

}  // namespace
}  // namespace trueaxis::runtime
