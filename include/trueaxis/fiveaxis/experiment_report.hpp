#pragma once
// HTML report of a five-axis experiment (report/ page and charts): the path,
// contour error (position and orientation) along it for no FF / FF / FF +
// correction with RMS and max, and each axis's tracking error.
#include <string>

#include "trueaxis/fiveaxis/experiment.hpp"
#include "trueaxis/report/html_page.hpp"

namespace trueaxis::fiveaxis {

report::HtmlPage BuildExperimentReport(const Experiment& x, const FiveAxisMachine& m, const TrackingErrorModel& model);

// 100 · (1 − after / before); 0 when before is 0.
double ReductionPercent(double before, double after);

}  // namespace trueaxis::fiveaxis
