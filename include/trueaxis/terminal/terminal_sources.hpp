#pragma once
// The temperature side of a terminal, built from its configuration: the
// 1-Wire sensors and each [[rtd]] group, each read on its own thread
// (PolledTemperatureSource), combined into one channel list in register order.
// Used by `trueaxis terminal` and its tests.
#include <memory>
#include <vector>

#include "trueaxis/terminal/combined_temperature_source.hpp"
#include "trueaxis/terminal/one_wire_temperature_source.hpp"
#include "trueaxis/terminal/polled_temperature_source.hpp"
#include "trueaxis/terminal/terminal_config.hpp"

namespace trueaxis::terminal {

struct TerminalSources {
  std::unique_ptr<CombinedTemperatureSource> combined;  // what the MODBUS server reads
  // Thread-safe views for status lines: every part's poller (in channel order), and the
  // 1-Wire source (nullptr without [one_wire]; it is the first part when present).
  std::vector<PolledTemperatureSource*> parts;
  OneWireTemperatureSource* one_wire = nullptr;
};

// Not yet configured or activated (hw lifecycle: the caller does both).
TerminalSources BuildTerminalSources(const TerminalConfig& config);

}  // namespace trueaxis::terminal
