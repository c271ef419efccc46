#pragma once
// OneWireTemperatureSource: DS18B20 sensors through the Linux 1-Wire sysfs
// interface (w1-gpio + w1-therm): channel i reads
// <root>/<sensor id>/w1_slave, e.g. /sys/bus/w1/devices/28-0316a2794aff/w1_slave.
// Sensor ids are mapped to channel names by the terminal's configuration
// (docs/terminal.md).
//
// Per read and channel (hardware_fault = true and temp_c = NaN unless OK):
//  * CRC NO, all-zero scratchpad, a file that is not the two-line format,
//    a value outside the DS18B20's −55…125 °C: a failed read.
//  * a sensor directory that is gone: the channel is lost; it comes back by
//    itself with the first good read once the directory is there again.
//  * exactly 85.000 °C (the power-on value of the temperature register): refused
//    unless confirmed — the read after an 85000 also says 85000, or the last
//    accepted reading of the channel was within 1 °C of 85 °C (a real
//    temperature passing through 85). A sensor that lost power answers 85000
//    once and then a real conversion, so a single 85000 never reaches the
//    compensation.
// Read() returns false (a link fault) only when <root> itself is missing
// (no 1-Wire bus master).
//
// Reading w1_slave makes the kernel start a conversion and wait ~750 ms per
// sensor: Read() blocks that long. The terminal therefore runs it on its own
// thread (PolledTemperatureSource), never on the machine thread.
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/terminal/w1_slave.hpp"

namespace trueaxis::terminal {

struct OneWireSensor {
  std::string id;       // sysfs directory name, "28-0316a2794aff"
  std::string channel;  // channel name, "x_nut"
};

struct OneWireOptions {
  std::string root = "/sys/bus/w1/devices";
  std::vector<OneWireSensor> sensors;
  bool IsValid(std::string* why) const;
};

enum class OneWireChannelState { kNeverRead, kOk, kCrcError, kNoResponse, kMalformed, kOutOfRange, kPowerOnValue, kMissing };
const char* OneWireChannelStateName(OneWireChannelState state);

struct OneWireChannelStatus {
  OneWireChannelState state = OneWireChannelState::kNeverRead;
  double last_good_c = 0;    // meaningful when good_reads > 0
  std::uint64_t good_reads = 0;
  std::uint64_t failed_reads = 0;       // everything but kOk
  std::uint64_t power_on_refused = 0;   // 85000 refused (pending confirmation)
  std::uint64_t losses = 0;             // times the directory disappeared
  std::string detail;                   // why the last read failed
};

class OneWireTemperatureSource final : public hw::TemperatureSource {
 public:
  explicit OneWireTemperatureSource(OneWireOptions options);

  std::size_t ChannelCount() const override { return options_.sensors.size(); }
  std::string ChannelName(std::size_t channel) const override { return options_.sensors.at(channel).channel; }
  bool Read(std::span<hw::RawTemperature> out) override;
  // The DS18B20's datasheet range, −55 … 125 °C.
  hw::MeasuringRange ChannelMeasuringRange(std::size_t) const override { return {kDs18b20MinC, kDs18b20MaxC}; }
  bool Configure(std::string* error) override;

  // Per channel, copied under a lock: safe from another thread than Read()'s.
  std::vector<OneWireChannelStatus> StatusSnapshot() const;
  // Sensor ids present under root that no channel names (for the startup message).
  std::vector<std::string> UnmappedSensors() const;

 private:
  hw::RawTemperature ReadChannel(std::size_t i);
  // The verdict on one read (mu_ held): `missing` = why the file could not be read, else its text.
  hw::RawTemperature Judge(std::size_t i, const char* missing, const std::string& text);
  OneWireOptions options_;
  mutable std::mutex mu_;  // guards status_ and pending_power_on_ (never held during a file read)
  std::vector<OneWireChannelStatus> status_;
  std::vector<bool> pending_power_on_;
};

}  // namespace trueaxis::terminal
