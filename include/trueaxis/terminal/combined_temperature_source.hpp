#pragma once
// CombinedTemperatureSource: one channel list made of several sources (the
// terminal's 1-Wire sensors, then each RTD module group), in the order given.
// A part that cannot be read marks only its own channels as faulted
// (hardware_fault, NaN): a dead RTD module does not take the 1-Wire sensors
// down with it. Read() returns false (out untouched) only when no part can be read.
// Configure() before Read().
#include <memory>
#include <vector>

#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::terminal {

class CombinedTemperatureSource final : public hw::TemperatureSource {
 public:
  explicit CombinedTemperatureSource(std::vector<std::unique_ptr<hw::TemperatureSource>> parts);

  std::size_t ChannelCount() const override { return names_.size(); }
  std::string ChannelName(std::size_t channel) const override { return names_.at(channel); }
  bool Read(std::span<hw::RawTemperature> out) override;
  hw::MeasuringRange ChannelMeasuringRange(std::size_t channel) const override;  // the owning part's

  // Configure: every part; a channel name used twice across parts is refused.
  bool Configure(std::string* error) override;
  bool Activate(std::string* error) override;  // every part; false (with the reasons) when any failed
  void Deactivate() override;

  std::size_t PartCount() const { return parts_.size(); }
  hw::TemperatureSource& part(std::size_t i) { return *parts_.at(i); }

 private:
  std::vector<std::unique_ptr<hw::TemperatureSource>> parts_;
  std::vector<std::string> names_;
  std::vector<hw::RawTemperature> buffer_;  // sized by Configure: Read() does not allocate
};

}  // namespace trueaxis::terminal
