#pragma once
// Campaign: what a calibration engineer does on one machine (seed 000 §2),
// axis after axis: a cold-state measurement in the morning; a warm-up with
// all axes reciprocating at 2000–4000 mm/min, measuring the axis each time its
// nut sensor has risen another 0.5 °C, until thermal saturation; cold
// measurements on other days (other ambient); a warm-up with coolant on.
// Writes the measurement files, temperature_log.csv and manifest.json
// (docs/campaign.md).
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>
#include <string>
#include <vector>

#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::sim {

struct CampaignOptions {
  std::string out_dir;
  std::uint64_t seed = 1;
  std::vector<std::string> axes;        // empty: every axis of the machine
  LaserOptions laser;                   // cold and ambient measurements (5 runs)
  int warm_runs = 3;                    // runs of the warm-up / coolant measurements: shorter, so the
                                        //   warm-up is interrupted less (seed 000 allows 3–5)
  double warmup_feed_low_mm_min = 2000;   // strokes alternate between low and high feed
  double warmup_feed_high_mm_min = 4000;
  double nut_step_c = 0.5;                // measure each time the nut rose this much more …
  double nut_step_growth = 0.25;          // … or this fraction of the rise so far, or the even share of
                                          // the rise still to come (extrapolated from the warm-up curve),
                                          // whichever is larger: the tests cover the whole rise
  // The dry warm-up's next test waits for at least this many times the last test's duration of
  // machining (as well as the nut step): 0 = none. A long axis's test takes 30 min; without it the
  // warm-up is mostly laser moves and the fit never sees the nut far above the screw after hours
  // of machining, as a working day does — the data the motion-heat input is identified from
  // (bench/results/zoo.md: 0.5 with coolant_visit kBoth and the fit's motion heat auto).
  double min_warmup_per_test = 0.5;
  int max_warm_measurements = 16;      // the last one is kept for saturation
  double max_warmup_hours = 5;            // give up waiting for saturation after this
  double saturation_window_min = 30;      // saturated when the nut rose less than
  double saturation_rise_c = 0.15;        //   this much within the window
  // Cool-down after saturation: axes stopped, a measurement each time the nut
  // sensor fell another cooldown_step_c (nut and screw now cool at different
  // rates: data a warm-up-only model has never seen).
  int cooldown_measurements = 2;
  double cooldown_step_c = 1.5;
  double max_cooldown_hours = 3;
  // Other ambient: the idle machine measured on these days after the cold day, at each of
  // ambient_hours (hours of the day, in order). More than one hour shows the fit the machine
  // following the room as it falls in the night (03:00: the air below the still warm structure),
  // rises in the morning and falls in the evening, not only a soaked afternoon. bench/results/zoo.md:
  // {3, 10, 19} against {10, 19} lowers A_on by 3–4 % on every zoo seed (must 630 vs 629 of 650);
  // {10, 19} against {14} kept the must count and lowered A_on 3–8 %. {14} is the campaign of
  // stop 25, two sets of tests shorter per ambient day.
  std::vector<int> ambient_day_offsets = {60, 150};
  std::vector<double> ambient_hours = {3, 10, 19};
  bool coolant_session = true;
  CoolantState coolant_state = CoolantState::kFlood;
  int max_coolant_measurements = 4;     // per coolant session
  // One coolant session per entry, each on its own day per axis: the flood starts after this many
  // hours of dry warm-up machining (0: over the cold machine, seed 000's session). A session over a
  // warm machine shows the fit the sensors drawn to the coolant while the screw still holds the
  // dry heat, as on a working day whose flood follows hours of dry machining.
  std::vector<double> coolant_prewarm_h = {0};
  // When the coolant sessions are measured: after the other-season days, on the days right after
  // the dry warm-ups (the first visit: the season of the cold state and of a working day soon
  // after), or both (the default: the sessions repeated in the two seasons, so a coolant's own
  // gains are fitted on twice the states and on two rooms; bench/results/zoo.md).
  enum class CoolantVisit { kAfterSeasons, kFirstVisit, kBoth };
  CoolantVisit coolant_visit = CoolantVisit::kBoth;
  bool coolant_rest = true;  // after the coolant warm-up: the axes stop under coolant, cooldown measurements ("coolant_rest")
  double log_interval_s = 30;
  std::function<void(const std::string&)> progress;  // one line per event (stderr in the CLI)

  bool IsValid(std::string* why) const;
};

// "after-seasons", "first", "both" (the CLI's --coolant-visit) and back; nullopt for another name.
std::optional<CampaignOptions::CoolantVisit> ParseCoolantVisit(std::string_view name);
const char* CoolantVisitName(CampaignOptions::CoolantVisit visit);

struct CampaignFile {
  std::string file;       // relative to out_dir
  std::string axis;
  std::string state;      // cold | warm | cooldown | ambient | coolant
  std::string coolant;    // off | flood | mist | air
  int sequence = 0;       // 1-based within (axis, state)
  double start_time_s = 0, end_time_s = 0;
  std::string start_date;
  double nut_rise_c = 0;  // nut sensor vs the axis' cold measurement
  int coolant_session = 0;  // 1-based: which of coolant_prewarm_h's sessions (0: a dry-day state)
};

// Where a warm-up's tests leave most of its rise untested: for each axis's dry warm-up ("warm",
// counted from the cold state) and coolant warm-up ("coolant", from its first test; each session
// on its own), the largest
// step in nut rise between two tests when it is more than `max_gap_fraction` of the session's
// rise, as one line naming the tests' rises. A coolant warm-up with few tests bunches them in the
// nut's first jump and then waits for saturation (bench/results/zoo.md): said, not hidden.
std::vector<std::string> WarmUpCoverageGaps(const std::vector<CampaignFile>& files, double max_gap_fraction = 0.5);

struct CampaignSummary {
  std::vector<CampaignFile> files;
  double machine_time_s = 0;
  double wall_time_s = 0;
  // The file counts and machine time; then one line per WarmUpCoverageGaps entry.
  std::string BriefReport() const;
};

CampaignSummary RunCampaign(const MachineDescription& machine, const CampaignOptions& options);

}  // namespace trueaxis::sim
