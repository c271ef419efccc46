#include "trueaxis/station/site_config.hpp"

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::station {
namespace {

using runtime::LinkLossPolicy;
using runtime::Programming;
using runtime::SensorFallback;

constexpr const char* kFull = R"(
[machine]
kind = "virtual"
file = "../machines/vmc.toml"
seed = 7
time_scale = 60
duty = 0.5
coolant = "flood"

[model]
file = "model.json"
reload = false

[loop]
period_s = 0.005
duration_s = 30

[limits]
max_correction_um = 80
max_step_um = 0.25
hysteresis = 0.3

[sensor_fault]
hold_last_good_s = 20
fallback_handover_s = 900
fallback = "zero"
max_rate_c_per_s = 1

[link]
loss_policy = "ramp_to_zero"
recovery_cycles = 10
follow_cnc_enable = false
direction_min_move_um = 5

[channels]
x_nut = "rtd_1"

[[axis]]
name = "X"
pulse_equivalent_um = 0.5
programming = "diameter"
position_offset_mm = -2.5
reference_position_mm = 10

[[axis]]
name = "Z"
enabled = false

[signal]
enabled = true
calibration = "cal.json"
groups = [["x_nut", "x_nut_b"], ["ambient", "ambient_2", "ambient_3"]]
max_disagreement_c = 1.5

[history]
db = "out/history.sqlite"
record_interval_s = 0.5
)";

// The installation — and with it the pure runtime it configures — holds no deployment: where the
// machine is (MODBUS host), its history and its web page are the SiteConfig's alone (the runtime
// library cannot link them either: trueaxis_forbid_links in CMakeLists.txt).
template <class T>
concept HoldsDeployment = requires(const T& c) { c.modbus; } || requires(const T& c) { c.web; } ||
                          requires(const T& c) { c.history; } || requires(const T& c) { c.history_db; } ||
                          requires(const T& c) { c.virtual_machine; } || requires(const T& c) { c.machine; };
static_assert(!HoldsDeployment<InstallationConfig>);
static_assert(HoldsDeployment<SiteConfig>);  // the check sees them where they are

TEST(RunConfig, ParsesEveryField) {
  const SiteConfig site = ParseSiteConfig(kFull, "/etc/trueaxis/run/run.toml");
  const InstallationConfig& c = site.installation;
  EXPECT_EQ(site.machine, MachineKind::kVirtual);
  EXPECT_EQ(site.virtual_machine.machine_file, "/etc/trueaxis/machines/vmc.toml");
  EXPECT_EQ(site.virtual_machine.seed, 7u);
  EXPECT_EQ(site.virtual_machine.time_scale, 60);
  EXPECT_EQ(site.virtual_machine.coolant, CoolantState::kFlood);
  EXPECT_EQ(c.model_file, "/etc/trueaxis/run/model.json");
  EXPECT_FALSE(c.model_reload);
  EXPECT_DOUBLE_EQ(c.period_s, 0.005);
  EXPECT_DOUBLE_EQ(c.duration_s, 30);
  EXPECT_DOUBLE_EQ(c.compensator.shaper.max_correction_um, 80);
  EXPECT_DOUBLE_EQ(c.compensator.shaper.max_step_um, 0.25);
  EXPECT_DOUBLE_EQ(c.compensator.shaper.hysteresis, 0.3);
  EXPECT_EQ(c.compensator.sensor.fallback, SensorFallback::kZero);
  EXPECT_DOUBLE_EQ(c.compensator.sensor.hold_last_good_s, 20);
  EXPECT_DOUBLE_EQ(c.compensator.sensor.fallback_handover_s, 900);
  EXPECT_EQ(c.compensator.link_loss, LinkLossPolicy::kRampToZero);
  EXPECT_EQ(c.compensator.link_recovery_cycles, 10);
  EXPECT_FALSE(c.compensator.follow_cnc_enable);
  EXPECT_DOUBLE_EQ(c.compensator.direction_min_move_um, 5);
  EXPECT_EQ(c.compensator.channel_map.at("x_nut"), "rtd_1");
  ASSERT_EQ(c.axes.size(), 2u);
  EXPECT_EQ(c.axes[0].programming, Programming::kDiameter);
  EXPECT_DOUBLE_EQ(c.axes[0].pulse_equivalent_um, 0.5);
  EXPECT_DOUBLE_EQ(c.axes[0].position_offset_mm, -2.5);
  EXPECT_DOUBLE_EQ(c.axes[0].reference_position_mm, 10);
  EXPECT_FALSE(c.axes[1].enabled);
  EXPECT_TRUE(std::isnan(c.axes[1].reference_position_mm));
  EXPECT_EQ(site.history.db, "/etc/trueaxis/run/out/history.sqlite");
  EXPECT_DOUBLE_EQ(site.history.record_interval_s, 0.5);
  EXPECT_TRUE(c.signal_processing);
  EXPECT_EQ(c.calibration_file, "/etc/trueaxis/run/cal.json");
  ASSERT_EQ(c.redundant_groups.size(), 2u);
  EXPECT_EQ(c.redundant_groups[0], (std::vector<std::string>{"x_nut", "x_nut_b"}));
  EXPECT_EQ(c.redundant_groups[1].size(), 3u);
  EXPECT_DOUBLE_EQ(c.compensator.sensor.judge.max_disagreement_c, 1.5);
  EXPECT_DOUBLE_EQ(c.compensator.sensor.judge.max_rate_c_per_s, 1);
}

TEST(RunConfig, HistoryDatabaseUrlIsKeptAsWritten) {
  const SiteConfig c = ParseSiteConfig(
      "[machine]\nkind = \"modbus\"\naxes = [\"X\"]\n[model]\nfile = \"/m.json\"\n[history]\ndb = \"postgresql://trueaxis@db.shop/hall3\"\n",
      "/etc/trueaxis/run.toml");
  EXPECT_EQ(c.history.db, "postgresql://trueaxis@db.shop/hall3");  // not joined to the config's folder like a path
}

TEST(RunConfig, MinimalModbusConfigGetsDefaults) {
  const SiteConfig site = ParseSiteConfig("[machine]\nkind = \"modbus\"\nport = 15020\n[model]\nfile = \"/m.json\"\n", "run.toml");
  const InstallationConfig& c = site.installation;
  EXPECT_EQ(site.machine, MachineKind::kModbus);
  EXPECT_EQ(site.modbus.port, 15020);
  EXPECT_EQ(site.modbus.host, "127.0.0.1");
  EXPECT_TRUE(site.history.db.empty() && site.history.csv.empty() && site.web.listen.empty());
  EXPECT_EQ(c.model_file, "/m.json");
  EXPECT_DOUBLE_EQ(c.period_s, 0.01);
  EXPECT_EQ(c.compensator.link_loss, LinkLossPolicy::kHold);
  EXPECT_TRUE(c.signal_processing);  // the temperature pipeline is on unless switched off
  EXPECT_DOUBLE_EQ(c.temperature_period_s, 0.1);
  EXPECT_DOUBLE_EQ(c.compensator.link_stale_after_s, 0.25);
  EXPECT_DOUBLE_EQ(c.compensator.direction_min_move_um, 2.0);
}

TEST(RunConfig, StalenessLimitsFollowTheLoopPeriod) {
  const std::string head = "[machine]\nkind = \"modbus\"\n[model]\nfile = \"/m.json\"\n";
  const InstallationConfig slow = ParseSiteConfig(head + "[loop]\nperiod_s = 0.5\n", "run.toml").installation;
  EXPECT_DOUBLE_EQ(slow.compensator.link_stale_after_s, 1.5);  // 3 periods when not given
  EXPECT_DOUBLE_EQ(slow.temperature_period_s, 0.5);            // never more often than the loop
  const InstallationConfig given = ParseSiteConfig(
      head + "[loop]\ntemperature_period_s = 1\n[link]\nstale_after_s = 0.05\n[sensor_fault]\nstale_after_s = 9\n", "run.toml").installation;
  EXPECT_DOUBLE_EQ(given.temperature_period_s, 1.0);
  EXPECT_DOUBLE_EQ(given.compensator.link_stale_after_s, 0.05);
  EXPECT_DOUBLE_EQ(given.compensator.sensor.stale_after_s, 9);
}

void ExpectError(const std::string& text, int line, const std::string& field, const std::string& words) {
  try {
    ParseSiteConfig(text, "run.toml");
    FAIL() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "run.toml");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

// The per-value limits of [sensor_fault] and [signal] are the temperature judge's, kept in one place
// (SensorFaultPolicy::judge) under the keys the run config has always had.
TEST(RunConfig, SensorFaultLimitsAreTheTemperatureJudges) {
  const std::string head = "[machine]\nkind = \"modbus\"\n[model]\nfile = \"m.json\"\n";
  const InstallationConfig d = ParseSiteConfig(head, "/r.toml").installation;
  const signal::FaultOptions& dj = d.compensator.sensor.judge;
  EXPECT_DOUBLE_EQ(dj.min_plausible_c, -20);
  EXPECT_DOUBLE_EQ(dj.max_plausible_c, 120);
  EXPECT_DOUBLE_EQ(dj.max_rate_c_per_s, 2.0);
  EXPECT_DOUBLE_EQ(dj.rate_allowance_c, 0.5);
  EXPECT_DOUBLE_EQ(dj.max_disagreement_c, 3.0);
  const InstallationConfig c = ParseSiteConfig(head +
                                                   "[sensor_fault]\nmin_valid_c = 5\nmax_valid_c = 60\nmax_rate_c_per_s = 0\n"
                                                   "rate_allowance_c = 0.2\n[signal]\nmax_disagreement_c = 1.5\n",
                                               "/r.toml")
                                    .installation;
  const signal::FaultOptions& j = c.compensator.sensor.judge;
  EXPECT_DOUBLE_EQ(j.min_plausible_c, 5);
  EXPECT_DOUBLE_EQ(j.max_plausible_c, 60);
  EXPECT_DOUBLE_EQ(j.max_rate_c_per_s, 0);  // 0: no rate rule, as documented
  EXPECT_DOUBLE_EQ(j.rate_allowance_c, 0.2);
  EXPECT_DOUBLE_EQ(j.max_disagreement_c, 1.5);
  std::string why;
  EXPECT_TRUE(c.compensator.IsValid(&why)) << why;
  EXPECT_NO_THROW(signal::TemperatureMonitor({"nut"}, signal::MonitorOptions{{}, j, {}}));
}

TEST(RunConfig, BadInputNamesLineAndField) {
  const std::string head = "[machine]\nkind = \"modbus\"\n[model]\nfile = \"m.json\"\n";  // lines 1-4
  ExpectError(head + "[limits]\nmax_step_um = -1\n", 6, "limits.max_step_um", "out of range");
  ExpectError(head + "[limits]\nmax_correction_um = 0\n", 6, "limits.max_correction_um", "out of range");  // all held at 0
  ExpectError(head + "[limits]\nmax_stepp_um = 1\n", 6, "limits.max_stepp_um", "unknown key");
  ExpectError(head + "[link]\nloss_policy = \"panic\"\n", 6, "link.loss_policy", "not one of");
  ExpectError(head + "[link]\ndirection_min_move_um = 0\n", 6, "link.direction_min_move_um", "out of range");
  ExpectError(head + "[loop]\nperiod_s = \"fast\"\n", 6, "loop.period_s", "must be a number");
  ExpectError(head + "[[axis]]\npulse_equivalent_um = 1\n", 5, "axis[0].name", "missing");
  ExpectError(head + "[[axis]]\nname = \"X\"\n[[axis]]\nname = \"X\"\n", 8, "axis[1].name", "twice");
  ExpectError(head + "[sensor_fault]\nfallback_handover_s = -60\n", 6, "sensor_fault.fallback_handover_s", "out of range");
  ExpectError(head + "[sensor_fault]\nmin_valid_c = 50\nmax_valid_c = 10\n", 7, "sensor_fault.max_valid_c", "greater");
  ExpectError("[machine]\nkind = \"virtual\"\n[model]\nfile = \"m.json\"\n", 1, "machine.file", "missing");
  ExpectError("[machine]\nkind = \"modbus\"\n", 1, "model", "missing");
  ExpectError("[machine]\nkind = \"modbus\"\n[model]\nfile = \"m.json\"\nextra = 1\n", 5, "model.extra", "unknown key");
  ExpectError("[machine\nkind = 1\n", 1, "", "");
  ExpectError(head + "[loop]\nperiod_s = 0.1\n[link]\nstale_after_s = 0.1\n", 8, "link.stale_after_s", "twice the loop period");
  ExpectError(head + "[signal]\ngroups = [\"y_nut\", \"y_nut_b\"]\n", 6, "signal.groups", "at least two");
  ExpectError(head + "[signal]\ngroups = [[\"y_nut\"]]\n", 6, "signal.groups", "at least two");
  ExpectError(head + "[signal]\ngroups = [[\"y_nut\", 3]]\n", 6, "signal.groups", "string");
  ExpectError(head + "[signal]\ngroups = [[\"y_nut\", \"y_nut\"]]\n", 6, "signal.groups", "twice");
  ExpectError(head + "[signal]\nenabled = false\ngroups = [[\"a\", \"b\"]]\n", 7, "signal.groups", "enabled = true");
  ExpectError(head + "[signal]\nmax_disagreement_c = 0\n", 6, "signal.max_disagreement_c", "out of range");
  // the pipeline is on by default; switched off, a calibration file has nothing to apply it
  ExpectError(head + "[signal]\nenabled = false\ncalibration = \"c.json\"\n", 7, "signal.calibration", "enabled = true");
}

// Two axes "X" made one axis get two corrections and a repeated RTD channel exited 1 from deep in
// the monitor; a dotted quad that is no address was tried as a host name at run time.
TEST(RunConfig, ModbusNamesAreUniqueAndTheHostAnAddress) {
  const std::string tail = "[model]\nfile = \"m.json\"\n";
  ExpectError("[machine]\nkind = \"modbus\"\naxes = [\"X\",\n  \"X\", \"Z\"]\n" + tail, 4, "machine.axes",
              "axis 'X' is listed twice");
  ExpectError("[machine]\nkind = \"modbus\"\nchannels = [\"x_nut\", \"x_nut\"]\n" + tail, 3, "machine.channels",
              "channel 'x_nut' is listed twice");
  ExpectError("[machine]\nkind = \"modbus\"\nhost = \"999.1.1.1\"\n" + tail, 3, "machine.host", "not an IPv4 address");
  ExpectError("[machine]\nkind = \"virtual\"\nfile = \"m.toml\"\nname = \"VMC-850\"\n" + tail, 4, "machine.name",
              "only for kind = \"modbus\"");
  // host names stay allowed (libmodbus looks them up); lines are kept for later checks
  const SiteConfig c = ParseSiteConfig("[machine]\nkind = \"modbus\"\nhost = \"cnc-7.local\"\n" + tail +
                                           "[[axis]]\nname = \"Y\"\n",
                                       "run.toml");
  EXPECT_EQ(c.modbus.host, "cnc-7.local");
  EXPECT_EQ(c.LineOf("model.file"), 5);
  EXPECT_EQ(c.LineOf("axis[0].name"), 7);
}

}  // namespace
}  // namespace trueaxis::station
