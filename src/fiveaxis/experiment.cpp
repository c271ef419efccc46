// simulate → feed-forward → correct → simulate the corrected program.
#include "trueaxis/fiveaxis/experiment.hpp"

#include "trueaxis/fiveaxis/command_correction.hpp"
#include "trueaxis/fiveaxis/program.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::fiveaxis {
namespace {

constexpr double kSettleWindowS = 0.05;  // a run stands when its error stays within tolerance this long

// The length a run needs so that it ends with a window in which every axis
// stands within `tolerance` of its final command.
std::size_t SettledLength(const SimulatedRun& run, std::size_t window, double tolerance) {
  const AxisVector& end = run.command.back();
  std::size_t last_off = 0;  // one past the last sample outside the tolerance
  for (std::size_t i = run.actual.size(); i-- > 0;) {
    bool off = false;
    for (int a = 0; a < kAxisCount; ++a) off = off || std::abs(end[a] - run.actual[i][a]) > tolerance;
    if (off) {
      last_off = i + 1;
      break;
    }
  }
  return last_off + window;
}

// The corrected program as the CNC would run it: read back from its text,
// interpolated and lined up with the original command (`samples` long).
std::vector<AxisVector> ReplayProgram(const std::string& gcode, const FiveAxisMachine& m, const Kinematics& kin,
                                      std::size_t samples) {
  const ToolPath replay = ParseGcodeProgram(gcode, "corrected program", m);
  // No rest added: the program's first block reaches the second sample, so
  // with the start sample in front the replay lines up with the original,
  // final rest included (the program holds it as blocks at the end point).
  std::vector<AxisVector> joints = Interpolate(replay, m, 0.0).joints;
  joints.insert(joints.begin(), VertexJoints(replay, kin).front());
  if (joints.size() < samples) joints.resize(samples, joints.back());
  return joints;
}

}  // namespace

SimulatedRun SimulateRun(const FiveAxisMachine& m, const std::vector<AxisVector>& command, double kf,
                         double acceleration_ff) {
  SimulatedRun run;
  run.kf = kf;
  run.command = command;
  run.actual.assign(command.size(), AxisVector{});
  std::vector<double> column(command.size());
  for (int a = 0; a < kAxisCount; ++a) {
    for (std::size_t i = 0; i < command.size(); ++i) column[i] = command[i][a];
    const std::vector<double> y = RunDrive(m.drives[a], m.servo_rate_hz, FeedForward{kf, acceleration_ff}, column,
                                           &run.saturated_periods[a]);
    for (std::size_t i = 0; i < y.size(); ++i) run.actual[i][a] = y[i];
  }
  return run;
}

Experiment RunExperiment(const FiveAxisMachine& m, const TrackingErrorModel& model, const ToolPath& path,
                         const ExperimentOptions& o) {
  const Kinematics kin(m.kinematics);
  Experiment x;
  x.path = path;
  x.trajectory = Interpolate(path, m);
  const double dt = x.trajectory.dt_s;
  x.feed_forward = ChooseFeedForward(model, x.trajectory.joints, dt);
  const double kf = x.feed_forward.averaged;
  // Every run stands at the end until the drives have settled (as the model
  // predicts them), so each run's end point is judged at rest and the
  // correction has room to fade out onto the programmed end.
  x.end_rest_added_s = ExtendRestUntilSettled(x.trajectory.joints, model, dt, kf);

  const std::vector<AxisVector> corrected =
      o.correction_method == CorrectionMethod::kModelInverse
          ? InvertTrackingModel(model, x.trajectory.joints, dt, kf)
          : CorrectCommands(kin, model, x.trajectory.joints, dt, kf, o.correction_iterations, o.correction_filter_s);
  // The end point is judged standing: the model's settling (above) is a
  // prediction; a drive may still creep where the model misses a slow friction
  // transient at the final stop. So the measured runs decide too: if FF alone
  // or the corrected program still moves at the end, the same programs are run
  // with a long rest to see when they stand, and the rest of all three runs
  // (and of the written program) is lengthened to that; then they run again.
  const std::size_t n = x.trajectory.joints.size();
  const std::size_t chunk = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(kSettleWindowS / dt)));
  const std::size_t max_extra = static_cast<std::size_t>(std::lround(o.max_measured_rest_s / dt));
  std::size_t extra = 0;
  for (int attempt = 0;; ++attempt) {
    std::vector<AxisVector> command = x.trajectory.joints, corrected_command = corrected;
    command.resize(n + extra, command.back());
    corrected_command.resize(n + extra, corrected_command.back());
    x.corrected_program = CommandsToProgram(corrected_command, kin, dt, o.samples_per_block, path.name + " (corrected)");
    x.corrected_gcode = WriteGcodeProgram(
        x.corrected_program, m, "trueaxis fiveaxis: " + path.name + ", corrected for FF kf=" + std::to_string(kf));
    const std::vector<AxisVector> replay_joints = ReplayProgram(x.corrected_gcode, m, kin, command.size());
    x.with_ff = SimulateRun(m, command, kf);
    x.corrected = SimulateRun(m, replay_joints, kf);
    const bool done = attempt > 0 || max_extra == 0 ||
                      std::max(SettledLength(x.with_ff, chunk, o.settle_tolerance),
                               SettledLength(x.corrected, chunk, o.settle_tolerance)) <= command.size();
    if (done) {
      x.without_ff = SimulateRun(m, command, 0.0);
      break;
    }
    // Still moving: how long until they stand (the drives are causal, so the
    // long runs' beginnings are the short runs).
    std::vector<AxisVector> long_command = command, long_corrected = replay_joints;
    long_command.resize(n + max_extra, command.back());
    long_corrected.resize(n + max_extra, replay_joints.back());
    const std::size_t settled = std::max(SettledLength(SimulateRun(m, long_command, kf), chunk, o.settle_tolerance),
                                         SettledLength(SimulateRun(m, long_corrected, kf), chunk, o.settle_tolerance));
    extra = settled > n ? std::min(max_extra, ((settled - n + chunk - 1) / chunk) * chunk) : 0;
  }
  x.measured_rest_added_s = static_cast<double>(extra) * dt;
  x.trajectory.joints.resize(n + extra, x.trajectory.joints.back());
  x.without_ff.label = "no FF";
  x.with_ff.label = "FF";
  x.corrected.label = "FF + correction";

  for (SimulatedRun* run : {&x.without_ff, &x.with_ff, &x.corrected}) run->contour = EvaluateContour(path, kin, run->actual);
  return x;
}

}  // namespace trueaxis::fiveaxis
