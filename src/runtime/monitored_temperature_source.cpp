#include "trueaxis/runtime/monitored_temperature_source.hpp"

namespace trueaxis::runtime {

std::vector<std::string> MonitoredTemperatureSource::Names(const hw::TemperatureSource& s) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < s.ChannelCount(); ++i) names.push_back(s.ChannelName(i));
  return names;
}

MonitoredTemperatureSource::MonitoredTemperatureSource(hw::TemperatureSource& inner, signal::MonitorOptions options,
                                                       std::function<double()> clock)
    : inner_(inner), monitor_(Names(inner), std::move(options)), clock_(std::move(clock)), raw_(inner.ChannelCount()) {}

bool MonitoredTemperatureSource::Read(std::span<hw::RawTemperature> out) {
  const double now_s = clock_();
  if (!inner_.Read(raw_)) {
    monitor_.MarkSourceFailed(now_s);
    return false;
  }
  monitor_.Update(now_s, raw_);
  for (std::size_t i = 0; i < raw_.size() && i < out.size(); ++i) {
    const signal::ChannelReading& r = monitor_.reading(i);
    out[i].temp_c = r.usable() ? r.filtered_c : r.last_good_c;
    out[i].hardware_fault = !r.usable();
  }
  return true;
}

}  // namespace trueaxis::runtime
