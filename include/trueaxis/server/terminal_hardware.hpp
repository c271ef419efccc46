#pragma once
// A workshop machine's asynchronous hardware (the ros2_control idea: slow
// hardware on its own schedule, the loop unchanged). The server's one event
// thread talks MODBUS to the machine's terminal on its own schedule and
// decodes the answers into these buffers; the machine's station::Installation
// reads them through hw::CncLink / hw::TemperatureSource when the thread
// calls its cycle. Nothing here blocks or allocates after construction.
//
// The command is not written through WriteCompensation: the event thread
// sends Installation::command() itself when the terminal can take it and
// reports the answer with Installation::CommitWrite().
#include <algorithm>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::server {

class TerminalCnc final : public hw::CncLink {
 public:
  explicit TerminalCnc(std::vector<std::string> axis_names)
      : names_(std::move(axis_names)), axes(names_.size()) {}
  std::size_t AxisCount() const override { return names_.size(); }
  std::string AxisName(std::size_t axis) const override { return names_[axis]; }
  bool Read(std::span<hw::AxisState> out, hw::CncState& out_machine) override {
    if (!ok) return false;
    std::copy(axes.begin(), axes.end(), out.begin());
    out_machine = machine;
    if (coolant_override) out_machine.coolant = *coolant_override;  // forced from the control API
    return true;
  }
  bool WriteCompensation(std::span<const double>) override { return false; }  // the event thread writes

 private:
  std::vector<std::string> names_;

 public:
  // ---- the event thread: the window as decoded last ----
  std::vector<hw::AxisState> axes;  // with applied_um: the pick-up without a jump
  hw::CncState machine;
  bool ok = false;                  // the last window read was good (and its heartbeat alive)
  std::optional<CoolantState> coolant_override;
};

class TerminalTemperatures final : public hw::TemperatureSource {
 public:
  explicit TerminalTemperatures(std::vector<std::string> channel_names)
      : names_(std::move(channel_names)), channels(names_.size()) {}
  std::size_t ChannelCount() const override { return names_.size(); }
  std::string ChannelName(std::size_t channel) const override { return names_[channel]; }
  bool Read(std::span<hw::RawTemperature> out) override {
    if (!ok) return false;
    std::copy(channels.begin(), channels.end(), out.begin());
    return true;
  }

 private:
  std::vector<std::string> names_;

 public:
  // ---- the event thread: the RTD modules' values as decoded last ----
  std::vector<hw::RawTemperature> channels;
  bool ok = false;
};

}  // namespace trueaxis::server
