#include "trueaxis/signal/monitored_temperature_source.hpp"

#include <chrono>

namespace trueaxis::signal {

std::vector<std::string> MonitoredTemperatureSource::Names(const hw::TemperatureSource& s) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < s.ChannelCount(); ++i) names.push_back(s.ChannelName(i));
  return names;
}

MonitoredTemperatureSource::MonitoredTemperatureSource(hw::TemperatureSource& inner, MonitorOptions options,
                                                       std::function<double()> clock_s)
    : inner_(inner), monitor_(Names(inner), std::move(options)), clock_s_(std::move(clock_s)), raw_(inner.ChannelCount()) {
  if (!clock_s_) {
    clock_s_ = [] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    };
  }
}

bool MonitoredTemperatureSource::Read(std::span<JudgedTemperature> out) {
  const double now = clock_s_();
  if (!inner_.Read(raw_)) {
    monitor_.MarkSourceFailed(now);
    return false;
  }
  for (std::size_t i = 0; i < monitor_.ChannelCount(); ++i) monitor_.SetMeasuringRange(i, inner_.ChannelMeasuringRange(i));
  monitor_.Update(now, raw_);
  monitor_.Judge(out);
  return true;
}

}  // namespace trueaxis::signal
