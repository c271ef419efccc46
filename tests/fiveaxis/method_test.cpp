// Seed 004's method: identification against a known plant, the averaged
// feed-forward coefficient, the nearest-point search (sharp corners, singular
// orientations), the interpolator, the drive, and the whole experiment.
#include <cmath>
#include <functional>
#include <numbers>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/fiveaxis/axis_identification.hpp"
#include "trueaxis/fiveaxis/command_correction.hpp"
#include "trueaxis/fiveaxis/contour_error.hpp"
#include "trueaxis/fiveaxis/experiment.hpp"
#include "trueaxis/fiveaxis/machine_variation.hpp"
#include "trueaxis/fiveaxis/program.hpp"
#include "trueaxis/fiveaxis/servo_drive.hpp"

namespace trueaxis::fiveaxis {
namespace {

FiveAxisMachine Machine(const std::string& name) {
  return ReadFiveAxisMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/fiveaxis/" + name);
}

// A linear drive (no friction) with a known position gain: the identified
// velocity coefficient without feed-forward is 1/Kp (seed 004: c_v = (1 − kf)/Kp),
// near zero with full feed-forward, and the model predicts the tracking error
// of a command it was not fitted on.
TEST(FiveAxisIdentification, RecoversAKnownPlant) {
  FiveAxisMachine m;
  m.servo_rate_hz = 2000;
  DriveParams d;
  d.kp_per_s = 33;
  d.coulomb = 0;
  for (auto& drive : m.drives) drive = d;
  AxisTestOptions o;
  const TrackingErrorModel model = IdentifyTrackingModel(m, o, VirtualMachineRunner(m));
  const auto& ax = model.axes[kX];
  EXPECT_NEAR(ax.without_ff[0], 1.0 / 33, 0.03 / 33);
  EXPECT_LT(std::abs(ax.full_ff[0]), 0.02 / 33);
  EXPECT_LT(ax.fit_rms, 0.02 * ax.signal_rms);
  // A different command: a smooth move with a dwell, at kf = 0.7.
  std::vector<AxisVector> cmd(6000, AxisVector{});
  for (std::size_t i = 0; i < cmd.size(); ++i) {
    const double t = i / m.servo_rate_hz;
    cmd[i][kX] = 30 * (1 - std::cos(std::numbers::pi * std::min(t, 2.0) / 2)) + 5 * std::sin(3 * t);
  }
  const auto predicted = PredictTrackingError(model, cmd, 1 / m.servo_rate_hz, 0.7);
  std::vector<double> column(cmd.size());
  for (std::size_t i = 0; i < cmd.size(); ++i) column[i] = cmd[i][kX];
  const auto actual = RunDrive(d, m.servo_rate_hz, FeedForward{0.7, 0}, column);
  double err2 = 0, sig2 = 0;
  for (std::size_t i = 0; i < cmd.size(); ++i) {
    const double e = column[i] - actual[i];
    sig2 += e * e;
    err2 += (e - predicted[i][kX]) * (e - predicted[i][kX]);
  }
  EXPECT_LT(std::sqrt(err2 / sig2), 0.03);
}

// Seed 004: kf per moving axis minimises that axis's modelled error; the
// machine's kf is their mean, and an axis standing still takes no part.
TEST(FiveAxisIdentification, FeedForwardIsTheMeanOverMovingAxes) {
  TrackingErrorModel model;
  model.with_extensions = false;
  for (int a = 0; a < kAxisCount; ++a) {
    model.axes[a].without_ff = {0.025, 0, 0};
    model.axes[a].full_ff = {0.025 - 0.025 / (0.9 + 0.02 * a), 0, 0};  // zero error at kf = 0.9 + 0.02a
  }
  std::vector<AxisVector> cmd(2000, AxisVector{});
  for (std::size_t i = 0; i < cmd.size(); ++i)
    for (int a = 0; a < kAxisCount - 1; ++a) cmd[i][a] = std::sin(0.003 * i * (a + 1));  // C stands
  const FeedForwardChoice c = ChooseFeedForward(model, cmd, 0.0005);
  for (int a = 0; a < kAxisCount - 1; ++a) EXPECT_NEAR(c.per_axis[a], 0.9 + 0.02 * a, 1e-9);
  EXPECT_TRUE(std::isnan(c.per_axis[kRot]));
  EXPECT_NEAR(c.averaged, (0.9 + 0.92 + 0.94 + 0.96) / 4, 1e-9);
  // C moving only by numerical noise (1e-9°, as the inverse kinematics' atan2 of tiny numbers
  // gives) still stands: its kf would be the noise's.
  for (std::size_t i = 0; i < cmd.size(); ++i) cmd[i][kRot] = 1e-9 * std::sin(0.7 * i);
  const FeedForwardChoice noisy = ChooseFeedForward(model, cmd, 0.0005);
  EXPECT_TRUE(std::isnan(noisy.per_axis[kRot]));
  EXPECT_NEAR(noisy.averaged, c.averaged, 1e-12);
}

ToolPath Square() {  // a 20 mm square with sharp corners, tool vertical
  ToolPath p;
  for (auto [x, y] : std::vector<std::pair<double, double>>{{0, 0}, {20, 0}, {20, 20}, {0, 20}, {0, 0}}) {
    PathVertex v;
    v.tip_mm = {x, y, 0};
    v.move = p.vertices.empty() ? MoveKind::kStart : MoveKind::kFeed;
    v.feed_mm_per_min = 1000;
    p.vertices.push_back(v);
  }
  return p;
}

TEST(FiveAxisContour, NearestPointAtSharpCorners) {
  KinematicsParams kp;
  const Kinematics kin(kp);
  const ToolPath square = Square();
  NearestPointTracker t(square, kin);
  ToolPose pose;
  // Walk along the first edge, then cut inside the corner at (20, 0), then overshoot outside it.
  for (double x = 0; x <= 19; x += 0.5) {
    pose.tip_mm = {x, 0.002, 0};
    EXPECT_NEAR(t.Next(pose).distance_mm, 0.002, 1e-12);
  }
  pose.tip_mm = {19.995, 0.003, 0};  // inside: 0.003 from the first edge, 0.005 from the second
  EXPECT_NEAR(t.Next(pose).distance_mm, 0.003, 1e-12);
  pose.tip_mm = {20.003, -0.004, 0};  // outside beyond the vertex: distance to the vertex
  auto m = t.Next(pose);
  EXPECT_NEAR(m.distance_mm, 0.005, 1e-12);
  EXPECT_NEAR(m.arc_mm, 20, 1e-9);
  pose.tip_mm = {20.001, 3, 0};  // on along the second edge
  EXPECT_NEAR(t.Next(pose).distance_mm, 0.001, 1e-12);
}

TEST(FiveAxisContour, ClosedPathStartsAtItsStartNotItsEnd) {
  KinematicsParams kp;
  const Kinematics kin(kp);
  NearestPointTracker t(Square(), kin);
  ToolPose pose;
  pose.tip_mm = {0.5, 0.001, 0};
  const auto m = t.Next(pose);
  EXPECT_NEAR(m.arc_mm, 0.5, 1e-9);  // not 80 − … on the closing edge
}

// Tool axis parallel to the C axis (A = 0): a C error changes nothing; while
// the tip stands and only C turns (a singular swing), the match is by tool
// axis, and a tilt error shows as orientation error only.
TEST(FiveAxisContour, SingularOrientation) {
  KinematicsParams kp;
  kp.family = Family::kTableAC;
  kp.offset_mm = {0, 0, -50};
  const Kinematics kin(kp);
  ToolPath p;
  for (int i = 0; i <= 10; ++i) {  // tip standing at (5, 0, 0), tilt 0 → 20°, C swinging 0 → 90°
    PathVertex v;
    v.tip_mm = {5, 0, 0};
    v.tilt_deg = 2.0 * i;
    v.rot_deg = 9.0 * i;
    v.move = i == 0 ? MoveKind::kStart : MoveKind::kFeed;
    v.feed_mm_per_min = 100;
    p.vertices.push_back(v);
  }
  NearestPointTracker t(p, kin);
  // At A = 0 any C gives the same pose: zero error, although C is 40° off.
  auto m = t.Next(kin.Forward(kin.Inverse({5, 0, 0}, 0, 40)));
  EXPECT_LT(m.distance_mm, 1e-9);
  EXPECT_LT(m.angle_rad, 1e-9);
  // Halfway (A = 10°, C = 45°) with A 0.01° short: matched at its own pose within the swing.
  m = t.Next(kin.Forward(kin.Inverse({5, 0, 0}, 9.99, 45)));
  EXPECT_LT(m.distance_mm, 1e-9);
  EXPECT_LT(m.angle_rad, 0.011 * std::numbers::pi / 180);
  EXPECT_GT(m.angle_rad, 0.0);
}

TEST(FiveAxisInterpolator, FollowsThePathAtTheFeedWithRampsAndStops) {
  FiveAxisMachine m = Machine("table_ac.toml");
  const Kinematics kin(m.kinematics);
  const ToolPath square = Square();
  const Trajectory t = Interpolate(square, m);
  // Every commanded tip lies on the square.
  const ContourErrors on_path = EvaluateContour(square, kin, t.joints);
  EXPECT_LT(on_path.max_um, 1e-6);
  // Four exact stops, each edge at 1000 mm/min in the middle.
  const double dt = t.dt_s;
  double peak = 0;
  for (std::size_t i = 1; i < t.joints.size(); ++i) {
    const double v = (kin.Forward(t.joints[i]).tip_mm - kin.Forward(t.joints[i - 1]).tip_mm).norm() / dt;
    peak = std::max(peak, v);
  }
  EXPECT_NEAR(peak, 1000.0 / 60, 1e-6);
  const double duration = t.joints.size() * dt;
  EXPECT_GT(duration, 80 / (1000.0 / 60));
  EXPECT_LT(duration, 80 / (1000.0 / 60) + 4 * 0.05 + 0.2);
}

// Work grows as 1/feed: a path needing more than kMaxServoSamples servo
// periods is refused before it is allocated, naming the line and its field.
TEST(FiveAxisInterpolator, RefusesAPathBeyondTheServoBudgetWithTheLine) {
  const FiveAxisMachine m = Machine("table_ac.toml");
  auto expect_refused = [&](const ToolPath& p, const std::string& source, int line, const std::string& field) {
    try {
      Interpolate(p, m);
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), source) << e.what();
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  expect_refused(ParseGcodeProgram("G1 X10 Y0 Z0 A0 C0 F4000\nG1 X20\nG1 X100 F0.001\nM30\n", "slow.nc", m), "slow.nc", 3,
                 "F");
  expect_refused(ParseCsvProgram("x_mm,y_mm,z_mm,a_deg,c_deg,feed_mm_per_min\n0,0,0,0,0,0\n90,0,0,0,0,0.00001\n", "slow.csv",
                                 m, 0),
                 "slow.csv", 3, "feed_mm_per_min");
  ToolPath cone = MakeTestPath("cone", Kinematics(m.kinematics), 0.00001);
  cone.feed_field = "--feed";
  expect_refused(cone, "command line", 0, "--feed");
  // Within the budget: 90 mm at 12 mm/min is 450 s (900 000 periods at 2000 Hz).
  const ToolPath slow_but_fits = ParseGcodeProgram("G1 X0 Y0 Z0 A0 C0 F4000\nG1 X90 F12\n", "ok.nc", m);
  EXPECT_NO_THROW(Interpolate(slow_but_fits, m));
}

// The model reader names the field of a broken model instead of leaking
// nlohmann's text or letting a 1e308 coefficient corrupt the generated program.
TEST(FiveAxisModelFile, RefusesBrokenModelsNamingTheField) {
  const auto names = AxisNames(Family::kTableAC);
  const nlohmann::json good = nlohmann::json::parse(ModelToJson(TrackingErrorModel{}, names));
  EXPECT_NO_THROW(ModelFromJson(good.dump(), "m.json", names));
  auto expect_field = [&](const std::function<void(nlohmann::json&)>& change, const std::string& field) {
    nlohmann::json j = good;
    change(j);
    try {
      ModelFromJson(j.dump(), "m.json", names);
      FAIL() << "no error for " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "m.json");
      EXPECT_EQ(e.field(), field) << e.what();
      EXPECT_EQ(std::string(e.what()).find("json.exception"), std::string::npos) << e.what();
    }
  };
  expect_field([](auto& j) { j["axes"][0]["without_ff"].erase(20); }, "axes[0].without_ff");  // 28 of 29
  expect_field([](auto& j) { j["axes"][0]["without_ff"][0] = 1e308; }, "axes[0].without_ff[0]");
  expect_field([](auto& j) { j["axes"][2]["full_ff"][3] = "x"; }, "axes[2].full_ff[3]");
  expect_field([](auto& j) { j["axes"][1]["axis"] = "X"; }, "axes[1].axis");  // X twice
  expect_field([](auto& j) { j["derivative_window_s"] = -1; }, "derivative_window_s");
  expect_field([](auto& j) { j["derivative_window_s"] = 0; }, "derivative_window_s");
  expect_field([](auto& j) { j.erase("derivative_window_s"); }, "derivative_window_s");
  expect_field([](auto& j) { j["format"] = "x"; }, "format");
  expect_field([](auto& j) { j["axes"][4].erase("friction_band"); }, "axes[4].friction_band");
  // A model of an A/C table does not fit a B/C head.
  EXPECT_THROW(ModelFromJson(good.dump(), "m.json", AxisNames(Family::kHeadBC)), InputError);
}

TEST(FiveAxisDrive, SettlesWithoutSteadyErrorAndCountsSaturation) {
  DriveParams d;
  std::vector<double> cmd(4000, 1.0);  // 1 mm step
  cmd[0] = 0;
  std::int64_t saturated = 0;
  auto y = RunDrive(d, 2000, FeedForward{}, cmd, &saturated);
  EXPECT_NEAR(y.back(), 1.0, 1e-5);  // the PI loop removes the friction's steady error
  EXPECT_EQ(saturated, 0);
  std::fill(cmd.begin() + 1, cmd.end(), 500.0);  // a 500 mm step hits the current limit
  RunDrive(d, 2000, FeedForward{}, cmd, &saturated);
  EXPECT_GT(saturated, 0);
}

// Acceleration feed-forward (the drive's option besides seed 004's velocity
// FF) lowers what velocity FF leaves on a sine (most of that residual is the
// half-period delay of the differenced command, which torque FF cannot undo).
TEST(FiveAxisDrive, AccelerationFeedForwardReducesTheResidual) {
  DriveParams d;
  d.coulomb = 0;
  std::vector<double> cmd(8000);
  for (std::size_t i = 0; i < cmd.size(); ++i) cmd[i] = 20 * (1 - std::cos(2 * std::numbers::pi * 2 * i / 2000.0));
  auto rms = [&](FeedForward ff) {
    const auto y = RunDrive(d, 2000, ff, cmd);
    double s = 0;
    for (std::size_t i = 0; i < cmd.size(); ++i) s += (cmd[i] - y[i]) * (cmd[i] - y[i]);
    return std::sqrt(s / cmd.size());
  };
  EXPECT_LT(rms({1.0, 1.0}), 0.9 * rms({1.0, 0.0}));
  EXPECT_LT(rms({1.0, 0.0}), 0.1 * rms({0.0, 0.0}));
}

// Joint commands as an inverse-time program: every block lasts its samples,
// the last block ends on the last sample, and replaying it gives the joints back.
TEST(FiveAxisExperiment, CommandsToProgramKeepsTimeAndEnd) {
  FiveAxisMachine m = Machine("table_ac.toml");
  const Kinematics kin(m.kinematics);
  const Trajectory t = Interpolate(MakeTestPath("cone", kin, 3000), m);
  for (int block : {1, 7}) {
    const ToolPath p = CommandsToProgram(t.joints, kin, t.dt_s, block, "p");
    double total = 0;
    for (const auto& v : p.vertices) total += v.duration_s;
    EXPECT_NEAR(total, (t.joints.size() - 1) * t.dt_s, 1e-9) << block;
    const AxisVector end = VertexJoints(p, kin).back();
    for (int a = 0; a < kAxisCount; ++a) EXPECT_NEAR(end[a], t.joints.back()[a], 1e-9);
    if (block == 1) {
      const auto replay = Interpolate(p, m, 0.0).joints;
      ASSERT_EQ(replay.size() + 1, t.joints.size());
      for (std::size_t i = 0; i < replay.size(); i += 97)
        for (int a = 0; a < kAxisCount; ++a) EXPECT_NEAR(replay[i][a], t.joints[i + 1][a], 1e-9);
    }
  }
}

// The whole method on the example A/C machine and on a varied one: the
// corrected program (read back from its text) beats feed-forward alone.
TEST(FiveAxisExperiment, CorrectionReducesTheContourError) {
  for (unsigned variant : {0u, 5u}) {
    const FiveAxisMachine base = Machine("table_ac.toml");
    const FiveAxisMachine m = variant == 0 ? base : VaryMachine(base, variant);
    const TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
    const Experiment x = RunExperiment(m, model, MakeTestPath("inclined-circle", Kinematics(m.kinematics), 4000));
    EXPECT_LT(x.with_ff.contour.rms_um, 0.2 * x.without_ff.contour.rms_um) << m.name;
    EXPECT_LT(x.corrected.contour.rms_um, 0.3 * x.with_ff.contour.rms_um) << m.name;
    EXPECT_EQ(x.corrected.actual.size(), x.trajectory.joints.size());
  }
}

// The long, winding paths on the head B/C example, whose errors come largely
// from friction at starts, stops and reversals (the tip circles while the
// head's X and Y swing at several times its speed): the friction transients
// are identified on the axis's measured motion, so the correction removes
// at least 90 % of what FF alone leaves (83 % and 78 % when they followed the
// command's direction).
TEST(FiveAxisExperiment, HelixAndPocketOnTheHeadAreCorrectedByNinetyPercent) {
  const FiveAxisMachine m = Machine("head_bc.toml");
  const TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
  for (const char* name : {"helix", "inclined-pocket"}) {
    const Experiment x = RunExperiment(m, model, MakeTestPath(name, Kinematics(m.kinematics), 3000));
    EXPECT_LT(x.corrected.contour.rms_um, 0.1 * x.with_ff.contour.rms_um) << name;
    EXPECT_LT(x.corrected.contour.end_point_um, 1.0) << name;
  }
}

// The end point is a constraint: the corrected program of a program with
// sharp corners and a final step ends exactly where the original ends, and
// the re-run of the written program stands there once the drives settle.
TEST(FiveAxisExperiment, CorrectedProgramEndsOnTheProgrammedEndPoint) {
  for (const char* machine : {"table_ac.toml", "head_bc.toml"}) {
    const FiveAxisMachine m = Machine(machine);
    const Kinematics kin(m.kinematics);
    const TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
    const ToolPath path = std::string(machine) == "table_ac.toml"
                              ? ReadProgramFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/fiveaxis/pocket_corner.nc", m, 0)
                              : MakeTestPath("inclined-pocket", kin, 3000);
    const Experiment x = RunExperiment(m, model, path);
    const PathVertex& programmed = path.vertices.back();
    const PathVertex& corrected = x.corrected_program.vertices.back();
    EXPECT_LT((corrected.tip_mm - programmed.tip_mm).norm(), 1e-6) << machine;  // 1 nm
    EXPECT_NEAR(corrected.tilt_deg, programmed.tilt_deg, 1e-6) << machine;
    EXPECT_NEAR(corrected.rot_deg, programmed.rot_deg, 1e-6) << machine;
    EXPECT_LT(x.corrected.contour.end_point_um, 0.1) << machine;
    EXPECT_GT(x.end_rest_added_s, 0.0) << machine << ": the default 50 ms rest does not let the model settle";
    // The correction still does its work along the path.
    EXPECT_LT(x.corrected.contour.rms_um, 0.5 * x.with_ff.contour.rms_um) << machine;
  }
}

// A varied head whose heavy X and Y ring (a slow speed loop under a heavy load): the model
// without the drive mode leaves 9 and 10 % of their identification run's error unexplained
// (the correction removed only 8.5 % of the contour error on a pocket) and identification says
// so, naming the axes; with the drive mode they fit to about 1 %, and the well-described base
// machine (about 2 %) gets no warning either way.
TEST(FiveAxisIdentification, WarnsAboutAxesTheModelDescribesPoorly) {
  const FiveAxisMachine base = Machine("head_bc.toml");
  AxisTestOptions without_mode;
  without_mode.search_mode = false;
  const TrackingErrorModel good = IdentifyTrackingModel(base, without_mode, VirtualMachineRunner(base));
  EXPECT_TRUE(ModelFitWarnings(good, base.axis_names()).empty());
  const FiveAxisMachine m = VaryMachine(base, 33);
  const TrackingErrorModel model = IdentifyTrackingModel(m, without_mode, VirtualMachineRunner(m));
  const std::vector<std::string> warnings = ModelFitWarnings(model, m.axis_names());
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("axis X:"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("axis Y:"), std::string::npos) << warnings[1];
  // A model read from a file without fit figures gives no warning.
  TrackingErrorModel bare = model;
  for (auto& ax : bare.axes) ax.fit_rms = ax.signal_rms = 0;
  EXPECT_TRUE(ModelFitWarnings(bare, m.axis_names()).empty());
  // With the drive mode the same axes are described well.
  const TrackingErrorModel with_mode = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
  EXPECT_TRUE(ModelFitWarnings(with_mode, m.axis_names()).empty());
  for (int axis : {kX, kY}) {
    EXPECT_TRUE(with_mode.axes[axis].mode.present()) << axis;
    EXPECT_LT(with_mode.axes[axis].fit_rms, 0.02 * with_mode.axes[axis].signal_rms) << axis;
  }
}

// On a drive that rings (a varied head whose X the plain passes made worse
// after the third: predicted residual 1.03 µm after 3 passes, 2.54 µm after
// 16), more passes keep lowering the model's predicted residual: each pass
// takes, per window, the fraction of its step that leaves the least.
TEST(FiveAxisCorrection, MorePassesKeepLoweringThePredictedResidual) {
  const FiveAxisMachine m = VaryMachine(Machine("head_bc.toml"), 22);
  const Kinematics kin(m.kinematics);
  const TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
  std::vector<AxisVector> q = Interpolate(MakeTestPath("cone", kin, 6000), m).joints;
  const double dt = 1.0 / m.servo_rate_hz, kf = ChooseFeedForward(model, q, dt).averaged;
  ExtendRestUntilSettled(q, model, dt, kf);
  auto predicted_residual_um = [&](int passes, int axis) {
    const std::vector<AxisVector> u = CorrectCommands(kin, model, q, dt, kf, passes);
    const std::vector<AxisVector> e = PredictTrackingError(model, u, dt, kf, &q);
    double sum = 0;
    for (std::size_t i = 0; i < q.size(); ++i) sum += std::pow(u[i][axis] - e[i][axis] - q[i][axis], 2);
    return 1e3 * std::sqrt(sum / static_cast<double>(q.size()));
  };
  for (int axis : {kX, kY}) {
    const double after3 = predicted_residual_um(3, axis), after8 = predicted_residual_um(8, axis),
                 after16 = predicted_residual_um(16, axis);
    EXPECT_LE(after8, after3 * 1.001) << "axis " << axis;
    EXPECT_LE(after16, after8 * 1.001) << "axis " << axis;
    EXPECT_LT(after16, 0.4) << "axis " << axis;  // µm; FF alone leaves 2.9 (X) and 5.1 (Y)
  }
}

TEST(FiveAxisCorrection, RestIsLengthenedUntilThePredictedErrorDecays) {
  const FiveAxisMachine m = Machine("head_bc.toml");
  const Kinematics kin(m.kinematics);
  const TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
  Trajectory t = Interpolate(MakeTestPath("inclined-pocket", kin, 3000), m);
  const std::size_t before = t.joints.size();
  const double added_s = ExtendRestUntilSettled(t.joints, model, t.dt_s, 1.0, 1e-7);
  EXPECT_NEAR(added_s, static_cast<double>(t.joints.size() - before) * t.dt_s, 1e-12);
  EXPECT_GT(added_s, 0.0);
  for (std::size_t i = before; i < t.joints.size(); ++i) EXPECT_EQ(t.joints[i], t.joints[before - 1]);
  const auto error = PredictTrackingError(model, t.joints, t.dt_s, 1.0);
  for (int a = 0; a < kAxisCount; ++a) EXPECT_LE(std::abs(error.back()[a]), 1e-7) << a;
}

// A run that stops 2 µm beside the end point: the contour error there is
// about the distance to the path's last segment, the end point error 2 µm.
TEST(FiveAxisContour, EndPointIsTheLastSampleAgainstTheLastVertex) {
  const FiveAxisMachine m = Machine("table_ac.toml");
  const Kinematics kin(m.kinematics);
  const ToolPath path = MakeTestPath("inclined-pocket", kin, 3000);
  std::vector<AxisVector> actual = Interpolate(path, m).joints;
  EXPECT_LT(EvaluateContour(path, kin, actual).end_point_um, 1e-6);
  // 2 µm back along the last side (still on the path) and 1 µm off it.
  const Eigen::Vector3d along = (path.vertices[path.vertices.size() - 2].tip_mm - path.vertices.back().tip_mm).normalized();
  const Eigen::Vector3d normal = kin.ToolAxis(path.vertices.back().tilt_deg, path.vertices.back().rot_deg);
  const PathVertex& end = path.vertices.back();
  actual.back() = kin.Inverse(end.tip_mm + 0.002 * along + 0.001 * normal, end.tilt_deg, end.rot_deg);
  const ContourErrors c = EvaluateContour(path, kin, actual);
  EXPECT_NEAR(c.end_point_um, std::sqrt(5.0), 1e-6);
  EXPECT_NEAR(c.position_um.back(), 1.0, 1e-6);
}

TEST(FiveAxisPaths, HelixWindsThreeTurnsAndThePocketHasFourSharpCorners) {
  const FiveAxisMachine m = Machine("table_ac.toml");
  const Kinematics kin(m.kinematics);
  const ToolPath helix = MakeTestPath("helix", kin, 3000);
  EXPECT_NEAR(std::abs(helix.vertices.back().rot_deg - helix.vertices.front().rot_deg), 1080.0, 1.0);
  EXPECT_NEAR(helix.vertices.front().tip_mm.z() - helix.vertices.back().tip_mm.z(), 15.0, 1e-9);
  const ToolPath pocket = MakeTestPath("inclined-pocket", kin, 3000);
  ASSERT_EQ(pocket.vertices.size(), 5u);
  EXPECT_LT((pocket.vertices.front().tip_mm - pocket.vertices.back().tip_mm).norm(), 1e-9);
  for (const PathVertex& v : pocket.vertices) {
    EXPECT_EQ(v.tilt_deg, pocket.vertices.front().tilt_deg);
    EXPECT_EQ(v.rot_deg, pocket.vertices.front().rot_deg);
  }
  EXPECT_THROW(MakeTestPath("spiral", kin, 3000), InputError);
}

}  // namespace
}  // namespace trueaxis::fiveaxis
