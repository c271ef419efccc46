// The correction on a machine whose model fits (docs/fiveaxis.md, "Correction"):
// the model inverted per axis, and the end point of the corrected program
// judged standing on the measured positions.
#include <cmath>

#include <gtest/gtest.h>

#include "trueaxis/fiveaxis/axis_identification.hpp"
#include "trueaxis/fiveaxis/command_correction.hpp"
#include "trueaxis/fiveaxis/experiment.hpp"
#include "trueaxis/fiveaxis/machine_variation.hpp"

namespace trueaxis::fiveaxis {
namespace {

// A varied head (4 kHz; its axes' models fit to 2.2 % or better, no model-fit
// warning) on which the repeated passes stalled: on the helix at 6000 mm/min
// X's friction transient at each reversal (25 µm under FF) kept a predicted
// residual of 0.56 µm rms, 5.5 µm peak, from 8 passes on (the plain passes
// diverge there), and the corrected program's rms error was only 70 % below FF.
struct VariedHead {
  FiveAxisMachine m = VaryMachine(
      ReadFiveAxisMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/fiveaxis/head_bc.toml"), 32);
  Kinematics kin{m.kinematics};
  TrackingErrorModel model = IdentifyTrackingModel(m, AxisTestOptions{}, VirtualMachineRunner(m));
};

const VariedHead& Head() {
  static const VariedHead h;
  return h;
}

double RmsUm(const std::vector<AxisVector>& a, const std::vector<AxisVector>& b, int axis) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::pow(a[i][axis] - b[i][axis], 2);
  return 1e3 * std::sqrt(sum / static_cast<double>(a.size()));
}

// The inverse's predicted actual motion is the programmed one: on X of that
// helix the model's predicted residual is a small fraction of FF's.
TEST(FiveAxisCorrection, ModelInverseLeavesNoPredictedResidual) {
  const VariedHead& h = Head();
  ASSERT_TRUE(ModelFitWarnings(h.model, h.m.axis_names()).empty());
  std::vector<AxisVector> q = Interpolate(MakeTestPath("helix", h.kin, 6000), h.m).joints;
  const double dt = 1.0 / h.m.servo_rate_hz, kf = ChooseFeedForward(h.model, q, dt).averaged;
  ExtendRestUntilSettled(q, h.model, dt, kf);
  auto predicted_actual = [&](const std::vector<AxisVector>& u) {
    const std::vector<AxisVector> e = PredictTrackingError(h.model, u, dt, kf, &q);
    std::vector<AxisVector> y(u.size());
    for (std::size_t i = 0; i < u.size(); ++i)
      for (int a = 0; a < kAxisCount; ++a) y[i][a] = u[i][a] - e[i][a];
    return y;
  };
  const std::vector<AxisVector> inverse = InvertTrackingModel(h.model, q, dt, kf);
  const double ff_um = RmsUm(predicted_actual(q), q, kX);
  const double inverse_um = RmsUm(predicted_actual(inverse), q, kX);
  const double passes_um = RmsUm(predicted_actual(CorrectCommands(h.kin, h.model, q, dt, kf, 8)), q, kX);
  EXPECT_GT(ff_um, 2.0);
  EXPECT_LT(inverse_um, 0.02 * ff_um) << "passes leave " << passes_um << " µm";
  EXPECT_LT(inverse_um, 0.25 * passes_um);
  // The correction starts and ends on the programmed command (it fades in and
  // out over the rests), and it stays bounded.
  for (int a = 0; a < kAxisCount; ++a) {
    EXPECT_EQ(inverse.front()[a], q.front()[a]);
    EXPECT_EQ(inverse.back()[a], q.back()[a]);
  }
  double largest = 0;
  for (std::size_t i = 0; i < q.size(); ++i) largest = std::max(largest, std::abs(inverse[i][kX] - q[i][kX]));
  EXPECT_LT(largest, 0.1);  // mm
}

// On that head the written, re-run corrected program removes at least 90 % of
// FF's rms contour error on the helix and the inclined circle at 6000 mm/min
// (70 % and 79 % with the passes), and ends within 0.1 µm of the programmed end
// point: the s-shape's X creeps for 0.5 s after the final stop, which the model
// does not predict (its predicted error had settled, the measured one not: the
// corrected program ended 1.09 µm off).
TEST(FiveAxisExperiment, VariedHeadWhoseModelFitsIsCorrectedByNinetyPercentAndEndsOnItsEndPoint) {
  const VariedHead& h = Head();
  for (const char* name : {"helix", "inclined-circle", "s-shape"}) {
    const ToolPath path = MakeTestPath(name, h.kin, 6000);
    const Experiment x = RunExperiment(h.m, h.model, path);
    EXPECT_LT(x.corrected.contour.rms_um, 0.1 * x.with_ff.contour.rms_um) << name;
    EXPECT_LT(x.corrected.contour.end_point_um, 0.1) << name;
    EXPECT_LT(x.with_ff.contour.end_point_um, 0.1) << name;  // the runs are judged over the same, longer rest
    EXPECT_LT((x.corrected_program.vertices.back().tip_mm - path.vertices.back().tip_mm).norm(), 1e-6) << name;
    EXPECT_LT((x.corrected_program.vertices.front().tip_mm - path.vertices.front().tip_mm).norm(), 1e-6) << name;
    EXPECT_EQ(x.corrected.actual.size(), x.trajectory.joints.size()) << name;
    if (std::string(name) == "s-shape") EXPECT_GT(x.measured_rest_added_s, 0.0);
  }
}

}  // namespace
}  // namespace trueaxis::fiveaxis
