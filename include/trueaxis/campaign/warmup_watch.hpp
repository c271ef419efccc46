#pragma once
// What `trueaxis campaign log` says while the machine warms up: for one axis, from the campaign's
// manifest (its cold test and the warm-up tests added since) and the logged nut sensor, whether
// the next warm-up test is due by the campaign's warm-up rule (warmup_rule.hpp, the same rule the
// virtual machine's campaign follows) and whether thermal saturation is reached.
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "trueaxis/sim/warmup_rule.hpp"

namespace trueaxis::campaign {

struct WarmUpStatus {
  std::string axis;
  bool has_cold = false;       // the manifest has a cold test of the axis (the warm-up's start)
  bool has_nut = false;        // the log has the axis's nut sensor (<axis>_nut) with readings since
  double rise_c = 0;           // nut (1-minute mean) − the cold test's mean nut
  double next_rise_c = 0;      // |rise| at which the next threshold test is due
  int taken = 0;               // warm-up tests since the cold test
  double machining_left_s = 0; // machining still to wait for (R × the last test's duration)
  bool due = false;            // take the next warm-up test now
  bool saturated = false;      // thermal saturation: take the last warm-up test now
  bool complete = false;       // every warm-up test the rule allows is taken
  std::string Text() const;    // one line for the status
};

// `measurements`: the manifest's array; `time_s` / `nut_c` / `travel_mm`: the log's rows (campaign
// clock; the axis's nut sensor, NaN where not read; the summed travel of every axis), `period_s`
// apart. `min_warmup_per_test`: R (docs/campaign.md step 2).
WarmUpStatus WatchWarmUp(const sim::WarmUpRule& rule, double min_warmup_per_test, const nlohmann::ordered_json& measurements,
                         const std::string& axis, std::span<const double> time_s, std::span<const double> nut_c,
                         std::span<const double> travel_mm, double period_s);

}  // namespace trueaxis::campaign
