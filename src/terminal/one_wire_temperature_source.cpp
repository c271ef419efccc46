#include "trueaxis/terminal/one_wire_temperature_source.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <fmt/format.h>

namespace trueaxis::terminal {
namespace fs = std::filesystem;

bool OneWireOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (root.empty()) return fail("root is empty");
  if (sensors.empty()) return fail("no sensors");
  std::set<std::string> ids, names;
  for (const auto& s : sensors) {
    if (s.id.empty() || s.id.find('/') != std::string::npos || s.id == "." || s.id == "..")
      return fail(fmt::format("sensor id '{}' is not a sysfs directory name", s.id));
    if (s.channel.empty()) return fail(fmt::format("sensor '{}' has no channel name", s.id));
    if (!ids.insert(s.id).second) return fail(fmt::format("sensor '{}' is listed twice", s.id));
    if (!names.insert(s.channel).second) return fail(fmt::format("channel '{}' is named twice", s.channel));
  }
  return true;
}

const char* OneWireChannelStateName(OneWireChannelState state) {
  switch (state) {
    case OneWireChannelState::kNeverRead: return "never_read";
    case OneWireChannelState::kOk: return "ok";
    case OneWireChannelState::kCrcError: return "crc_error";
    case OneWireChannelState::kNoResponse: return "no_response";
    case OneWireChannelState::kMalformed: return "malformed";
    case OneWireChannelState::kOutOfRange: return "out_of_range";
    case OneWireChannelState::kPowerOnValue: return "power_on_value";
    case OneWireChannelState::kMissing: return "missing";
  }
  return "?";
}

OneWireTemperatureSource::OneWireTemperatureSource(OneWireOptions options)
    : options_(std::move(options)), status_(options_.sensors.size()), pending_power_on_(options_.sensors.size(), false) {}

bool OneWireTemperatureSource::Configure(std::string* error) { return options_.IsValid(error); }

std::vector<std::string> OneWireTemperatureSource::UnmappedSensors() const {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(options_.root, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("28-", 0) != 0) continue;  // DS18B20 family code 0x28
    const bool mapped = std::any_of(options_.sensors.begin(), options_.sensors.end(), [&](const auto& s) { return s.id == name; });
    if (!mapped) out.push_back(name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

hw::RawTemperature OneWireTemperatureSource::ReadChannel(std::size_t i) {
  // The file read (a whole conversion on real hardware) happens without the lock.
  std::string text;
  const char* missing = nullptr;
  const fs::path dir = fs::path(options_.root) / options_.sensors[i].id;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    missing = "sensor directory is gone";
  } else {
    std::ifstream in(dir / "w1_slave", std::ios::binary);
    std::ostringstream buffer;
    if (!in) missing = "w1_slave cannot be opened";
    else if (buffer << in.rdbuf(); in.bad()) missing = "w1_slave read error";
    text = buffer.str();
  }
  std::lock_guard<std::mutex> lock(mu_);
  return Judge(i, missing, text);
}

hw::RawTemperature OneWireTemperatureSource::Judge(std::size_t i, const char* missing, const std::string& text) {
  OneWireChannelStatus& st = status_[i];
  const hw::RawTemperature fault{std::numeric_limits<double>::quiet_NaN(), true};
  auto fail = [&](OneWireChannelState state, std::string detail) {
    if (state == OneWireChannelState::kMissing && st.state != OneWireChannelState::kMissing) ++st.losses;
    st.state = state;
    st.detail = std::move(detail);
    ++st.failed_reads;
    if (state != OneWireChannelState::kPowerOnValue) pending_power_on_[i] = false;
    return fault;
  };
  if (missing) return fail(OneWireChannelState::kMissing, missing);
  const W1SlaveReading r = ParseW1Slave(text);
  switch (r.status) {
    case W1SlaveStatus::kCrcError: return fail(OneWireChannelState::kCrcError, "CRC check failed (crc=.. NO)");
    case W1SlaveStatus::kNoResponse: return fail(OneWireChannelState::kNoResponse, "all-zero scratchpad: the sensor did not answer");
    case W1SlaveStatus::kMalformed: return fail(OneWireChannelState::kMalformed, r.why);
    case W1SlaveStatus::kOk: break;
  }
  const double temp_c = static_cast<double>(r.milli_c) / 1000.0;
  if (temp_c < kDs18b20MinC || temp_c > kDs18b20MaxC)
    return fail(OneWireChannelState::kOutOfRange, fmt::format("{} °C is outside the DS18B20's range", temp_c));
  if (r.milli_c == kDs18b20PowerOnMilliC) {
    const bool near_85 = st.good_reads > 0 && std::abs(st.last_good_c - 85.0) <= 1.0;
    if (!pending_power_on_[i] && !near_85) {
      pending_power_on_[i] = true;
      ++st.power_on_refused;
      return fail(OneWireChannelState::kPowerOnValue, "85.000 °C power-on value, refused until the next read confirms it");
    }
  }
  pending_power_on_[i] = false;
  st.state = OneWireChannelState::kOk;
  st.detail.clear();
  st.last_good_c = temp_c;
  ++st.good_reads;
  return {temp_c, false};
}

std::vector<OneWireChannelStatus> OneWireTemperatureSource::StatusSnapshot() const {
  std::lock_guard<std::mutex> lock(mu_);
  return status_;
}

bool OneWireTemperatureSource::Read(std::span<hw::RawTemperature> out) {
  std::error_code ec;
  if (!fs::is_directory(options_.root, ec)) return false;
  for (std::size_t i = 0; i < options_.sensors.size() && i < out.size(); ++i) out[i] = ReadChannel(i);
  return true;
}

}  // namespace trueaxis::terminal
