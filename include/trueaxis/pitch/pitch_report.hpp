#pragma once
// The HTML report of `trueaxis pitch report`: the analysis report of the fine
// run before and after (analysis_report.hpp: ISO 230-2, curves, the seed-002
// decomposition of `before`), followed by the pitch table's own section —
// seed 002's figures before/after (maximum positioning error, 3σ error band)
// with ISO 230-2 A, E, R, B, at every fine target and at the lead points
// only; the table's interpolation error against the repeatability; the table
// curves over the measured means; optionally the following error vs feed.
#include <vector>

#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/pitch/error_table.hpp"
#include "trueaxis/pitch/proof.hpp"
#include "trueaxis/report/html_page.hpp"

namespace trueaxis::pitch {

struct PitchReportInput {
  const measure::Measurement* before = nullptr;  // fine run without the table
  const measure::Measurement* after = nullptr;   // fine run with it
  const PitchErrorTable* table = nullptr;
  std::vector<FollowingPoint> following;         // optional
};

report::HtmlPage BuildPitchReport(const PitchReportInput& in);

}  // namespace trueaxis::pitch
