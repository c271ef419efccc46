#pragma once
// Seed 001's stop rule: a non-credible reading is re-taken; more than
// `max_rejected_in_row` non-credible readings in a row stop the machine and ask
// for the marker to be redrawn. The monitor also holds the Δz in force: the
// last credible reading (a rejected frame never changes the compensation).
//
// Hook for the runtime (docs/vision.md): when stop() turns true, the caller
// raises a feed hold with message() — `trueaxis vision run` stops the virtual
// spindle and records it; `trueaxis vision measure --alarm-out` writes
// {"feed_hold": true, "message": …} for a CNC/PLC bridge to consume.
#include <string>

#include "trueaxis/vision/marker_measurement.hpp"

namespace trueaxis::vision {

class CredibilityMonitor {
 public:
  explicit CredibilityMonitor(int max_rejected_in_row = 5);

  // Counts one reading; returns true when this reading trips the stop.
  bool Add(const MarkerReading& reading);
  void Reset();  // after the marker has been redrawn

  bool stop() const { return stop_; }
  int rejected_in_row() const { return rejected_in_row_; }
  bool has_growth() const { return has_growth_; }
  double growth_um() const { return growth_um_; }  // Δz in force (last credible), 0 before the first
  std::string message() const;

 private:
  int max_;
  int rejected_in_row_ = 0;
  bool stop_ = false;
  bool has_growth_ = false;
  double growth_um_ = 0;
  std::string last_reason_;
};

}  // namespace trueaxis::vision
