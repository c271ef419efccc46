#pragma once
// The HTML report of `trueaxis analyze --report`: one self-contained page
// (report::HtmlPage) with the test setup (metadata, temperatures), the axis
// results, the forward/reverse mean deviation curves with their ±k·s bands
// (before and after when a comparison is given), repeatability/reversal per
// target, the error decomposition and the per-target table.
#include <optional>

#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/report/html_page.hpp"

namespace trueaxis::analysis {

struct AnalyzedTest {
  const measure::Measurement* measurement = nullptr;
  const Evaluation* evaluation = nullptr;
};

struct AnalysisReportInput {
  AnalyzedTest before;                 // required
  std::optional<AnalyzedTest> after;   // --compare
  const Decomposition* decomposition = nullptr;  // of `before`; optional
};

report::HtmlPage BuildAnalysisReport(const AnalysisReportInput& in);

}  // namespace trueaxis::analysis
