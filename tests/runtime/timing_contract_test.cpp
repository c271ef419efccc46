// The timing contract of the cycle (docs/runtime.md, *Timing contract*): the
// step never waits on hardware. The I/O runs on workers; a stalled terminal (a
// MODBUS peer on 127.0.0.1 that accepts and never answers), a CNC link blocked
// in process, or a flapping terminal only make snapshots old, which the step
// treats as a fault through the limiter: the output holds or ramps, never jumps,
// and the loop keeps its cycles.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/station/machine_connection.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestModel;

template <class Pred>
bool WaitFor(Pred pred, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return pred();
}

// Records, on the loop thread, what the contract is about: the largest change of any output
// between two cycles, and the link alarm raised / cleared.
class ContractObserver : public CycleObserver {
 public:
  void OnCycle(const CycleStatus& s) override {
    for (std::size_t i = 0; i < s.axes.size() && i < std::size(last_); ++i) {
      if (seen_) max_delta_um = std::max(max_delta_um, std::fabs(s.axes[i].output_um - last_[i]));
      last_[i] = s.axes[i].output_um;
    }
    seen_ = true;
    const bool link_alarm = (s.alarms & kAlarmLinkRead) != 0;
    if (link_alarm && !link_alarm_) raised.fetch_add(1);
    if (!link_alarm && link_alarm_) cleared.fetch_add(1);
    link_alarm_ = link_alarm;
    if (s.alarms & kAlarmStaleInput) stale_cycles.fetch_add(1);
    if (link_alarm) link_alarm_cycles.fetch_add(1);
    output_um.store(s.axes.empty() ? 0 : s.axes[0].output_um);
    cycles.fetch_add(1);
  }
  double max_delta_um = 0;  // read after the loop stopped
  std::atomic<int> raised{0}, cleared{0};
  std::atomic<long> stale_cycles{0}, link_alarm_cycles{0}, cycles{0};
  std::atomic<double> output_um{0};

 private:
  bool seen_ = false, link_alarm_ = false;
  double last_[8] = {};
};

CompensatorOptions ContractOptions() {
  CompensatorOptions o;
  o.shaper.max_step_um = 1.0;
  o.link_stale_after_s = 0.1;
  o.sensor.stale_after_s = 0.5;
  return o;
}

// An installation with these compensator options and the defaults otherwise (the filter on).
station::InstallationConfig InstallationWith(const CompensatorOptions& o) {
  station::InstallationConfig c;
  c.compensator = o;
  return c;
}

// The compensator (axis X, TestModel) behind the real-time loop with its I/O workers; the raw
// temperatures through the temperature judge, as `run` reads them.
struct ContractLoop {
  ContractLoop(hw::CncLink& cnc, hw::TemperatureSource& temps, const CompensatorOptions& o, double period_s)
      : judged(temps, station::TemperatureJudgeOptions(InstallationWith(o))),
        comp(Compensator::ForHardware(o, cnc, judged, {})),
        runner(*comp, cnc, judged, LoopOptions{period_s, 10 * period_s}, &obs) {
    comp->PublishModel(TestModel(1.0, {"X"}), "m");
  }
  signal::MonitoredTemperatureSource judged;
  std::unique_ptr<Compensator> comp;
  ContractObserver obs;
  LoopRunner runner;
};

// The MODBUS clients of a terminal on 127.0.0.1:port (one axis, one RTD module), as `run` makes them.
station::ModbusClients TerminalClients(int port, double response_timeout_s) {
  station::ModbusConfig mc;
  mc.port = port;
  mc.response_timeout_s = response_timeout_s;
  mc.axis_names = {"X"};
  mc.channel_names = {"ambient", "nut", "bearing"};
  return station::MakeModbusClients(mc, "test", 2.0);
}

// ---- the pure step: a stale snapshot is a fault, handled through the limiter ----

