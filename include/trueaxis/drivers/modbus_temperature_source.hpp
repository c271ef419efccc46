#pragma once
// ModbusTemperatureSource: hw::TemperatureSource over MODBUS TCP from one or
// more Advantech ADAM-6015 RTD modules (adam6015_map.hpp), e.g. the ones
// `trueaxis sim serve` emulates, or real modules on the shop network.
//
// Channel i is channel i % 7 of module i / 7 (modules in `unit_ids` order).
// On (re)connect each module's name register (40211 = 0x6015) and type codes
// (40201..) are read, so the scaling follows the range configured in the
// module, as the manual intends. Per Read(): per module one FC 03 for the AI
// values (40001..) and one FC 01 for the burn-out flags (00121..).
// hardware_fault = burn-out flag set, or the value at 0xFFFF (burn-out/over range).
// False (and `out` untouched) on any link fault; no allocation per call once connected.
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/drivers/adam6015_map.hpp"
#include "trueaxis/drivers/modbus_connection.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::drivers {

// The unit ids of the RTD modules holding `channel_count` channels, adam6015::kChannelCount per
// module, numbered from `first_unit_id` (the layout ModbusMachineServer serves).
std::vector<int> RtdModuleUnitIds(int first_unit_id, std::size_t channel_count);

struct ModbusTemperatureSourceOptions {
  ModbusEndpoint endpoint;
  std::vector<int> unit_ids = {2};          // one per ADAM-6015
  std::vector<std::string> channel_names;   // at most 7 per module; the modules do not know names
  bool read_burnout_flags = true;           // false: rely on the 0xFFFF value alone (one request less)

  bool IsValid(std::string* why) const;
};

class ModbusTemperatureSource final : public hw::TemperatureSource {
 public:
  explicit ModbusTemperatureSource(ModbusTemperatureSourceOptions options);

  std::size_t ChannelCount() const override { return options_.channel_names.size(); }
  std::string ChannelName(std::size_t channel) const override { return options_.channel_names.at(channel); }
  bool Read(std::span<hw::RawTemperature> out) override;
  // The range of the module's type code (unknown before the first connect).
  hw::MeasuringRange ChannelMeasuringRange(std::size_t channel) const override {
    const adam6015::RtdRange* r = ranges_.at(channel);
    return r ? hw::MeasuringRange{r->min_c, r->max_c} : hw::MeasuringRange{};
  }

  // hw lifecycle: Configure checks the options; Activate connects (false while the terminal is not
  // reachable — Read/Write then retry on their own); Deactivate closes the connection.
  bool Configure(std::string* error) override;
  bool Activate(std::string* error) override;
  void Deactivate() override;
  bool Connect();
  bool connected() const { return connection_.connected(); }
  const std::string& last_error() const { return error_.empty() ? connection_.last_error() : error_; }
  // The range each channel is scaled with (known after the first connect).
  const adam6015::RtdRange* ChannelRange(std::size_t channel) const { return ranges_.at(channel); }

 private:
  bool EnsureReady(bool ignore_throttle = false);
  std::size_t ModuleChannels(std::size_t k) const;
  ModbusTemperatureSourceOptions options_;
  bool options_valid_ = false;
  ModbusConnection connection_;
  std::vector<const adam6015::RtdRange*> ranges_;
  std::vector<std::uint16_t> values_;   // 7 per module
  std::vector<std::uint8_t> burnout_;   // 7 per module
  std::string error_;
};

}  // namespace trueaxis::drivers
