#include <cmath>
#include <filesystem>
#include <limits>
#include <regex>
#include <set>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "trueaxis/core/text_file.hpp"
#include "trueaxis/report/html_page.hpp"
#include "trueaxis/report/svg_chart.hpp"

namespace tr = trueaxis::report;

namespace {
int Count(const std::string& s, const std::string& what) {
  int n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}
}  // namespace

TEST(NiceTicks, CoverRangeWithRoundSteps) {
  auto t = tr::NiceTicks(-3.2, 11.7, 8);
  ASSERT_GE(t.size(), 4u);
  const double step = t[1] - t[0];
  EXPECT_DOUBLE_EQ(step, 2.0);
  EXPECT_GE(t.front(), -3.2);
  EXPECT_LE(t.back(), 11.7);
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], step, 1e-12);
  EXPECT_EQ(tr::NiceTicks(5, 5, 8), std::vector<double>{5});
  EXPECT_TRUE(tr::NiceTicks(0, std::numeric_limits<double>::quiet_NaN(), 8).empty());
  auto small = tr::NiceTicks(0, 0.001, 5);
  EXPECT_NEAR(small[1] - small[0], 0.0002, 1e-15);
}

TEST(FormatTick, DecimalsFollowStep) {
  EXPECT_EQ(tr::FormatTick(2.5, 0.5), "2.5");
  EXPECT_EQ(tr::FormatTick(10, 10), "10");
  EXPECT_EQ(tr::FormatTick(0.25, 0.25), "0.25");
  EXPECT_EQ(tr::FormatTick(-1e-17, 0.1), "0.0");
}

TEST(SvgChart, RendersSeriesLegendAndEscapedText) {
  tr::SvgChartOptions o;
  o.title = "A<B & \"C\"";
  o.x_label = "target (mm)";
  o.y_label = "deviation (µm)";
  tr::SvgChart chart(o);
  chart.AddBand("±2s", {0, 100, 200}, {-1, -2, -1}, {1, 2, 3});
  chart.AddLine("mean", {0, 100, 200}, {0, 1, 2});
  chart.AddPoints("runs <raw>", {0, 100}, {0.5, 1.5});
  chart.AddHorizontalLine("limit", 4, {.color = "#ff0000", .dashed = true});
  const auto svg = chart.Render();
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("A&lt;B &amp; &quot;C&quot;"), std::string::npos);
  EXPECT_NE(svg.find("runs &lt;raw&gt;"), std::string::npos);
  EXPECT_EQ(svg.find("<raw>"), std::string::npos);
  EXPECT_EQ(Count(svg, "<polygon"), 1);
  EXPECT_EQ(Count(svg, "<polyline"), 1);
  EXPECT_NE(svg.find("#ff0000"), std::string::npos);
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
  EXPECT_NE(svg.find("target (mm)"), std::string::npos);
  EXPECT_NE(svg.find(">200<"), std::string::npos);  // an x tick label in data units
  // Opening and closing svg tags balance (nested plot area).
  EXPECT_EQ(Count(svg, "<svg"), Count(svg, "</svg>"));
}

TEST(SvgChart, HigherValueIsDrawnHigher) {
  tr::SvgChart chart;
  chart.AddPoints("p", {0, 1}, {0, 10});
  const auto svg = chart.Render();
  std::regex circle(R"re(<circle cx="([0-9.]+)" cy="([0-9.]+)")re");
  std::vector<double> cy;
  for (std::sregex_iterator it(svg.begin(), svg.end(), circle), end; it != end; ++it)
    cy.push_back(std::stod((*it)[2]));
  // Two data circles plus the legend marker.
  ASSERT_GE(cy.size(), 2u);
  EXPECT_GT(cy[0], cy[1]);  // y = 0 lies below y = 10 (SVG y grows downwards)
}

TEST(SvgChart, NanBreaksLineAndEmptyChartSaysNoData) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  tr::SvgChart chart;
  chart.AddLine("l", {0, 1, 2, 3, 4}, {0, 1, nan, 3, 4});
  EXPECT_EQ(Count(chart.Render(), "<polyline"), 2);
  tr::SvgChart empty;
  EXPECT_NE(empty.Render().find("no data"), std::string::npos);
  tr::SvgChart all_nan;
  all_nan.AddLine("l", {nan}, {nan});
  EXPECT_NE(all_nan.Render().find("no data"), std::string::npos);
}