TEST(TimingContract, StepIsAPureFunctionOfModelStateAndInputs) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 25.0);
  auto comp = Compensator::ForHardware(ContractOptions(), cnc, temps, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  cnc.axes[0] = {300, 1, true};
  for (int c = 1; c <= 50; ++c) comp->RunCycle(cnc, temps, c * 0.01);
  // The same state and inputs, stepped twice from copies, give the same outputs and next state.
  TemperatureSnapshot ts = comp->MakeTemperatureSnapshot();
  CncSnapshot cs = comp->MakeCncSnapshot();
  ReadTemperatures(temps, 0.51, 99, ts);
  ReadCnc(cnc, 0.51, 99, cs);
  const StepState before = comp->state();
  StepState a = before, b = before;
  StepOutputs out_a(1, 3), out_b(1, 3);
  const BoundModel* none = nullptr;
  const StepModel model{comp->options(), comp->axes(), none};
  StepInputs in;
  in.now_s = 0.51;
  in.temperatures = &ts;
  in.cnc = &cs;
  Step(model, a, in, out_a);
  Step(model, b, in, out_b);
  EXPECT_EQ(out_a.command.correction_um[0], out_b.command.correction_um[0]);
  EXPECT_EQ(out_a.status.alarms, out_b.status.alarms);
  EXPECT_EQ(a.shaper[0].counts, b.shaper[0].counts);
  EXPECT_EQ(a.cycle, before.cycle + 1);
  EXPECT_TRUE(out_a.status.alarms & kAlarmNoModel);  // no model given: ramps towards 0
  EXPECT_LT(std::fabs(out_a.command.correction_um[0]), std::fabs(comp->LastStatus().axes[0].written_um));
}

TEST(TimingContract, StaleCncSnapshotIsALinkLossThroughTheLimiter) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 25.0);
  CompensatorOptions o = ContractOptions();
  o.link_loss = LinkLossPolicy::kRampToZero;
  auto comp = Compensator::ForHardware(o, cnc, temps, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  cnc.axes[0] = {400, 1, true};
  TemperatureSnapshot ts = comp->MakeTemperatureSnapshot();
  CncSnapshot cs = comp->MakeCncSnapshot();
  double t = 0;
  for (int c = 1; c <= 100; ++c) {  // fresh snapshots: the output reaches the model's value
    t = c * 0.01;
    ReadTemperatures(temps, t, c, ts);
    ReadCnc(cnc, t, c, cs);
    comp->Cycle(ts, cs, t);
    comp->CommitWrite(true);
  }
  const double settled = comp->LastStatus().axes[0].output_um;
  ASSERT_GT(std::fabs(settled), 5.0);
  EXPECT_EQ(comp->LastStatus().alarms & (kAlarmLinkRead | kAlarmStaleInput), 0u);
  // The CNC worker stops delivering: the snapshot ages. Within the limit nothing changes; beyond it
  // the link counts as lost and the output ramps to 0 at the rate limit, never in one jump.
  double last = settled, max_delta = 0;
  bool stale_seen = false;
  for (int c = 1; c <= 100; ++c) {
    t += 0.01;
    const auto& s = comp->Cycle(ts, cs, t);
    comp->CommitWrite(true);
    const double out = comp->LastStatus().axes[0].output_um;
    max_delta = std::max(max_delta, std::fabs(out - last));
    last = out;
    if (t - cs.sampled_at_s <= o.link_stale_after_s - 1e-9) {
      EXPECT_EQ(s.alarms & kAlarmStaleInput, 0u) << "cycle " << c;
    } else {
      EXPECT_TRUE(s.alarms & kAlarmStaleInput) << "cycle " << c;
      EXPECT_TRUE(s.alarms & kAlarmLinkRead) << "cycle " << c;
      stale_seen = true;
    }
  }
  EXPECT_TRUE(stale_seen);
  EXPECT_LE(max_delta, 1.0 + 1e-9);
  EXPECT_EQ(last, 0.0);  // ramped all the way down, ≤ 1 µm per cycle
}

