#pragma once
// ModbusCncLink: hw::CncLink over MODBUS TCP against the PMC window of
// ModbusMachineServer (`trueaxis sim serve`, or a real terminal laid out the
// same way; docs/protocols.md). The runtime cannot tell it from the virtual
// machine in process.
//
// Read(): one FC 04 request for the whole window. False when the link is down,
// the reply is bad, the server reports it cannot read the CNC, or the
// heartbeat has not moved for stale_after_s (the terminal answers but its
// machine side is frozen).
// WriteCompensation(): one FC 16 request for every axis at once (the CNC never
// sees half a vector). False on any fault, including a value the terminal
// refuses (beyond its bound).
// After a fault, calls fail at once until reconnect_interval_s has passed,
// then one reconnect is tried. No exceptions; no allocation per call once
// connected (buffers are sized at construction).
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/drivers/modbus_connection.hpp"
#include "trueaxis/drivers/pmc_window_map.hpp"
#include "trueaxis/drivers/terminal_registers.hpp"
#include "trueaxis/hw/cnc_link.hpp"

namespace trueaxis::drivers {

struct ModbusCncLinkOptions {
  ModbusEndpoint endpoint;
  int unit_id = pmc::kDefaultUnitId;
  std::vector<std::string> axis_names = {"X", "Y", "Z"};  // must match the window's axis count
  double stale_after_s = 0.5;  // heartbeat frozen longer than this = link fault

  bool IsValid(std::string* why) const;
};

class ModbusCncLink final : public hw::CncLink {
 public:
  explicit ModbusCncLink(ModbusCncLinkOptions options);

  std::size_t AxisCount() const override { return options_.axis_names.size(); }
  std::string AxisName(std::size_t axis) const override { return options_.axis_names.at(axis); }
  bool Read(std::span<hw::AxisState> axes, hw::CncState& machine) override;
  bool WriteCompensation(std::span<const double> correction_um) override;
  // One MODBUS transaction where the terminal allows it: writes the command block and reads the
  // window (its copy in holding registers 100…) with one FC 23. A terminal that refuses FC 23
  // (exception 0x01 or 0x02: an older one) is asked with FC 16 then FC 04 from then on, until
  // the next reconnect. True when the write and the read both succeeded (the read as Read()).
  bool WriteAndRead(std::span<const double> correction_um, std::span<hw::AxisState> axes, hw::CncState& machine);
  // The terminal answered FC 23 on this connection (false before the first WriteAndRead).
  bool read_write_answered() const { return read_write_ == ReadWrite::kAnswered; }

  // Tries to connect now (ignores the reconnect throttle's first wait).
  // hw lifecycle: Configure checks the options; Activate connects (false while the terminal is not
  // reachable — Read/Write then retry on their own); Deactivate closes the connection.
  bool Configure(std::string* error) override;
  bool Activate(std::string* error) override;
  void Deactivate() override;
  bool Connect();
  bool connected() const { return connection_.connected(); }
  const std::string& last_error() const { return error_.empty() ? connection_.last_error() : error_; }
  std::uint32_t last_heartbeat() const { return heartbeat_.heartbeat; }
  std::uint64_t reconnects() const { return connection_.connect_count(); }
  // Compensation the CNC reports it applies now (µm), from the last Read().
  const std::vector<double>& applied_um() const { return applied_um_; }

 private:
  bool EnsureReady(bool ignore_throttle = false);
  bool DecodeWindow(std::span<hw::AxisState> axes, hw::CncState& machine);
  enum class ReadWrite { kUnknown, kAnswered, kRefused };
  ReadWrite read_write_ = ReadWrite::kUnknown;
  bool options_valid_ = false;
  ModbusCncLinkOptions options_;
  ModbusConnection connection_;
  std::vector<std::uint16_t> window_;  // input registers 0..InputWindowLength(N)
  std::vector<std::uint16_t> out_;     // compensation registers
  std::vector<double> applied_um_;
  std::string error_;                  // handshake errors (wrong layout/axis count)
  HeartbeatWatch heartbeat_;
};

}  // namespace trueaxis::drivers
