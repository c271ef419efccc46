#pragma once
// SvgChart: a small, dependency-free x/y chart rendered as one inline <svg>
// element, meant to be embedded in self-contained HTML reports (HtmlPage).
//
//   report::SvgChartOptions o;
//   o.title = "X axis, mean deviation"; o.x_label = "target (mm)"; o.y_label = "deviation (µm)";
//   report::SvgChart chart(o);
//   chart.AddBand("±2s forward", x, lower, upper);
//   chart.AddLine("forward mean", x, y_fwd);
//   chart.AddPoints("runs", xs, ys);
//   std::string svg = chart.Render();
//
// Series are drawn in the order added (add bands first so lines sit on top).
// NaN values are skipped (a line is broken there). Colours default to a
// fixed palette by series index, so the same call order gives the same look.
// Legend labels are never cut: a label wider than the legend wraps onto
// further lines, and the chart grows taller when the legend needs the room.
// All text is XML-escaped. Mismatched vector lengths throw std::invalid_argument.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace trueaxis::report {

struct SvgChartOptions {
  int width_px = 860;
  int height_px = 360;
  std::string title;
  std::string x_label;  // include the unit, e.g. "target position (mm)"
  std::string y_label;  // e.g. "deviation (µm)"
  bool show_legend = true;
  bool y_includes_zero = true;  // deviation charts read better with 0 in view
  int target_tick_count = 8;    // approximate number of ticks per axis
  // Fixed axis limits (data units); unset = fitted to the data. Data outside is clipped.
  std::optional<double> x_min, x_max, y_min, y_max;

  bool IsValid(std::string* why) const;
};

struct SeriesStyle {
  std::string color;           // CSS colour; empty = palette colour by series index
  double width_px = 1.8;       // line width
  bool dashed = false;
  double fill_opacity = 0.18;  // bands
  double marker_radius_px = 2.5;  // points (and line markers if > 0 and markers = true)
  bool markers = false;        // lines: draw a dot at each vertex
};

class SvgChart {
 public:
  explicit SvgChart(SvgChartOptions options = {});

  SvgChart& AddLine(std::string label, std::vector<double> x, std::vector<double> y, SeriesStyle style = {});
  SvgChart& AddPoints(std::string label, std::vector<double> x, std::vector<double> y, SeriesStyle style = {});
  // Shaded area between lower(x) and upper(x).
  SvgChart& AddBand(std::string label, std::vector<double> x, std::vector<double> lower, std::vector<double> upper,
                    SeriesStyle style = {});
  // Horizontal reference line across the whole chart (e.g. a tolerance).
  SvgChart& AddHorizontalLine(std::string label, double y, SeriesStyle style = {});
  // Vertical marker across the whole chart at x (e.g. where validation data starts).
  SvgChart& AddVerticalLine(std::string label, double x, SeriesStyle style = {});

  const SvgChartOptions& options() const { return options_; }
  std::size_t series_count() const { return series_.size(); }

  // The <svg ...>...</svg> element. A chart without finite data renders a
  // frame saying "no data" rather than failing.
  std::string Render() const;

 private:
  enum class Kind { kLine, kPoints, kBand, kHLine, kVLine };
  struct Series {
    Kind kind;
    std::string label;
    std::vector<double> x, y, y2;
    SeriesStyle style;
  };
  SvgChartOptions options_;
  std::vector<Series> series_;
};

// "Nice" tick values (1, 2, 2.5, 5 × 10^k steps) covering [lo, hi], about
// `target_count` of them. Returns {lo} when lo == hi.
std::vector<double> NiceTicks(double lo, double hi, int target_count);
// Text of a tick value with just enough decimals for the given step.
std::string FormatTick(double value, double step);
// A legend label broken at spaces into lines of at most `max_chars` characters (UTF-8 characters,
// not bytes); a word longer than a line is split at a character. Nothing is dropped: every
// character of the label but the spaces broken at is on some line, in order.
std::vector<std::string> WrapLabel(std::string_view label, std::size_t max_chars);

}  // namespace trueaxis::report
