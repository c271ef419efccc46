#include "trueaxis/analysis/analysis_report.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "test_util.hpp"

using namespace trueaxis;

TEST(AnalysisReport, ShowsSetupTemperaturesResultsAndCharts) {
  auto m = trueaxis::testing::MakeMeasurement({0, 50, 100}, {{1, 2}, {3, 4}, {5, 6}}, {{2, 3}, {4, 5}, {6, 7}});
  m.source = "x <axis>.csv";
  m.SetMeta("machine", "VMC <850> & co");
  m.SetMeta("axis", "Y");
  m.sensor_names = {"nut"};
  double t = 20.0;
  for (auto& p : m.points) p.temperatures_c = {t += 0.1};
  const auto ev = analysis::Evaluate(m);
  analysis::DecompositionOptions o;
  o.lead_mm = 5;
  const auto d = analysis::Decompose(ev, o);
  analysis::AnalysisReportInput in;
  in.before = {&m, &ev};
  in.decomposition = &d;
  const auto html = analysis::BuildAnalysisReport(in).Render();
  EXPECT_NE(html.find("Positioning test of axis Y"), std::string::npos);
  EXPECT_NE(html.find("VMC &lt;850&gt; &amp; co"), std::string::npos);  // metadata shown, escaped
  EXPECT_NE(html.find("x &lt;axis&gt;.csv"), std::string::npos);
  EXPECT_NE(html.find("temperature nut"), std::string::npos);
  EXPECT_NE(html.find("range 20.10"), std::string::npos);
  EXPECT_NE(html.find("forward ±2s"), std::string::npos);
  EXPECT_NE(html.find("aliased"), std::string::npos);  // 50 mm targets vs a 5 mm lead
  EXPECT_EQ(html.find("After:"), std::string::npos);
  int svgs = 0;
  for (auto p = html.find("<svg xmlns"); p != std::string::npos; p = html.find("<svg xmlns", p + 1)) ++svgs;
  EXPECT_EQ(svgs, 4);  // deviation, repeatability, decomposition, periodic/residual

  // With an "after" test: before/after/change columns and the extra charts.
  auto after_m = m;
  for (auto& p : after_m.points) p.deviation_um *= 0.5;
  const auto after_ev = analysis::Evaluate(after_m);
  in.after = analysis::AnalyzedTest{&after_m, &after_ev};
  const auto html2 = analysis::BuildAnalysisReport(in).Render();
  EXPECT_NE(html2.find("After: forward and reverse mean deviation"), std::string::npos);
  EXPECT_NE(html2.find("change (µm)"), std::string::npos);
  EXPECT_NE(html2.find(fmt::format("{:+.4f}", after_ev.axis.E_um - ev.axis.E_um)), std::string::npos);

  analysis::AnalysisReportInput empty;
  EXPECT_THROW(analysis::BuildAnalysisReport(empty), std::invalid_argument);
}
