#include "trueaxis/signal/channel_status.hpp"

namespace trueaxis::signal {

std::string_view ChannelStatusDescription(ChannelStatus s) {
  switch (s) {
    case ChannelStatus::kOk: return "reading valid";
    case ChannelStatus::kNoData: return "no reading received (source not read yet or link fault)";
    case ChannelStatus::kHardwareFault: return "device flagged the reading (open wire, ADC rail, power-on value)";
    case ChannelStatus::kUnderRange: return "below the plausible range (shorted sensor or dead loop)";
    case ChannelStatus::kOverRange: return "above the plausible range (open sensor, up-scale burn-out)";
    case ChannelStatus::kRateOfChange: return "changing faster than the machine structure can";
    case ChannelStatus::kStuck: return "no change beyond noise for too long while other channels moved";
    case ChannelStatus::kDisagreement: return "disagrees with the other sensors of its neighbour group";
  }
  return "unknown";
}

std::optional<ChannelStatus> ParseChannelStatus(std::string_view name) {
  for (int i = 0; i < kChannelStatusCount; ++i)
    if (kChannelStatusNames[i] == name) return static_cast<ChannelStatus>(i);
  return std::nullopt;
}

}  // namespace trueaxis::signal
