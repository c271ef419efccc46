#pragma once
// The motion-heat input of a model (AxisModel::motion_lag_s, issue 10): the axis's feed |dP/dt| in
// m/min through a first-order lag of time constant τ — an observer of the heat the axis's own motion
// puts into its screw and nut, which no sensor measures (the nut sensor reads the nut, hot while it
// runs and cool minutes after it stops; the screw keeps its heat for hours).
//
// Along a logged history (the campaign's or a day's machine log, docs/campaign.md: <axis>_travel_mm,
// the path the axis has travelled) the feed between two rows is their path difference over their
// time difference, held over the interval, and the lag is stepped exactly over it — the same step
// as the runtime's per-cycle AdvanceMotionHeat (thermal_state.hpp), so the fit and the compensator
// see the same M.
#include <vector>

#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/modelfit/fit_input.hpp"

namespace trueaxis::model {

// M (m/min) at each point of `m` (file order) from the history's travel (TemperatureHistory::
// travel_time_s / travel_mm, which reach past the measurement's end). M starts at 0 at the
// history's first row (the window is hours long). NaN for every point when the history has no
// travel, τ <= 0, or a point has no time_s.
std::vector<double> MotionHeatAtPoints(const measure::Measurement& m, const TemperatureHistory& history, double tau_s);

}  // namespace trueaxis::model
