#include "trueaxis/linuxcnc/hal_temperatures.hpp"

#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/hw/no_temperature_source.hpp"
#include "trueaxis/linuxcnc/hal_temperature_source.hpp"

namespace trueaxis::linuxcnc {

HalTemperatures OpenHalTemperatures(HalComponent& component, const station::SiteConfig& c, bool from_hal_pins) {
  HalTemperatures t;
  if (c.modbus.channel_names.empty()) {
    t.own = std::make_unique<hw::NoTemperatureSource>();  // a geometric-only model: no channels to read
  } else if (from_hal_pins) {
    t.own = std::make_unique<HalTemperatureSource>(component, c.modbus.channel_names);
  } else {
    t.modbus = station::MakeModbusClients(c.modbus, c.source());
    std::string why;
    if (!t.modbus.temperatures->Configure(&why)) throw InputError(c.source(), 0, "machine", why);
    if (!t.modbus.temperatures->Activate(&why))
      fmt::print(stderr, "warning: RTD modules at {}:{} not reachable yet ({}); the loop keeps trying\n", c.modbus.host,
                 c.modbus.port, why);
  }
  t.source = t.own ? t.own.get() : t.modbus.temperatures.get();
  return t;
}

}  // namespace trueaxis::linuxcnc
