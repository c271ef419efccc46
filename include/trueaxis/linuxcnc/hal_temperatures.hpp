#pragma once
// The temperature channels of trueaxis-hal (docs/linuxcnc.md): none for a geometric-only
// configuration (channels = []), HAL pins C.temp.NAME (--temperatures hal), or the RTD modules of
// the run configuration's [machine] over MODBUS TCP (--temperatures modbus). Raw readings: the
// caller puts the temperature pipeline in front when it wants one.
#include <memory>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/linuxcnc/hal_component.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/station/machine_connection.hpp"

namespace trueaxis::linuxcnc {

struct HalTemperatures {
  std::unique_ptr<hw::TemperatureSource> own;  // no channels, or the HAL pins
  station::ModbusClients modbus;               // the RTD modules
  hw::TemperatureSource* source = nullptr;     // whichever of the two
};

// Creates the pins (before component.Ready) or connects to the RTD modules; an unreachable
// terminal is a warning on stderr (the reader keeps trying). InputError(config.source) when the
// MODBUS client refuses the configuration.
HalTemperatures OpenHalTemperatures(HalComponent& component, const station::SiteConfig& config, bool from_hal_pins);

}  // namespace trueaxis::linuxcnc
