// One machine configuration through the two drivers of station::Installation
// — `run`'s periodic loop (OpenMachine + Installation + LoopRunner, the MODBUS
// client with its I/O workers) and the workshop server's one event thread —
// against the same MODBUS terminal on 127.0.0.1. Both must settle on the same
// corrections, with the temperature pipeline's calibration applied on both
// paths (the calibration shifts the thermal part by tens of µm, so a path
// without it lands elsewhere), and `run` must pick the machine up where the
// server left it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "shop_fixture.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/signal/calibration.hpp"
#include "trueaxis/station/installation.hpp"
#include "trueaxis/station/machine_connection.hpp"

namespace trueaxis::server {
namespace {

using namespace testing;

// Geometric part plus a thermal part on each axis's nut sensor: 0.01 µm/mm/°C from mid-travel.
std::string WriteThermalModel(const std::string& path) {
  model::CompositeModel m;
  m.machine = "VMC-850";
  m.revision = 1;
  for (const char* axis : {"X", "Y", "Z"}) {
    model::AxisModel a;
    a.axis = axis;
    a.key_sensors = {std::string(1, static_cast<char>(std::tolower(axis[0]))) + "_nut"};
    a.baseline_temp_c = {20};
    a.reference_position_mm = 300;  // the thermal part grows away from mid-travel (the machine parks at 0)
    for (int d = 0; d < 2; ++d) {
      auto& dm = a.directions[d];
      dm.geometric.center_mm = 300;
      dm.geometric.half_span_mm = 300;
      dm.geometric.coefficients_um = {10.0, 5.0};
      model::ThermalGains g;
      g.k_um_per_mm_per_c = {0.01};
      dm.thermal.push_back(g);
    }
    m.axes.push_back(a);
  }
  model::WriteModelFile(m, path);
  return path;
}

std::vector<double> Targets(const MachineStatus& s) {
  std::vector<double> v;
  for (const auto& a : s.axes) v.push_back(a.target_um);
  return v;
}

TEST(InstallationEquivalence, RunAndServerGiveTheSameCorrectionsOnOneTerminal) {
  const std::string dir = TempDir("equivalence");
  const std::string model = WriteThermalModel(dir + "/model.json");
  // A calibration that reads every nut sensor 6 °C warmer than it reports.
  signal::CalibrationSet cal;
  cal.reference = "reference";
  for (const char* s : {"x_nut", "y_nut", "z_nut"}) cal.sensors[s].calibration.offset_c = 6.0;
  signal::WriteCalibrationFile(dir + "/cal.json", cal);

  VirtualShopOptions vo;
  vo.time_scale = 1e-6;  // the machine stands still: both paths see the same positions and temperatures
  auto vshop = StartVirtualShop(1, vo);
  ASSERT_NE(vshop, nullptr);
  const VirtualMachineInfo vm = vshop->Machines().at(0);

  // ---- the workshop server: until the terminal holds its corrections (within a quantum) ----
  const double period_s = 0.02;
  const std::string shop_text = ShopFileFor(vshop->Machines(), "127.0.0.1", model, "", period_s, 0);
  auto serve = [&](const std::string& text, std::vector<double>& targets, std::vector<double>& applied) {
    Shop shop(ParseShopConfig(text, dir + "/shop.toml"), nullptr);
    shop.Start();
    const bool settled = WaitFor(
        [&] {
          const auto s = shop.Machine(vm.name);
          if (!s || !s->connected || s->complete_cycles < 10) return false;
          const auto now = vshop->AppliedUm(0);
          for (std::size_t a = 0; a < s->axes.size(); ++a)
            if (std::abs(now[a] - s->axes[a].target_um) > 1.0) return false;
          return true;
        },
        30);
    targets = Targets(*shop.Machine(vm.name));
    applied = vshop->AppliedUm(0);
    shop.Stop();
    return settled;
  };
  std::vector<double> uncalibrated_targets, server_targets, server_applied;
  ASSERT_TRUE(serve(shop_text, uncalibrated_targets, server_applied));
  ASSERT_TRUE(serve(shop_text + "[machine.signal]\ncalibration = \"cal.json\"\n", server_targets, server_applied));

  // ---- `run`: the same machine as a run configuration ----
  const std::string run_path = dir + "/run.toml";
  {
    auto list = [](const std::vector<std::string>& v) {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", \"" : "\"") + v[i] + "\"";
      return s + "]";
    };
    std::ofstream f(run_path);
    f << "[machine]\nkind = \"modbus\"\nhost = \"127.0.0.1\"\nport = " << vm.port << "\naxes = " << list(vm.axes)
      << "\nchannels = " << list(vm.channels) << "\n\n[model]\nfile = \"model.json\"\nreload = false\n\n[loop]\nperiod_s = "
      << period_s << "\n\n[signal]\ncalibration = \"cal.json\"\n";
  }
  const station::SiteConfig site = station::ReadSiteConfig(run_path);
  const station::InstallationConfig& c = site.installation;
  station::Machine m = station::OpenMachine(site, false);
  station::Installation installation(c, *m.link, *m.source, m.Clock(), m.name);
  runtime::LoopRunner runner(installation.compensator(), *m.link, installation.temperatures(),
                             runtime::LoopOptions{c.period_s, c.temperature_period_s});
  // Picked up where the server left the CNC: what the terminal applies never leaves the server's
  // value by more than the quantum and the hysteresis (a loop starting from its own zero would
  // write ~0 first and ramp back up, tens of µm away for a dozen cycles).
  double max_departure_um = 0;
  auto watch = [&](const std::vector<double>& applied) {
    for (std::size_t a = 0; a < applied.size(); ++a)
      max_departure_um = std::max(max_departure_um, std::abs(applied[a] - server_applied[a]));
  };
  const std::uint64_t writes_before = vshop->Stats().compensation_writes;
  runner.Start();
  ASSERT_TRUE(WaitFor(
      [&] {
        watch(vshop->AppliedUm(0));
        return !installation.compensator().PickUpPending();
      },
      10));
  std::vector<double> run_targets;
  ASSERT_TRUE(WaitFor(
      [&] {
        const auto& axes = installation.compensator().LastStatus().axes;
        const auto applied = vshop->AppliedUm(0);
        watch(applied);
        run_targets.clear();
        for (std::size_t a = 0; a < axes.size(); ++a) {
          run_targets.push_back(axes[a].desired_um);
          if (std::isnan(axes[a].desired_um) || std::abs(applied[a] - axes[a].desired_um) > 1.0) return false;
        }
        // Settled after run wrote for a while (not just the server's values still standing).
        return installation.compensator().LastStatus().temperatures_ok &&
               vshop->Stats().compensation_writes >= writes_before + 25;
      },
      30));
  const auto run_applied = vshop->AppliedUm(0);
  runner.Stop();
  m.Close();

  EXPECT_LE(max_departure_um, 2.0);
  ASSERT_EQ(run_targets.size(), server_targets.size());
  for (std::size_t a = 0; a < run_targets.size(); ++a) {
    SCOPED_TRACE(vm.axes[a]);
    // The server calibrates: the calibration's +6 °C moves the correction by 0.01·6·|x − 300| µm,
    // 18 µm at the parked axes — far beyond the tolerance below.
    EXPECT_GT(std::abs(server_targets[a] - uncalibrated_targets[a]), 10.0);
    EXPECT_NEAR(run_targets[a], server_targets[a], 0.5);
    EXPECT_NEAR(run_applied[a], server_applied[a], 2.01);  // both settled within a quantum of the target
  }
}

}  // namespace
}  // namespace trueaxis::server
