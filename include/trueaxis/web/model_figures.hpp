#pragma once
// The before/after figures the machine page shows beside the model in use:
//  - ISO 230-2 from laser tests with compensation off and on (`<stem>_off.csv` + `<stem>_on.csv`
//    in one folder, as `trueaxis demo` writes to out/demo/day/): A and E per test, evaluated here
//    by analysis::Evaluate (ISO 230-2:2014);
//  - else the model's own fit summary: per state, uncorrected vs residual maximum (|error| before
//    and after the model, on the fit's data) — labelled as such, not as an ISO figure.
#include <string>
#include <vector>

#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

// Pairs in `dir` (a missing folder gives none). A file that does not read is skipped with a note
// in `warnings`.
std::vector<ModelFigure> IsoFiguresFromLaserPairs(const std::string& dir, std::vector<std::string>* warnings = nullptr);
std::vector<ModelFigure> FiguresFromFitSummary(const model::CompositeModel& model);

}  // namespace trueaxis::web
