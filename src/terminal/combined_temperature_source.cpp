#include "trueaxis/terminal/combined_temperature_source.hpp"

#include <algorithm>
#include <limits>
#include <set>

#include <fmt/format.h>

namespace trueaxis::terminal {

CombinedTemperatureSource::CombinedTemperatureSource(std::vector<std::unique_ptr<hw::TemperatureSource>> parts)
    : parts_(std::move(parts)) {
  for (const auto& p : parts_)
    for (std::size_t c = 0; c < p->ChannelCount(); ++c) names_.push_back(p->ChannelName(c));
}

bool CombinedTemperatureSource::Configure(std::string* error) {
  std::set<std::string> seen;
  for (const auto& n : names_)
    if (!seen.insert(n).second) {
      if (error) *error = fmt::format("channel '{}' is named by two sources", n);
      return false;
    }
  for (auto& p : parts_)
    if (!p->Configure(error)) return false;
  buffer_.assign(names_.size(), hw::RawTemperature{});
  return true;
}

bool CombinedTemperatureSource::Activate(std::string* error) {
  std::string reasons;
  for (auto& p : parts_) {
    std::string why;
    if (!p->Activate(&why)) reasons += (reasons.empty() ? "" : "; ") + why;
  }
  if (!reasons.empty() && error) *error = reasons;
  return reasons.empty();
}

void CombinedTemperatureSource::Deactivate() {
  for (auto& p : parts_) p->Deactivate();
}

hw::MeasuringRange CombinedTemperatureSource::ChannelMeasuringRange(std::size_t channel) const {
  for (const auto& p : parts_) {
    if (channel < p->ChannelCount()) return p->ChannelMeasuringRange(channel);
    channel -= p->ChannelCount();
  }
  return {};
}

bool CombinedTemperatureSource::Read(std::span<hw::RawTemperature> out) {
  bool any = false;
  std::size_t offset = 0;
  for (auto& p : parts_) {
    const std::size_t n = p->ChannelCount();
    const auto slice = std::span<hw::RawTemperature>(buffer_).subspan(offset, n);
    if (p->Read(slice)) {
      any = true;
    } else {
      for (auto& t : slice) t = {std::numeric_limits<double>::quiet_NaN(), true};
    }
    offset += n;
  }
  if (any) std::copy_n(buffer_.begin(), std::min(out.size(), buffer_.size()), out.begin());
  return any;
}

}  // namespace trueaxis::terminal
