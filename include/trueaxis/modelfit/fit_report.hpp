#pragma once
// Self-contained HTML report of a fit (report::HtmlPage): the summary tables
// and, per state, the measured error against the model's curve for both
// directions (seed 000 Fig. 4), so an engineer can see where the model holds.
#include <string>
#include <vector>

#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/model_fit.hpp"

namespace trueaxis::model {

std::string RenderFitReportHtml(const FitResult& result, const std::vector<FitState>& states);
void WriteFitReportHtml(const FitResult& result, const std::vector<FitState>& states, const std::string& path);

}  // namespace trueaxis::model