TEST(TimingContract, StaleTemperatureSnapshotHoldsThenLosesTheChannels) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 25.0);
  CompensatorOptions o = ContractOptions();
  o.sensor.hold_last_good_s = 2.0;
  auto comp = Compensator::ForHardware(o, cnc, temps, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  TemperatureSnapshot ts = comp->MakeTemperatureSnapshot();
  CncSnapshot cs = comp->MakeCncSnapshot();
  ReadTemperatures(temps, 0.0, 1, ts);  // the temperature worker delivers once, then stalls
  std::uint32_t alarms_at[4] = {};
  ChannelHealth health_at[4] = {};
  const double times[4] = {0.4, 1.0, 1.9, 2.4};
  int k = 0;
  for (int c = 1; c <= 300; ++c) {
    const double t = c * 0.01;
    ReadCnc(cnc, t, c, cs);
    const auto& s = comp->Cycle(ts, cs, t);
    comp->CommitWrite(true);
    if (k < 4 && std::fabs(t - times[k]) < 1e-9) {
      alarms_at[k] = s.alarms;
      health_at[k] = s.channels[1].health;
      ++k;
    }
  }
  ASSERT_EQ(k, 4);
  EXPECT_EQ(health_at[0], ChannelHealth::kOk);  // 0.4 s old: within stale_after_s (0.5 s)
  EXPECT_EQ(alarms_at[0] & kAlarmTemperatureSource, 0u);
  EXPECT_EQ(health_at[1], ChannelHealth::kHeld);  // stale: a failed read, last good value held
  EXPECT_TRUE(alarms_at[1] & kAlarmStaleInput);
  EXPECT_TRUE(alarms_at[1] & kAlarmTemperatureSource);
  EXPECT_EQ(health_at[2], ChannelHealth::kHeld);  // still within hold_last_good_s (2 s) of the last good value
  EXPECT_EQ(health_at[3], ChannelHealth::kLost);
  EXPECT_TRUE(alarms_at[3] & kAlarmSensorFallback);
}

// ---- the loop: a stalled link never delays a cycle ----

// A CNC link whose Read blocks until released (an in-process stand-in for a terminal that hangs).
class BlockingCnc : public MockCnc {
 public:
  using MockCnc::MockCnc;
  bool Read(std::span<hw::AxisState> out, hw::CncState& m) override {
    in_read.store(true);
    while (block.load()) std::this_thread::sleep_for(std::chrono::microseconds(200));
    in_read.store(false);
    return MockCnc::Read(out, m);
  }
  std::atomic<bool> block{false};
  std::atomic<bool> in_read{false};
};

TEST(TimingContract, BlockedCncReadDoesNotStopTheLoop) {
  BlockingCnc cnc({"X"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 25.0);
  cnc.axes[0] = {400, 1, true};
  ContractLoop loop(cnc, temps, ContractOptions(), 0.002);
  auto& obs = loop.obs;
  auto& runner = loop.runner;
  runner.Start();
  ASSERT_TRUE(WaitFor([&] { return obs.cycles.load() > 100 && obs.raised.load() == obs.cleared.load(); }, 20));
  const double settled = obs.output_um.load();
  ASSERT_GT(std::fabs(settled), 5.0);
  cnc.block.store(true);
  ASSERT_TRUE(WaitFor([&] { return cnc.in_read.load(); }, 10));
  const long cycles_at_block = obs.cycles.load();
  // While the worker hangs in one Read, the loop goes on cycling and flags the stale snapshot.
  ASSERT_TRUE(WaitFor([&] { return obs.cycles.load() > cycles_at_block + 200 && obs.stale_cycles.load() > 50; }, 30));
  EXPECT_TRUE(cnc.in_read.load());  // still the same blocked call
  EXPECT_EQ(obs.output_um.load(), settled);  // link loss with "hold": the output stays
  cnc.block.store(false);
  ASSERT_TRUE(WaitFor([&] { return obs.cleared.load() >= obs.raised.load() && obs.raised.load() >= 1; }, 20));
  runner.Stop();
  EXPECT_TRUE(runner.Stats().io_workers);
  EXPECT_LE(obs.max_delta_um, 1.0 + 1e-9);
}

// Accepts TCP connections on 127.0.0.1 and never sends a byte: a MODBUS terminal that hangs.
class SilentPeer {
 public:
  SilentPeer() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    int one = 1;
    ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    ok_ = ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 && ::listen(fd_, 16) == 0;
    socklen_t len = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] {
      while (!stop_.load()) {
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, 20) > 0) {
          const int c = ::accept(fd_, nullptr, nullptr);
          if (c >= 0) clients_.push_back(c);
        }
      }
    });
  }
  ~SilentPeer() {
    stop_.store(true);
    thread_.join();
    for (int c : clients_) ::close(c);
    ::close(fd_);
  }
  bool ok() const { return ok_; }
  int port() const { return port_; }

 private:
  int fd_ = -1, port_ = 0;
  bool ok_ = false;
  std::atomic<bool> stop_{false};
  std::vector<int> clients_;
  std::thread thread_;
};