TEST(SvgChart, RejectsMismatchedSeriesAndBadOptions) {
  tr::SvgChart chart;
  EXPECT_THROW(chart.AddLine("l", {0, 1}, {0}), std::invalid_argument);
  EXPECT_THROW(chart.AddBand("b", {0, 1}, {0, 1}, {0}), std::invalid_argument);
  tr::SvgChartOptions bad;
  bad.width_px = 10;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("width_px"), std::string::npos);
  EXPECT_THROW(tr::SvgChart{bad}, std::invalid_argument);
}

TEST(HtmlPage, SelfContainedEscapedAndSaved) {
  tr::HtmlPage page("Report <1>");
  page.AddHeading("Setup & data");
  page.AddParagraph("x < y");
  page.AddKeyValueTable({{"machine", "VMC <850>"}});
  tr::HtmlTable t({"target (mm)", "x̄↑ (µm)"}, "per target");
  t.AddRow({"0", "1.25"}).AddRow({"100", "text"}).AddRow({"12.5 µm", "5 from 15 to 55.8 mm"});
  EXPECT_THROW(t.AddRow({"only one"}), std::invalid_argument);
  page.AddTable(t);
  tr::SvgChart chart;
  chart.AddLine("l", {0, 1}, {0, 1});
  page.AddChart(chart);
  const auto html = page.Render();
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("<title>Report &lt;1&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("Setup &amp; data"), std::string::npos);
  EXPECT_NE(html.find("VMC &lt;850&gt;"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"num\">1.25</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>text</td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"num\">12.5 µm</td>"), std::string::npos);  // number + unit: right
  EXPECT_NE(html.find("<td>5 from 15 to 55.8 mm</td>"), std::string::npos);     // prose: left
  EXPECT_NE(html.find("<svg"), std::string::npos);
  // Self-contained: no scripts, no external resources.
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);

  const auto path = (std::filesystem::temp_directory_path() / "trueaxis_report_test.html").string();
  page.Save(path);
  EXPECT_EQ(trueaxis::ReadTextFile(path), html);
  std::filesystem::remove(path);
}

TEST(EscapeHtml, AllSpecialCharacters) {
  EXPECT_EQ(tr::EscapeHtml("<a href='x'>&\"</a>"), "&lt;a href=&#39;x&#39;&gt;&amp;&quot;&lt;/a&gt;");
  EXPECT_EQ(tr::EscapeHtml("µm ±2s"), "µm ±2s");
}

TEST(SvgChart, FixedLimitsOverrideTheDataRange) {
  tr::SvgChartOptions o;
  o.y_min = -10;
  o.y_max = 10;
  o.x_min = 0;
  o.x_max = 100;
  tr::SvgChart chart(o);
  chart.AddLine("l", {0, 50}, {1, 2});
  const auto svg = chart.Render();
  EXPECT_NE(svg.find(">-10.0<"), std::string::npos);  // tick labels at the fixed limits (step 2.5)
  EXPECT_NE(svg.find(">10.0<"), std::string::npos);
  EXPECT_NE(svg.find(">100<"), std::string::npos);
  tr::SvgChartOptions bad;
  bad.y_min = 5;
  bad.y_max = 1;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("y_min"), std::string::npos);
}

namespace {

// Every series of a chart looks different: 20 lines get 20 distinct (colour, dash) styles (the
// palette of 8 made x_nut and z_motor the same blue), and an explicit colour is not reused.
TEST(SvgChartStyle, EverySeriesHasItsOwnLook) {
  tr::SvgChart chart{tr::SvgChartOptions{}};
  chart.AddLine("explicit", {0, 1}, {0, 1}, tr::SeriesStyle{"#0072B2"});
  for (int i = 0; i < 20; ++i) chart.AddLine("s" + std::to_string(i), {0, 1}, {double(i), double(i + 1)});
  const std::string svg = chart.Render();
  std::regex poly(R"re(<polyline fill="none" stroke="(#[0-9A-Fa-f]{6})" stroke-width="[0-9.]+"( stroke-dasharray="[0-9 ]+")?)re");
  std::set<std::string> looks;
  int lines = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), poly); it != std::sregex_iterator(); ++it) {
    ++lines;
    looks.insert((*it)[1].str() + (*it)[2].str());
  }
  EXPECT_EQ(lines, 21);
  EXPECT_EQ(looks.size(), 21u);
}

