#pragma once
// One five-axis experiment (docs/fiveaxis.md): a tool path interpolated and
// run on the virtual machine three times — without feed-forward, with seed
// 004's averaged feed-forward, and with feed-forward plus the corrected
// command (written as a program, read back and run) — each judged by its
// contour error against the programmed path.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/fiveaxis/command_correction.hpp"
#include "trueaxis/fiveaxis/contour_error.hpp"
#include "trueaxis/fiveaxis/interpolator.hpp"
#include "trueaxis/fiveaxis/servo_drive.hpp"
#include "trueaxis/fiveaxis/tracking_model.hpp"

namespace trueaxis::fiveaxis {

struct SimulatedRun {
  std::string label;
  double kf = 0;
  std::vector<AxisVector> command, actual;
  std::array<std::int64_t, kAxisCount> saturated_periods{};
  ContourErrors contour;
};

// Runs every drive over its command column (velocity FF kf, optional acceleration FF).
SimulatedRun SimulateRun(const FiveAxisMachine& m, const std::vector<AxisVector>& command, double kf,
                         double acceleration_ff = 0);

struct ExperimentOptions {
  CorrectionMethod correction_method = CorrectionMethod::kModelInverse;
  // kPasses only:
  int correction_iterations = 16;       // 1 = seed 004's one-shot correction
  double correction_filter_s = 0.005;   // zero-phase low-pass of the later passes' updates
  int samples_per_block = 1;  // corrected program: one G93 block per this many servo periods
  // The runs stand at the end until every axis's measured tracking error stays
  // within this (mm or deg) for 50 ms, lengthening the rest by at most max_measured_rest_s.
  double settle_tolerance = 5e-5;
  double max_measured_rest_s = 2.0;
};

struct Experiment {
  ToolPath path;
  Trajectory trajectory;
  FeedForwardChoice feed_forward;
  double end_rest_added_s = 0;  // rest added at the end until the model's predicted error settles (ExtendRestUntilSettled)
  double measured_rest_added_s = 0;  // and then until the measured positions settle (the runs' own feedback)
  SimulatedRun without_ff, with_ff, corrected;
  ToolPath corrected_program;
  std::string corrected_gcode;
};

Experiment RunExperiment(const FiveAxisMachine& m, const TrackingErrorModel& model, const ToolPath& path,
                         const ExperimentOptions& o = {});

}  // namespace trueaxis::fiveaxis
