#pragma once
// Status of one temperature channel after fault detection (MISSION M2).
// Names are stable identifiers for logs, the history database and the UI;
// descriptions are one line of English for a person.
#include <array>
#include <optional>
#include <string_view>

namespace trueaxis::signal {

enum class ChannelStatus : int {
  kOk = 0,
  kNoData = 1,           // nothing read yet, or the source failed to deliver
  kHardwareFault = 2,    // the device/converter flagged the reading (open wire, ADC rail, 85 °C power-on value)
  kUnderRange = 3,       // below the plausible range: shorted RTD, dead loop
  kOverRange = 4,        // above the plausible range: open RTD with up-scale burn-out
  kRateOfChange = 5,     // changes faster than a machine structure can
  kStuck = 6,            // no change beyond noise for too long while other channels moved
  kDisagreement = 7,     // disagrees with the other channels of its neighbour group
};
inline constexpr int kChannelStatusCount = 8;

inline constexpr std::array<std::string_view, kChannelStatusCount> kChannelStatusNames = {
    "ok", "no_data", "hardware_fault", "under_range", "over_range", "rate_of_change", "stuck", "disagreement"};

inline constexpr std::string_view ChannelStatusName(ChannelStatus s) { return kChannelStatusNames[static_cast<int>(s)]; }
std::string_view ChannelStatusDescription(ChannelStatus s);
std::optional<ChannelStatus> ParseChannelStatus(std::string_view name);

}  // namespace trueaxis::signal