// The legend stands right of the plot frame, never over the data; a vertical marker is drawn.
TEST(SvgChartStyle, LegendOutsideThePlotAndVerticalMarker) {
  tr::SvgChartOptions o;
  o.x_label = "time (h)";
  o.y_label = "error (µm)";
  tr::SvgChart chart(o);
  chart.AddLine("measured", {0, 10}, {0, 5});
  chart.AddVerticalLine("validation starts", 6);
  const std::string svg = chart.Render();
  std::smatch frame, legend;
  ASSERT_TRUE(std::regex_search(svg, frame, std::regex(R"re(<rect x="([0-9.]+)" y="[0-9.]+" width="([0-9.]+)" height="[0-9.]+" fill="none" stroke="#666"/>)re")));
  ASSERT_TRUE(std::regex_search(svg, legend, std::regex(R"re(<g class="legend"><rect x="([0-9.]+)")re")));
  EXPECT_GE(std::stod(legend[1]), std::stod(frame[1]) + std::stod(frame[2]));
  EXPECT_NE(svg.find("validation starts"), std::string::npos);
}

// Legend labels are never cut: a long label wraps onto further lines of the legend (every word
// visible, no ellipsis), and a legend taller than the plot makes the chart taller.
TEST(SvgChartStyle, LongLegendLabelsWrapInsteadOfBeingCut) {
  tr::SvgChartOptions o;
  o.height_px = 150;
  tr::SvgChart chart(o);
  const std::string coolant = "coolant on (5) / off (0), the state the machine reported each minute";
  const std::string ri = "R_i (bidirectional repeatability at each target, ISO 230-2) — µm";
  chart.AddLine(coolant, {0, 1}, {0, 5});
  chart.AddLine(ri, {0, 1}, {1, 2});
  for (int k = 0; k < 6; ++k) chart.AddLine("series " + std::to_string(k), {0, 1}, {static_cast<double>(k), k + 1.0});
  const std::string svg = chart.Render();
  EXPECT_EQ(svg.find("…"), std::string::npos);
  // The visible text of each legend entry: its tspans, joined.
  std::vector<std::string> entries;
  const std::regex text_re(R"re(<text x="[0-9.]+" y="[0-9.]+">((?:<tspan[^>]*>[^<]*</tspan>)+)</text>)re");
  const std::regex tspan_re(R"re(<tspan[^>]*>([^<]*)</tspan>)re");
  int wrapped = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), text_re); it != std::sregex_iterator(); ++it) {
    const std::string inner = (*it)[1].str();
    std::string joined;
    int lines = 0;
    for (auto t = std::sregex_iterator(inner.begin(), inner.end(), tspan_re); t != std::sregex_iterator(); ++t, ++lines)
      joined += (joined.empty() ? "" : " ") + (*t)[1].str();
    if (lines > 1) ++wrapped;
    entries.push_back(joined);
  }
  ASSERT_EQ(entries.size(), 8u);
  EXPECT_EQ(entries[0], coolant);
  EXPECT_EQ(entries[1], ri);
  EXPECT_EQ(wrapped, 2);
  // Eight entries, two of them on several lines, do not fit 150 px: the chart grew.
  std::smatch height;
  ASSERT_TRUE(std::regex_search(svg, height, std::regex(R"re(class="chart" width="[0-9]+" height="([0-9]+)")re")));
  EXPECT_GT(std::stoi(height[1]), 150);
}

TEST(SvgChartStyle, WrapLabelCountsCharactersNotBytesAndSplitsLongWords) {
  // 10 two-byte characters fit a 10-character line.
  EXPECT_EQ(tr::WrapLabel("µµµµµµµµµµ", 10), std::vector<std::string>{"µµµµµµµµµµ"});
  EXPECT_EQ(tr::WrapLabel("ab cd ef", 5), (std::vector<std::string>{"ab cd", "ef"}));
  EXPECT_EQ(tr::WrapLabel("abcdefgh", 3), (std::vector<std::string>{"abc", "def", "gh"}));
  EXPECT_EQ(tr::WrapLabel("ααααα", 2), (std::vector<std::string>{"αα", "αα", "α"}));
}

}  // namespace
