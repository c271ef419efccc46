#pragma once
// The configuration of `trueaxis terminal` (terminal.toml, docs/terminal.md):
// what the machine's terminal reads (DS18B20 sensors on the 1-Wire bus, RTD
// modules over MODBUS TCP, optionally a CNC over MODBUS) and how it serves
// them to the workshop server (the register map of docs/protocols.md).
#include <string>
#include <vector>

#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "trueaxis/terminal/one_wire_temperature_source.hpp"

namespace trueaxis::terminal {

struct PollSettings {
  double period_s = 1.0;       // how often the reader thread reads the source
  double stale_after_s = 5.0;  // no completed read for this long = temperatures offline
};

struct OneWireSection {
  bool present = false;
  OneWireOptions options;
  PollSettings poll;  // default stale_after_s: max(5 s, 2 × 0.75 s × sensors + 2 × period): a pass converts one sensor after the other
};

struct RtdSection {
  drivers::ModbusTemperatureSourceOptions options;
  PollSettings poll{0.2, 2.0};
};

enum class CncKind { kNone, kModbus };

struct TerminalConfig {
  std::string source;
  drivers::ModbusMachineServerOptions server;
  OneWireSection one_wire;
  std::vector<RtdSection> rtd;
  CncKind cnc = CncKind::kNone;
  drivers::ModbusCncLinkOptions cnc_link;
  // Every channel name served, in register order (1-Wire first, then each [[rtd]] group).
  std::vector<std::string> ChannelNames() const;
};

// Throws InputError naming file, line and key.
TerminalConfig ParseTerminalConfig(const std::string& text, const std::string& source);
TerminalConfig ReadTerminalConfig(const std::string& path);

}  // namespace trueaxis::terminal
