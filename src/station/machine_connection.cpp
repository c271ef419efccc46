#include "trueaxis/station/machine_connection.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/signal/calibration.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/station/virtual_terminal.hpp"

namespace trueaxis::station {

ModbusClients MakeModbusClients(const ModbusConfig& b, const std::string& source,
                                double heartbeat_stale_after_s) {
  drivers::ModbusEndpoint ep;
  ep.host = b.host;
  ep.port = b.port;
  ep.response_timeout_s = b.response_timeout_s;
  drivers::ModbusCncLinkOptions co;
  co.endpoint = ep;
  co.unit_id = b.cnc_unit_id;
  co.axis_names = b.axis_names;
  co.stale_after_s = heartbeat_stale_after_s;
  drivers::ModbusTemperatureSourceOptions to;
  to.endpoint = ep;
  to.channel_names = b.channel_names;
  to.unit_ids = drivers::RtdModuleUnitIds(b.first_rtd_unit_id, b.channel_names.size());
  std::string why;
  if (!co.IsValid(&why)) throw InputError(source, 0, "machine", why);
  const bool rtd = !b.channel_names.empty();  // no channels: no RTD modules (a geometric-only model)
  if (rtd && !to.IsValid(&why)) throw InputError(source, 0, "machine", why);
  ModbusClients c;
  c.cnc = std::make_unique<drivers::ModbusCncLink>(co);
  if (rtd) c.temperatures = std::make_unique<drivers::ModbusTemperatureSource>(to);
  return c;
}

namespace {

void OpenVirtual(const SiteConfig& c, Machine& m) {
  const auto& v = c.virtual_machine;
  c.installation.RequireFile("machine.file", v.machine_file);
  m.vm = OpenVirtualMachine(v);
  m.name = m.vm->description().name;
  sim::VirtualMachine* vm = m.vm.get();
  const double scale = v.time_scale;
  m.advance = [vm, scale](double dt) { vm->Advance(dt * scale); };
  m.link = vm;
  m.source = vm;
  m.description = fmt::format("virtual machine {} ({}, seed {}, time ×{})", vm->description().name, v.machine_file,
                              v.seed, v.time_scale);
}

void OpenModbus(const SiteConfig& c, Machine& m) {
  const auto& b = c.modbus;
  // The PMC window and the RTD modules share one terminal: their unit ids must differ and stay
  // within MODBUS's 247 (the RTD modules hold 7 channels each, unit ids from first_rtd_unit_id).
  // No channels: no RTD modules are read (a model that needs a sensor is refused when published).
  const std::vector<int> rtd_units =
      b.channel_names.empty() ? std::vector<int>{} : drivers::RtdModuleUnitIds(b.first_rtd_unit_id, b.channel_names.size());
  if (!rtd_units.empty() && rtd_units.back() > 247)
    throw InputError(c.source(), c.LineOf("machine.first_rtd_unit_id"), "machine.first_rtd_unit_id",
                     fmt::format("{} channels need {} RTD modules: unit ids {}..{} go beyond 247", b.channel_names.size(),
                                 rtd_units.size(), rtd_units.front(), rtd_units.back()));
  if (std::find(rtd_units.begin(), rtd_units.end(), b.cnc_unit_id) != rtd_units.end())
    throw InputError(c.source(), c.LineOf("machine.cnc_unit_id"), "machine.cnc_unit_id",
                     fmt::format("{} is also an RTD module's unit id ({}..{} from first_rtd_unit_id)", b.cnc_unit_id,
                                 rtd_units.front(), rtd_units.back()));
  m.modbus = MakeModbusClients(b, c.source());
  m.name = b.machine_name;
  // The hardware lifecycle: configure (options), activate (connect; a terminal not reachable yet is
  // a warning — its Read/Write fail and retry on their own).
  std::string why;
  if (!m.modbus.cnc->Configure(&why) || (m.modbus.temperatures && !m.modbus.temperatures->Configure(&why)))
    throw InputError(c.source(), 0, "machine", why);
  if (!m.modbus.cnc->Activate(&why))
    m.warnings.push_back(fmt::format("CNC terminal {}:{} not reachable yet ({}); the loop keeps trying", b.host, b.port, why));
  if (m.modbus.temperatures && !m.modbus.temperatures->Activate(&why))
    m.warnings.push_back(fmt::format("RTD modules at {}:{} not reachable yet ({}); the loop keeps trying", b.host, b.port, why));
  m.link = m.modbus.cnc.get();
  if (m.modbus.temperatures) {
    m.source = m.modbus.temperatures.get();
  } else {
    m.no_temperatures = std::make_unique<hw::NoTemperatureSource>();
    m.source = m.no_temperatures.get();
  }
  m.description = m.modbus.temperatures ? fmt::format("MODBUS TCP {}:{} (PMC unit {}, RTD units from {})", b.host, b.port,
                                                      b.cnc_unit_id, b.first_rtd_unit_id)
                                        : fmt::format("MODBUS TCP {}:{} (PMC unit {}, no temperature channels)", b.host,
                                                      b.port, b.cnc_unit_id);
}

}  // namespace

std::function<double()> Machine::Clock() const {
  if (vm) {
    const sim::VirtualMachine* v = vm.get();
    return [v] { return v->TimeS(); };  // machine time: rates are judged in the machine's seconds
  }
  const auto t0 = std::chrono::steady_clock::now();
  return [t0] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
}

std::unique_ptr<signal::MonitoredTemperatureSource> MakeTemperaturePipeline(const InstallationConfig& c,
                                                                            hw::TemperatureSource& raw,
                                                                            std::function<double()> clock_s,
                                                                            std::vector<std::string>* warnings) {
  std::vector<std::string> channels;
  for (std::size_t i = 0; i < raw.ChannelCount(); ++i) channels.push_back(raw.ChannelName(i));
  for (const auto& group : c.redundant_groups)
    for (const auto& name : group)
      if (std::find(channels.begin(), channels.end(), name) == channels.end())
        throw InputError(c.source, c.redundant_groups_line, "signal.groups",
                         fmt::format("'{}' is not a temperature channel of the machine ({})", name, fmt::join(channels, ", ")));
  auto pipeline = std::make_unique<signal::MonitoredTemperatureSource>(raw, TemperatureJudgeOptions(c), std::move(clock_s));
  if (!c.calibration_file.empty()) {
    c.RequireFile("signal.calibration", c.calibration_file);
    for (const auto& name : pipeline->monitor().SetCalibration(signal::ReadCalibrationFile(c.calibration_file)))
      if (warnings) warnings->push_back(fmt::format("calibration for '{}' matches no channel of the machine", name));
  }
  return pipeline;
}

Machine OpenMachine(const SiteConfig& c, bool with_pipeline) {
  Machine m;
  if (c.machine == MachineKind::kVirtual) OpenVirtual(c, m);
  else OpenModbus(c, m);
  for (std::size_t k = 0; k < c.installation.axes.size(); ++k) {
    const auto& a = c.installation.axes[k];
    bool found = false;
    std::vector<std::string> names;
    for (std::size_t i = 0; i < m.link->AxisCount(); ++i) {
      names.push_back(m.link->AxisName(i));
      found = found || names.back() == a.axis;
    }
    const std::string key = fmt::format("axis[{}].name", k);
    if (!found)
      throw InputError(c.source(), c.LineOf(key), key,
                       fmt::format("the machine has no axis '{}' (its axes: {})", a.axis, fmt::join(names, ", ")));
  }
  if (with_pipeline) m.monitored = MakeTemperaturePipeline(c.installation, *m.source, m.Clock(), &m.warnings);
  return m;
}

void Machine::Close() {
  if (link) link->Deactivate();
  if (modbus.temperatures) modbus.temperatures->Deactivate();
}

}  // namespace trueaxis::station
