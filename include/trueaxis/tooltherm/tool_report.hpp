#pragma once
// HTML report of a tool day (`trueaxis tool day --report`): the score table, and per tool the
// true tip error against Tv split by the interval the seed-001 classifier gave (the hysteresis
// made visible) and the error over the test day before and after compensation.
// Pure: returns the page text; the CLI writes it.
#include <string>

#include "trueaxis/tooltherm/tool_evaluation.hpp"

namespace trueaxis::tooltherm {

std::string ToolDayReportHtml(const ToolTable& table, const ToolDayRecording& test, const ToolEvaluation& evaluation,
                              const std::string& subtitle);

}  // namespace trueaxis::tooltherm
