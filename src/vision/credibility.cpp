// Seed-001 stop rule (include/trueaxis/vision/credibility.hpp).
#include "trueaxis/vision/credibility.hpp"

#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::vision {

CredibilityMonitor::CredibilityMonitor(int max_rejected_in_row) : max_(max_rejected_in_row) {
  if (max_ < 1) throw std::invalid_argument("max_rejected_in_row must be ≥ 1");
}

bool CredibilityMonitor::Add(const MarkerReading& r) {
  if (r.credible()) {
    rejected_in_row_ = 0;
    has_growth_ = true;
    growth_um_ = r.growth_um;
    return false;
  }
  ++rejected_in_row_;
  last_reason_ = std::string(ReadingStatusName(r.status)) + (r.reason.empty() ? "" : ": " + r.reason);
  if (!stop_ && rejected_in_row_ > max_) {
    stop_ = true;
    return true;
  }
  return false;
}

void CredibilityMonitor::Reset() {
  rejected_in_row_ = 0;
  stop_ = false;
}

std::string CredibilityMonitor::message() const {
  if (!stop_) return "";
  return fmt::format(
      "FEED HOLD: {} spindle marker readings in a row were not credible (limit {}; last: {}). Stop the machine and "
      "redraw the deformation marker.",
      rejected_in_row_, max_, last_reason_);
}

}  // namespace trueaxis::vision