TEST(TimingContract, StalledModbusTerminalDoesNotDelayACycle) {
  SilentPeer peer;
  ASSERT_TRUE(peer.ok());
  constexpr double kTimeoutS = 1.0;
  auto terminal = TerminalClients(peer.port(), kTimeoutS);
  ContractLoop loop(*terminal.cnc, *terminal.temperatures, ContractOptions(), 0.002);
  auto& obs = loop.obs;
  auto& runner = loop.runner;
  runner.Start();
  // Wait until the CNC worker has sat through at least two timeouts of the silent terminal.
  ASSERT_TRUE(WaitFor([&] { return runner.Stats().cnc_io.max_call_s >= 0.9 * kTimeoutS && obs.cycles.load() > 500; }, 60));
  runner.Stop();
  const LoopStats s = runner.Stats();
  // The worker blocked for the whole timeout; the step never did: its longest cycle is a small
  // fraction of the worker's longest call (a step waiting on the socket would take the timeout).
  EXPECT_GE(s.cnc_io.max_call_s, 0.9 * kTimeoutS);
  EXPECT_LT(s.max_cycle_s, 0.25 * s.cnc_io.max_call_s) << s.BriefReport();
  // No snapshot ever came: every cycle ran without one, as a link loss.
  EXPECT_EQ(obs.link_alarm_cycles.load(), obs.cycles.load());
  EXPECT_TRUE(loop.comp->LastStatus().alarms & kAlarmLinkRead);
  EXPECT_LE(obs.max_delta_um, 1.0 + 1e-9);
}

// The CNC side of the terminal: the largest change between two values it accepted.
class RecordingCnc : public MockCnc {
 public:
  using MockCnc::MockCnc;
  bool WriteCompensation(std::span<const double> c) override {
    if (writes > 0) max_step_um = std::max(max_step_um, std::fabs(c[0] - cnc_value_um[0]));
    return MockCnc::WriteCompensation(c);
  }
  double max_step_um = 0;
};

TEST(TimingContract, FlappingModbusTerminalNeverMakesTheOutputJump) {
  RecordingCnc plant({"X"});
  MockTemperatures plant_temps({"ambient", "nut", "bearing"}, 25.0);
  plant.axes[0] = {400, 1, true};
  drivers::ModbusMachineServerOptions so;
  so.machine_period_s = 0.001;
  std::unique_ptr<drivers::ModbusMachineServer> server;
  std::string error;
  for (int port = 21000 + static_cast<int>(::getpid() % 20000), attempt = 0; attempt < 50 && !server; ++attempt, ++port) {
    so.port = port;
    auto s = std::make_unique<drivers::ModbusMachineServer>(&plant, &plant_temps, so);
    if (s->Start(&error)) server = std::move(s);
  }
  ASSERT_NE(server, nullptr) << error;
  auto terminal = TerminalClients(so.port, 1.0);
  CompensatorOptions o = ContractOptions();
  o.link_stale_after_s = 0.5;
  o.link_loss = LinkLossPolicy::kRampToZero;
  ContractLoop loop(*terminal.cnc, *terminal.temperatures, o, 0.005);
  auto& obs = loop.obs;
  auto& runner = loop.runner;
  runner.Start();
  ASSERT_TRUE(WaitFor([&] { return std::fabs(obs.output_um.load()) > 5 && obs.raised.load() == obs.cleared.load(); }, 30));
  // The terminal goes away and comes back six times.
  int restarts = 0;
  for (int flap = 0; flap < 6; ++flap) {
    server->Stop();
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    for (int attempt = 0; attempt < 40; ++attempt) {
      server = std::make_unique<drivers::ModbusMachineServer>(&plant, &plant_temps, so);
      if (server->Start(&error)) {
        ++restarts;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ASSERT_EQ(restarts, 6) << error;
  const int raised = obs.raised.load();
  ASSERT_TRUE(WaitFor([&] { return obs.cleared.load() == obs.raised.load(); }, 30));  // recovered at the end
  runner.Stop();
  server->Stop();
  EXPECT_GE(raised, 1);  // the flaps were seen as link losses
  EXPECT_LE(obs.max_delta_um, 1.0 + 1e-9);  // and the output only ever ramped,
  EXPECT_LE(plant.max_step_um, 1.0 + 1e-9);  // as the CNC saw it too
  EXPECT_GT(plant.writes, 10);  // the CNC side did receive values between the flaps
}

}  // namespace
}  // namespace trueaxis::runtime
