#include "trueaxis/drivers/modbus_temperature_source.hpp"

#include <modbus.h>

#include <cerrno>

#include <fmt/format.h>

#include "trueaxis/drivers/terminal_registers.hpp"

namespace trueaxis::drivers {

std::vector<int> RtdModuleUnitIds(int first_unit_id, std::size_t channel_count) {
  std::vector<int> ids;
  for (std::size_t k = 0; k * adam6015::kChannelCount < channel_count; ++k) ids.push_back(first_unit_id + static_cast<int>(k));
  return ids;
}

bool ModbusTemperatureSourceOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (!endpoint.IsValid(why)) return false;
  if (unit_ids.empty()) return fail("unit_ids is empty: name at least one ADAM-6015");
  for (int id : unit_ids)
    if (id < 0 || id > 255) return fail(fmt::format("unit id {} is outside 0..255", id));
  if (channel_names.empty()) return fail("channel_names is empty");
  if (channel_names.size() > unit_ids.size() * adam6015::kChannelCount)
    return fail(fmt::format("{} channel names but {} modules hold only {} channels", channel_names.size(), unit_ids.size(),
                            unit_ids.size() * adam6015::kChannelCount));
  return true;
}

ModbusTemperatureSource::ModbusTemperatureSource(ModbusTemperatureSourceOptions options)
    : options_(std::move(options)), connection_(options_.endpoint) {
  std::string why;
  options_valid_ = options_.IsValid(&why);
  if (!options_valid_) error_ = "invalid ModbusTemperatureSource options: " + why;
  ranges_.assign(options_.channel_names.size(), nullptr);
  values_.assign(options_.unit_ids.size() * adam6015::kChannelCount, 0);
  burnout_.assign(options_.unit_ids.size() * adam6015::kChannelCount, 0);
}

std::size_t ModbusTemperatureSource::ModuleChannels(std::size_t k) const {
  return RtdModuleChannels(options_.channel_names.size(), k);
}

bool ModbusTemperatureSource::Configure(std::string* error) {
  if (!options_valid_ && error) *error = error_;
  return options_valid_;
}

bool ModbusTemperatureSource::Activate(std::string* error) {
  const bool ok = Connect();
  if (!ok && error) *error = last_error();
  return ok;
}

void ModbusTemperatureSource::Deactivate() { connection_.Close(); }

bool ModbusTemperatureSource::Connect() { return EnsureReady(true); }

bool ModbusTemperatureSource::EnsureReady(bool ignore_throttle) {
  if (!options_valid_) return false;
  bool fresh = false;
  if (!connection_.Ensure(&fresh, ignore_throttle)) return false;
  if (!fresh) return true;
  for (std::size_t k = 0; k < options_.unit_ids.size(); ++k) {
    const std::size_t n = ModuleChannels(k);
    if (n == 0) continue;
    const int unit = options_.unit_ids[k];
    std::uint16_t name = 0;
    if (!connection_.ReadHoldingRegisters(unit, adam6015::kModuleNameAddress, 1, &name)) {
      if (connection_.connected()) connection_.Fault("module name");
      return false;
    }
    if (name != adam6015::kModuleName) {
      error_ = fmt::format("{}:{} unit {}: module name register 40211 reads 0x{:04X}, not an ADAM-6015 (0x6015)",
                           options_.endpoint.host, options_.endpoint.port, unit, name);
      errno = EMBBADDATA;
      connection_.Fault("handshake");
      return false;
    }
    std::uint16_t codes[adam6015::kChannelCount];
    if (!connection_.ReadHoldingRegisters(unit, adam6015::kTypeCodeAddress, static_cast<int>(n), codes)) {
      if (connection_.connected()) connection_.Fault("type codes");
      return false;
    }
    for (std::size_t c = 0; c < n; ++c) {
      const auto* r = FindRtdRange(codes[c]);
      if (!r) {
        error_ = fmt::format("{}:{} unit {} channel {}: type code 0x{:04X} (register {}) is not an RTD range",
                             options_.endpoint.host, options_.endpoint.port, unit, c, codes[c], 40201 + c);
        errno = EMBBADDATA;
        connection_.Fault("handshake");
        return false;
      }
      ranges_[k * adam6015::kChannelCount + c] = r;
    }
  }
  error_.clear();
  return true;
}

bool ModbusTemperatureSource::Read(std::span<hw::RawTemperature> out) {
  const std::size_t channels = ChannelCount();
  if (out.size() < channels) return false;
  if (!EnsureReady()) return false;
  for (std::size_t k = 0; k < options_.unit_ids.size(); ++k) {
    const std::size_t n = ModuleChannels(k);
    if (n == 0) continue;
    const int unit = options_.unit_ids[k];
    std::uint16_t* v = &values_[k * adam6015::kChannelCount];
    std::uint8_t* b = &burnout_[k * adam6015::kChannelCount];
    if (!connection_.ReadHoldingRegisters(unit, adam6015::kAiValueAddress, static_cast<int>(n), v)) return false;
    if (options_.read_burnout_flags &&
        !connection_.ReadCoils(unit, adam6015::kBurnoutCoilAddress, static_cast<int>(n), b))
      return false;
  }
  for (std::size_t ch = 0; ch < channels; ++ch)
    out[ch] = DecodeRtdChannel(values_[ch], options_.read_burnout_flags && burnout_[ch] != 0, *ranges_[ch]);
  return true;
}

}  // namespace trueaxis::drivers
