#include "trueaxis/station/virtual_terminal.hpp"

#include <stdexcept>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::station {

std::unique_ptr<sim::VirtualMachine> OpenVirtualMachine(const runtime::VirtualMachineConfig& v) {
  auto vm = std::make_unique<sim::VirtualMachine>(sim::ReadMachineFile(v.machine_file), v.seed);
  if (v.reciprocate) {
    for (std::size_t i = 0; i < vm->AxisCount(); ++i) {
      const double travel = vm->description().axes[i].travel_mm;
      vm->CommandReciprocate(i, 0.1 * travel, 0.9 * travel, v.feed_mm_min, v.duty);
    }
  }
  vm->SetCoolant(v.coolant);
  return vm;
}

VirtualTerminal::VirtualTerminal(const runtime::VirtualMachineConfig& config, drivers::ModbusMachineServerOptions server)
    : vm_(OpenVirtualMachine(config)) {
  for (std::size_t a = 0; a < vm_->AxisCount(); ++a) axis_names_.push_back(vm_->AxisName(a));
  for (std::size_t c = 0; c < vm_->ChannelCount(); ++c) channel_names_.push_back(vm_->ChannelName(c));
  temps_.resize(channel_names_.size());
  const std::size_t n = axis_names_.size();
  for (auto* v : {&status_.commanded_mm, &status_.actual_mm, &status_.error_um, &status_.correction_um}) v->assign(n, 0.0);
  status_.sensor_c.assign(channel_names_.size(), 0.0);
  Snapshot();
  server_ = std::make_unique<drivers::ModbusMachineServer>(vm_.get(), vm_.get(), std::move(server));
  const double scale = config.time_scale;
  server_->SetAdvance([this, scale](double wall_elapsed_s) {
    vm_->Advance(wall_elapsed_s * scale);
    Snapshot();
  });
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
