// simulate → feed-forward → correct → simulate the corrected program.
#include "trueaxis/fiveaxis/experiment.hpp"

#include "trueaxis/fiveaxis/command_correction.hpp"
#include "trueaxis/fiveaxis/program.hpp"

namespace trueaxis::fiveaxis {

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

  x.without_ff = SimulateRun(m, x.trajectory.joints, 0.0);
  x.without_ff.label = "no FF";
  x.with_ff = SimulateRun(m, x.trajectory.joints, kf);
  x.with_ff.label = "FF";

  const std::vector<AxisVector> corrected = CorrectCommands(kin, model, x.trajectory.joints, dt, kf, o.correction_iterations,
                                                             o.correction_filter_s);
  x.corrected_program = CommandsToProgram(corrected, kin, dt, o.samples_per_block, path.name + " (corrected)");
  x.corrected_gcode = WriteGcodeProgram(x.corrected_program, m,
                                        "trueaxis fiveaxis: " + path.name + ", corrected for FF kf=" + std::to_string(kf));
  // The corrected program as the CNC would run it: read back, interpolated, simulated.
  const ToolPath replay = ParseGcodeProgram(x.corrected_gcode, "corrected program", m);
  // No rest added: the program's first block reaches the second sample, so
  // with the start sample in front the replay lines up with the original,
  // final rest included (the program holds it as blocks at the end point).
  std::vector<AxisVector> replay_joints = Interpolate(replay, m, 0.0).joints;
  replay_joints.insert(replay_joints.begin(), VertexJoints(replay, kin).front());
  if (replay_joints.size() < x.trajectory.joints.size())
    replay_joints.resize(x.trajectory.joints.size(), replay_joints.back());
  x.corrected = SimulateRun(m, replay_joints, kf);
  x.corrected.label = "FF + correction";

  for (SimulatedRun* run : {&x.without_ff, &x.with_ff, &x.corrected}) run->contour = EvaluateContour(path, kin, run->actual);
  return x;
}

}  // namespace trueaxis::fiveaxis
