#pragma once
// `trueaxis campaign plan`: the calibration campaign of a real machine, written into a campaign folder
// (docs/real-machine.md): which states to measure and when — the same campaign the virtual machine
// runs (sim::CampaignOptions: cold after an overnight soak, warm-up tests as the nut rises, the last at
// saturation, cool-down, other ambient days and hours, coolant sessions) — the ISO 230-2 targets of
// each axis, the laser test and warm-up as NC programs per controller, plan.md for the person at the
// machine, plan.json for programs, and the empty manifest.json and temperature_log.csv that
// `campaign log` and `campaign add` fill.
#include <string>
#include <vector>

#include "trueaxis/campaign/campaign_machine.hpp"
#include "trueaxis/campaign/test_targets.hpp"
#include "trueaxis/sim/campaign.hpp"

namespace trueaxis::campaign {

struct PlanOptions {
  std::string out_dir;
  std::vector<std::string> axes;          // empty: every axis of the machine
  TargetOptions targets;
  // The schedule and its rules: the virtual campaign's own options and defaults (docs/campaign.md);
  // out_dir, seed, laser and progress are not used.
  sim::CampaignOptions schedule;
  std::vector<Controller> controllers;    // empty: the machine file's controller, or every one
  std::string start_date;                 // YYYY-MM-DD of the first cold day; "" = days counted from day 0
};

struct PlanStep {
  int day = 0;           // after the first cold day
  double hour = 7;       // local time the step starts
  std::string axis;
  std::string state;     // cold | warm | cooldown | ambient | coolant | coolant_rest (measure::CampaignStates)
  std::string coolant;   // off | flood | mist | air
  int runs = 0;          // per test
  int max_tests = 1;     // tests of this step (warm-up: up to; cool-down: this many)
  std::string what;      // one line for the person at the machine
};

struct CampaignPlan {
  CampaignMachine machine;
  PlanOptions options;
  std::vector<std::string> axes;       // measured, in order
  std::vector<AxisTargets> targets;    // parallel to axes
  std::vector<PlanStep> steps;         // in the order they are taken
  std::vector<Controller> controllers;
};

// InputError("command line", 0, "--axes", …) for an axis the machine has not, or bad options.
CampaignPlan MakeCampaignPlan(const CampaignMachine& machine, const PlanOptions& options);

std::string PlanMarkdown(const CampaignPlan& plan);
std::string PlanJson(const CampaignPlan& plan);

// Writes plan.md, plan.json, programs/ and the empty manifest.json and temperature_log.csv into
// options.out_dir. Refuses (InputError) a folder that already holds a manifest.json: a campaign is
// never overwritten. Returns the files written, relative to the folder.
std::vector<std::string> WriteCampaignFolder(const CampaignPlan& plan);

}  // namespace trueaxis::campaign
