#include "trueaxis/station/virtual_terminal.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/campaign/campaign_clock.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::station {

void StartProgram(sim::VirtualMachine& vm, const VirtualMachineConfig& v) {
  if (!v.reciprocate) return;
  for (std::size_t i = 0; i < vm.AxisCount(); ++i) {
    const double travel = vm.description().axes[i].travel_mm;
    vm.CommandReciprocate(i, 0.1 * travel, 0.9 * travel, v.feed_mm_min, v.duty);
  }
}

std::unique_ptr<sim::VirtualMachine> OpenVirtualMachine(const VirtualMachineConfig& v) {
  auto vm = std::make_unique<sim::VirtualMachine>(sim::ReadMachineFile(v.machine_file), v.seed);
  StartProgram(*vm, v);
  vm->SetCoolant(v.coolant);
  return vm;
}

VirtualTerminal::VirtualTerminal(const VirtualMachineConfig& config, drivers::ModbusMachineServerOptions server)
    : config_(config), vm_(OpenVirtualMachine(config)) {
  for (std::size_t a = 0; a < vm_->AxisCount(); ++a) axis_names_.push_back(vm_->AxisName(a));
  for (std::size_t c = 0; c < vm_->ChannelCount(); ++c) channel_names_.push_back(vm_->ChannelName(c));
  temps_.resize(channel_names_.size());
  const std::size_t n = axis_names_.size();
  for (auto* v : {&status_.commanded_mm, &status_.actual_mm, &status_.error_um, &status_.correction_um}) v->assign(n, 0.0);
  status_.sensor_c.assign(channel_names_.size(), 0.0);
  Snapshot();
  server_ = std::make_unique<drivers::ModbusMachineServer>(vm_.get(), vm_.get(), std::move(server));
  server_->SetAdvance([this](double wall_elapsed_s) { Advance(wall_elapsed_s); });
}

void VirtualTerminal::SetLaser(const ServedLaser& laser) {
  const int axis = vm_->description().AxisIndex(laser.axis);
  if (axis < 0) throw InputError("command line", 0, "--laser-axis", fmt::format("the machine has no axis '{}'", laser.axis));
  if (laser.out_dir.empty()) throw InputError("command line", 0, "--laser-out", "name the folder for the laser files");
  sim::LaserOptions lo;
  lo.runs = laser.runs;
  lo.spacing_mm = laser.spacing_mm;
  std::string why;
  if (!lo.IsValid(&why)) throw InputError("command line", 0, "--laser-runs", why);
  std::filesystem::create_directories(laser.out_dir);
  laser_ = laser;
  laser_axis_ = static_cast<std::size_t>(axis);
  interferometer_ = std::make_unique<sim::LaserInterferometer>(lo, config_.seed * 7919 + 17);
  next_laser_s_ = vm_->TimeS() + laser.first_s;
  for (std::size_t i = 0; i < vm_->AxisCount(); ++i) vm_->CommandStop(i);  // soaked until the cold test
}

int VirtualTerminal::LaserTests() const { return laser_tests_.load(); }

void VirtualTerminal::Advance(double wall_elapsed_s) {
  double dt = wall_elapsed_s * config_.time_scale;
  // A laser test runs in machine time at once; the machine stands for as long in scaled wall time,
  // before the test (by the last test's duration: what the channels show during the test is the
  // machine as the test starts) and after it for what the test took longer.
  const double pause = std::min(dt, pause_s_);
  pause_s_ -= pause;
  dt -= pause;
  if (laser_due_ && pause_s_ <= 0) {
    laser_due_ = false;
    TakeLaserTest();
  }
  if (dt > 0 && pause_s_ <= 0) vm_->Advance(dt);
  if (laser_ && !laser_due_ && vm_->TimeS() >= next_laser_s_ &&
      (laser_->count <= 0 || laser_tests_.load() < laser_->count)) {
    laser_due_ = true;
    laser_wall_start_ = campaign::WallClockNowS();
    for (std::size_t i = 0; i < vm_->AxisCount(); ++i) vm_->CommandStop(i);
    pause_s_ = last_laser_s_;
    if (pause_s_ <= 0) {
      laser_due_ = false;
      TakeLaserTest();
    }
  }
  Snapshot();
}

void VirtualTerminal::TakeLaserTest() {
  const double wall_start = laser_wall_start_;
  const double before = vm_->TimeS();
  for (std::size_t i = 0; i < vm_->AxisCount(); ++i) vm_->CommandStop(i);
  interferometer_->Setup(*vm_, laser_axis_, vm_->description().axes[laser_axis_].reference_mm);
  const double t0 = vm_->TimeS();
  measure::Measurement m = interferometer_->Measure(*vm_, laser_->runs, {});
  // What laser software knows: its own clock and the machine's axis, not the machine's sensors.
  m.SetMeta("date", campaign::FormatCampaignDate(wall_start + (t0 - before) / config_.time_scale, 3));
  m.sensor_names.clear();
  for (auto& p : m.points) p.temperatures_c.clear();
  const int n = laser_tests_.load() + 1;
  const std::filesystem::path out =
      std::filesystem::path(laser_->out_dir) / fmt::format("{}_laser_{:03}.csv", laser_->axis, n);
  measure::WriteMeasurementCsv(m, out.string() + ".tmp");
  std::filesystem::rename(out.string() + ".tmp", out);
  const double took = vm_->TimeS() - before;
  pause_s_ += std::max(0.0, took - last_laser_s_);
  last_laser_s_ = took;
  next_laser_s_ = before + laser_->every_s;
  if (next_laser_s_ < vm_->TimeS()) next_laser_s_ = vm_->TimeS();
  StartProgram(*vm_, config_);
  laser_tests_.store(n);
}

VirtualTerminal::~VirtualTerminal() { Stop(); }

void VirtualTerminal::Start() {
  std::string why;
  if (!server_->Start(&why)) throw std::runtime_error(why);
}

void VirtualTerminal::Stop() {
  if (server_) server_->Stop();
}

void VirtualTerminal::Snapshot() {
  vm_->Read(temps_);
  std::lock_guard<std::mutex> lock(mu_);
  status_.machine_time_s = vm_->TimeS();
  status_.iso_time = vm_->IsoTime();
  status_.coolant = std::string(CoolantStateName(vm_->coolant()));
  for (std::size_t a = 0; a < axis_names_.size(); ++a) {
    status_.commanded_mm[a] = vm_->CommandedMm(a);
    status_.actual_mm[a] = vm_->ActualMm(a);
    status_.error_um[a] = vm_->ErrorUm(a);
    status_.correction_um[a] = vm_->CorrectionUm(a);
  }
  for (std::size_t c = 0; c < temps_.size(); ++c) status_.sensor_c[c] = temps_[c].temp_c;
}

VirtualTerminalStatus VirtualTerminal::Status() const {
  std::lock_guard<std::mutex> lock(mu_);
  return status_;
}

}  // namespace trueaxis::station
