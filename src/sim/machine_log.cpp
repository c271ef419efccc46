#include "trueaxis/sim/machine_log.hpp"

#include <cctype>
#include <cmath>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"

namespace trueaxis::sim {
namespace {
// Rounded to `digits` decimals, written without trailing zeros (the log stays small).
std::string LogFixed(double v, int digits) {
  const double scale = std::pow(10.0, digits);
  return FormatShortest(std::round(v * scale) / scale);
}
}  // namespace

std::string MachineLogHeader(const VirtualMachine& vm) {
  std::vector<std::string> axes, sensors;
  for (std::size_t i = 0; i < vm.AxisCount(); ++i) axes.push_back(vm.AxisName(i));
  for (std::size_t i = 0; i < vm.ChannelCount(); ++i) sensors.push_back(vm.ChannelName(i));
  return measure::CampaignLogHeader(axes, sensors);
}

std::string MachineLogRow(const VirtualMachine& vm) {
  std::string row = LogFixed(vm.TimeS(), 1) + "," + vm.IsoTime() + "," + std::string(CoolantStateName(vm.coolant()));
  for (std::size_t i = 0; i < vm.AxisCount(); ++i) row += "," + LogFixed(vm.CommandedMm(i), 3);
  for (std::size_t i = 0; i < vm.AxisCount(); ++i) row += "," + LogFixed(vm.TravelMm(i), 1);
  for (std::size_t i = 0; i < vm.SensorCount(); ++i) {
    const auto r = vm.sensor(i).Latest();
    row += "," + (r.hardware_fault || !std::isfinite(r.temp_c) ? std::string() : LogFixed(r.temp_c, 4));
  }
  return row + "\n";
}

}  // namespace trueaxis::sim
