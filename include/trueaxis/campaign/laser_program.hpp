#pragma once
// The NC programs a campaign runs (docs/real-machine.md "Programs"), for LinuxCNC (RS274/NGC),
// FANUC, SINUMERIK and HEIDENHAIN Klartext:
//
// - the laser test of one axis: the bidirectional cycle of ISO 230-2 (sim::RunBidirectionalCycle, the
//   one copy every laser test in trueaxis runs): per run, past the first target by the overrun, every
//   target going up with the dwell at each, past the last by the overrun, every target coming down.
//   Positions in machine coordinates (LinuxCNC G53 G1, SINUMERIK SUPA, HEIDENHAIN M91; FANUC moves
//   G91 increments from a G53 start, since its G53 moves only at rapid), at the laser feed.
// - the warm-up: all axes reciprocating together over their travel, strokes alternating the low and
//   high feeds (sim::CampaignOptions' warm-up, seed 000's 2000–4000 mm/min), repeated until stopped.
#include <string>

#include "trueaxis/campaign/campaign_machine.hpp"
#include "trueaxis/campaign/test_targets.hpp"

namespace trueaxis::campaign {

struct ProgramFile {
  std::string file_name;  // e.g. "X_laser5_linuxcnc.ngc", "O7001_X_laser5_fanuc.nc", "TA_X_LASER5.MPF", "TAXLASER5.H"
  std::string text;
};

// `number`: the program's number where the dialect wants one (FANUC O-number), 1…9999.
ProgramFile LaserTestProgram(Controller c, const CampaignMachine& machine, const CampaignAxis& axis,
                             const AxisTargets& targets, int runs, int number);

// `margin_mm` kept from each soft limit; the feeds alternate stroke by stroke (the longest axis
// moves at the stroke's feed, the others together with it).
ProgramFile WarmUpProgram(Controller c, const CampaignMachine& machine, const std::vector<std::string>& axes,
                          double feed_low_mm_min, double feed_high_mm_min, int number);

// The sequence of positions (machine coordinates) and dwells the laser test runs, as the
// programs write it: a dwell is {position, true}. Tests read the programs against it.
struct ProgramStep {
  double position_mm = 0;
  bool dwell = false;  // a target: the axis stops here for the dwell (a reading)
};
std::vector<ProgramStep> LaserTestSteps(const AxisTargets& targets, int runs);

}  // namespace trueaxis::campaign
