#include "trueaxis/report/svg_chart.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "trueaxis/report/html_page.hpp"

namespace trueaxis::report {
namespace {

// Colour-blind-friendly palette (Okabe–Ito) first, then further distinct hues; a chart with more
// series than colours cycles through dash patterns too, so no two series share a look.
constexpr std::array<const char*, 16> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9",
                                                  "#000000", "#B8A000", "#7F3C8D", "#11A579", "#E73F74", "#3969AC",
                                                  "#80BA5A", "#8C564B", "#F97B72", "#4B4B8F"};
constexpr std::array<const char*, 3> kDashes = {"", " stroke-dasharray=\"6 4\"", " stroke-dasharray=\"2 3\""};

// Plot area margins in px: room for tick labels, axis labels, title. The legend, when shown,
// stands to the right of the plot area, never over the data.
constexpr double kLeft = 70, kRightBare = 20, kTop = 36, kBottom = 52;

std::string Num(double v) { return fmt::format("{:.2f}", v); }

// Legend text metrics: an average character of the 12 px sans-serif font, the row of one series,
// and each further line of a wrapped label.
constexpr double kCharPx = 6.6, kLegendRowPx = 17, kLegendLinePx = 14;

bool Utf8Continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

std::size_t Utf8Length(std::string_view s) {
  return static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char c) { return !Utf8Continuation(c); }));
}

}  // namespace

std::vector<std::string> WrapLabel(std::string_view label, std::size_t max_chars) {
  max_chars = std::max<std::size_t>(max_chars, 1);
  std::vector<std::string> lines;
  std::string line;
  auto push_word = [&](std::string_view word) {
    // A word longer than a line is split at whole UTF-8 characters.
    while (Utf8Length(word) > max_chars) {
      std::size_t cut = 0;
      for (std::size_t n = 0; cut < word.size() && n < max_chars; ++n) {
        ++cut;
        while (cut < word.size() && Utf8Continuation(word[cut])) ++cut;
      }
      if (!line.empty()) lines.push_back(std::move(line)), line.clear();
      lines.emplace_back(word.substr(0, cut));
      word.remove_prefix(cut);
    }
    if (word.empty()) return;
    if (!line.empty() && Utf8Length(line) + 1 + Utf8Length(word) > max_chars) lines.push_back(std::move(line)), line.clear();
    if (!line.empty()) line += ' ';
    line += word;
  };
  std::size_t i = 0;
  while (i < label.size()) {
    while (i < label.size() && label[i] == ' ') ++i;
    std::size_t j = i;
    while (j < label.size() && label[j] != ' ') ++j;
    if (j > i) push_word(label.substr(i, j - i));
    i = j;
  }
  if (!line.empty() || lines.empty()) lines.push_back(std::move(line));
  return lines;
}

namespace {

void CheckSameLength(const std::string& label, std::size_t a, std::size_t b) {
  if (a != b)
    throw std::invalid_argument(fmt::format("SvgChart series '{}': x has {} values, y has {}", label, a, b));
}

}  // namespace

bool SvgChartOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (width_px < 200 || width_px > 10000) return fail("width_px must be in 200..10000");
  if (height_px < 120 || height_px > 10000) return fail("height_px must be in 120..10000");
  if (target_tick_count < 2 || target_tick_count > 50) return fail("target_tick_count must be in 2..50");
  for (const auto* v : {&x_min, &x_max, &y_min, &y_max})
    if (*v && !std::isfinite(**v)) return fail("fixed axis limits must be finite");
  if (x_min && x_max && !(*x_min < *x_max)) return fail("x_min must be below x_max");
  if (y_min && y_max && !(*y_min < *y_max)) return fail("y_min must be below y_max");
  return true;
}

std::vector<double> NiceTicks(double lo, double hi, int target_count) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {};
  if (hi < lo) std::swap(lo, hi);
  if (hi == lo) return {lo};
  const double raw = (hi - lo) / std::max(1, target_count);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  std::vector<double> ticks;
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (double t = first; t <= hi + step * 1e-9; t += step) {
    ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
    if (ticks.size() > 1000) break;
  }
  return ticks;
}

std::string FormatTick(double value, double step) {
  int decimals = 0;
  if (step > 0 && std::isfinite(step)) {
    decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
    // 2.5 × 10^k steps need one more decimal.
    const double scaled = step * std::pow(10.0, decimals);
    if (std::abs(scaled - std::round(scaled)) > 1e-6) ++decimals;
  }
  decimals = std::min(decimals, 9);
  std::string s = fmt::format("{:.{}f}", value, decimals);
  if (s == "-0" || s.find_first_not_of("-0.") == std::string::npos) s = fmt::format("{:.{}f}", 0.0, decimals);
  return s;
}

SvgChart::SvgChart(SvgChartOptions options) : options_(std::move(options)) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("SvgChartOptions: " + why);
}

SvgChart& SvgChart::AddLine(std::string label, std::vector<double> x, std::vector<double> y, SeriesStyle style) {
  CheckSameLength(label, x.size(), y.size());
  series_.push_back({Kind::kLine, std::move(label), std::move(x), std::move(y), {}, std::move(style)});
  return *this;
}

SvgChart& SvgChart::AddPoints(std::string label, std::vector<double> x, std::vector<double> y, SeriesStyle style) {
  CheckSameLength(label, x.size(), y.size());
  series_.push_back({Kind::kPoints, std::move(label), std::move(x), std::move(y), {}, std::move(style)});
  return *this;
}

SvgChart& SvgChart::AddBand(std::string label, std::vector<double> x, std::vector<double> lower,
                            std::vector<double> upper, SeriesStyle style) {
  CheckSameLength(label, x.size(), lower.size());
  CheckSameLength(label, x.size(), upper.size());
  series_.push_back({Kind::kBand, std::move(label), std::move(x), std::move(lower), std::move(upper), std::move(style)});
  return *this;
}

SvgChart& SvgChart::AddHorizontalLine(std::string label, double y, SeriesStyle style) {
  series_.push_back({Kind::kHLine, std::move(label), {}, {y}, {}, std::move(style)});
  return *this;
}

SvgChart& SvgChart::AddVerticalLine(std::string label, double x, SeriesStyle style) {
  series_.push_back({Kind::kVLine, std::move(label), {x}, {}, {}, std::move(style)});
  return *this;
}

std::string SvgChart::Render() const {
  const double w = options_.width_px;
  double h = options_.height_px;
  std::vector<std::size_t> labelled;
  if (options_.show_legend)
    for (std::size_t k = 0; k < series_.size(); ++k)
      if (!series_[k].label.empty()) labelled.push_back(k);
  std::size_t longest = 0;
  for (auto k : labelled) longest = std::max(longest, Utf8Length(series_[k].label));
  // Legend beside the plot: as wide as its longest label, at most 40 % of the chart; a longer
  // label wraps onto further lines (never cut), and the chart grows taller when the legend needs it.
  const double legend_w =
      labelled.empty() ? 0 : std::min(0.4 * w, 40 + kCharPx * static_cast<double>(std::min<std::size_t>(longest, 60)));
  const std::size_t max_chars = static_cast<std::size_t>(std::max(4.0, std::floor((legend_w - 40) / kCharPx + 1e-6)));
  std::vector<std::vector<std::string>> legend_lines;
  double legend_h = 6;
  for (auto k : labelled) {
    legend_lines.push_back(WrapLabel(series_[k].label, max_chars));
    legend_h += kLegendRowPx + kLegendLinePx * static_cast<double>(legend_lines.back().size() - 1);
  }
  const double kRight = labelled.empty() ? kRightBare : legend_w + 14;
  if (!labelled.empty()) h = std::max(h, kTop + legend_h + kBottom);
  const double pw = w - kLeft - kRight, ph = h - kTop - kBottom;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double xmin = kInf, xmax = -kInf, ymin = kInf, ymax = -kInf;
  auto take_y = [&](double v) {
    if (std::isfinite(v)) ymin = std::min(ymin, v), ymax = std::max(ymax, v);
  };
  for (const auto& s : series_) {
    if (s.kind == Kind::kHLine) {
      take_y(s.y[0]);
      continue;
    }
    if (s.kind == Kind::kVLine) {
      if (std::isfinite(s.x[0])) xmin = std::min(xmin, s.x[0]), xmax = std::max(xmax, s.x[0]);
      continue;
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const bool ok = std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && (s.kind != Kind::kBand || std::isfinite(s.y2[i]));
      if (!ok) continue;
      xmin = std::min(xmin, s.x[i]), xmax = std::max(xmax, s.x[i]);
      take_y(s.y[i]);
      if (s.kind == Kind::kBand) take_y(s.y2[i]);
    }
  }
  std::string out = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"sans-serif\" font-size=\"12\" role=\"img\" aria-label=\"{2}\">\n",
      options_.width_px, static_cast<int>(std::ceil(h)), EscapeHtml(options_.title));
  out += fmt::format("<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>\n", options_.width_px,
                     static_cast<int>(std::ceil(h)));
  if (!options_.title.empty())
    out += fmt::format("<text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"14\" font-weight=\"bold\">{}</text>\n",
                       Num(w / 2), EscapeHtml(options_.title));
  if (options_.x_min) xmin = *options_.x_min, xmax = std::max(xmax, xmin);
  if (options_.x_max) xmax = *options_.x_max, xmin = std::min(xmin, xmax);
  if (options_.y_min) ymin = *options_.y_min, ymax = std::max(ymax, ymin);
  if (options_.y_max) ymax = *options_.y_max, ymin = std::min(ymin, ymax);
  if (!std::isfinite(xmin) || !std::isfinite(ymin) || !std::isfinite(xmax) || !std::isfinite(ymax)) {
    out += fmt::format(
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>"
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"#888\">no data</text>\n</svg>\n",
        Num(kLeft), Num(kTop), Num(pw), Num(ph), Num(kLeft + pw / 2), Num(kTop + ph / 2));
    return out;
  }
  const bool fixed_x = options_.x_min || options_.x_max, fixed_y = options_.y_min || options_.y_max;
  if (options_.y_includes_zero && !fixed_y) ymin = std::min(ymin, 0.0), ymax = std::max(ymax, 0.0);
  if (xmax == xmin) xmin -= 0.5, xmax += 0.5;
  if (ymax == ymin) ymin -= 0.5, ymax += 0.5;
  if (!fixed_x) {
    // A little room at the ends so markers on the first/last target are not cut in half.
    const double xpad = 0.02 * (xmax - xmin);
    xmin -= xpad, xmax += xpad;
  }
  if (!fixed_y) {
    const double ypad = 0.06 * (ymax - ymin);
    ymin -= ypad, ymax += ypad;
  }
  auto xticks = NiceTicks(xmin, xmax, options_.target_tick_count);
  auto yticks = NiceTicks(ymin, ymax, options_.target_tick_count);
  // Widen the y range to whole ticks so the frame ends on a labelled value.
  if (yticks.size() >= 2 && !fixed_y) {
    const double step = yticks[1] - yticks[0];
    if (yticks.front() > ymin) yticks.insert(yticks.begin(), yticks.front() - step);
    if (yticks.back() < ymax) yticks.push_back(yticks.back() + step);
    ymin = yticks.front(), ymax = yticks.back();
  }
  auto sx = [&](double x) { return kLeft + (x - xmin) / (xmax - xmin) * pw; };
  auto sy = [&](double y) { return kTop + (ymax - y) / (ymax - ymin) * ph; };

  // Grid, ticks and tick labels.
  const double xstep = xticks.size() >= 2 ? xticks[1] - xticks[0] : 1;
  const double ystep = yticks.size() >= 2 ? yticks[1] - yticks[0] : 1;
  out += "<g stroke=\"#e4e4e4\" stroke-width=\"1\">";
  for (double t : xticks) out += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\"/>", Num(sx(t)), Num(kTop), Num(kTop + ph));
  for (double t : yticks) out += fmt::format("<line x1=\"{1}\" y1=\"{0}\" x2=\"{2}\" y2=\"{0}\"/>", Num(sy(t)), Num(kLeft), Num(kLeft + pw));
  out += "</g>\n";
  if (ymin < 0 && ymax > 0)
    out += fmt::format("<line x1=\"{1}\" y1=\"{0}\" x2=\"{2}\" y2=\"{0}\" stroke=\"#999\" stroke-width=\"1\"/>\n",
                       Num(sy(0)), Num(kLeft), Num(kLeft + pw));
  out += "<g fill=\"#333\">";
  for (double t : xticks)
    out += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>", Num(sx(t)), Num(kTop + ph + 16),
                       FormatTick(t, xstep));
  for (double t : yticks)
    out += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>", Num(kLeft - 6), Num(sy(t) + 4),
                       FormatTick(t, ystep));
  out += "</g>\n";
  if (!options_.x_label.empty())
    out += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", Num(kLeft + pw / 2), Num(h - 10),
                       EscapeHtml(options_.x_label));
  if (!options_.y_label.empty())
    out += fmt::format("<text transform=\"translate(16,{}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
                       Num(kTop + ph / 2), EscapeHtml(options_.y_label));

  // Series, clipped to the plot area.
  out += fmt::format("<svg x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" overflow=\"hidden\" "
                     "viewBox=\"{} {} {} {}\">\n",
                     Num(kLeft), Num(kTop), Num(pw), Num(ph), Num(kLeft), Num(kTop), Num(pw), Num(ph));
  std::vector<std::string> colors, dashes;
  {
    // Palette colours go to the series without their own, skipping colours given explicitly.
    std::vector<std::string> explicit_colors;
    for (const auto& s : series_)
      if (!s.style.color.empty()) explicit_colors.push_back(s.style.color);
    std::vector<std::string> free;
    for (const char* c : kPalette)
      if (std::find(explicit_colors.begin(), explicit_colors.end(), c) == explicit_colors.end()) free.push_back(c);
    std::size_t next = 0;
    for (const auto& s : series_) {
      if (!s.style.color.empty()) {
        colors.push_back(s.style.color);
        dashes.push_back(s.style.dashed ? kDashes[1] : "");
        continue;
      }
      const std::size_t j = next++;
      colors.push_back(free[j % free.size()]);
      const std::size_t cycle = j / free.size();
      dashes.push_back(s.style.dashed ? kDashes[1] : kDashes[cycle % kDashes.size()]);
    }
  }
  for (std::size_t k = 0; k < series_.size(); ++k) {
    const auto& s = series_[k];
    const std::string& color = colors[k];
    const std::string& dash = dashes[k];
    switch (s.kind) {
      case Kind::kHLine:
        if (std::isfinite(s.y[0]))
          out += fmt::format("<line x1=\"{1}\" y1=\"{0}\" x2=\"{2}\" y2=\"{0}\" stroke=\"{3}\" stroke-width=\"{4}\"{5}/>\n",
                             Num(sy(s.y[0])), Num(kLeft), Num(kLeft + pw), color, Num(s.style.width_px), dash);
        break;
      case Kind::kVLine:
        if (std::isfinite(s.x[0]))
          out += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"{3}\" stroke-width=\"{4}\"{5}/>\n",
                             Num(sx(s.x[0])), Num(kTop), Num(kTop + ph), color, Num(s.style.width_px), dash);
        break;
      case Kind::kLine: {
        // One polyline per run of finite points (NaN breaks the line).
        std::string pts;
        auto flush = [&] {
          if (!pts.empty())
            out += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"{}\"{} points=\"{}\"/>\n", color,
                               Num(s.style.width_px), dash, pts);
          pts.clear();
        };
        for (std::size_t i = 0; i < s.x.size(); ++i) {
          if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
            flush();
            continue;
          }
          pts += fmt::format("{},{} ", Num(sx(s.x[i])), Num(sy(s.y[i])));
          if (s.style.markers)
            out += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{}\"/>", Num(sx(s.x[i])), Num(sy(s.y[i])),
                               Num(s.style.marker_radius_px), color);
        }
        flush();
        break;
      }
      case Kind::kPoints:
        out += fmt::format("<g fill=\"{}\">", color);
        for (std::size_t i = 0; i < s.x.size(); ++i)
          if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
            out += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>", Num(sx(s.x[i])), Num(sy(s.y[i])),
                               Num(s.style.marker_radius_px));
        out += "</g>\n";
        break;
      case Kind::kBand: {
        std::vector<std::size_t> idx;
        for (std::size_t i = 0; i < s.x.size(); ++i)
          if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && std::isfinite(s.y2[i])) idx.push_back(i);
        std::stable_sort(idx.begin(), idx.end(), [&](auto a, auto b) { return s.x[a] < s.x[b]; });
        if (idx.empty()) break;
        std::string pts;
        for (auto i : idx) pts += fmt::format("{},{} ", Num(sx(s.x[i])), Num(sy(s.y2[i])));
        for (auto it = idx.rbegin(); it != idx.rend(); ++it)
          pts += fmt::format("{},{} ", Num(sx(s.x[*it])), Num(sy(s.y[*it])));
        out += fmt::format("<polygon fill=\"{}\" fill-opacity=\"{}\" stroke=\"none\" points=\"{}\"/>\n", color,
                           Num(s.style.fill_opacity), pts);
        break;
      }
    }
  }
  out += "</svg>\n";
  out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#666\"/>\n", Num(kLeft),
                     Num(kTop), Num(pw), Num(ph));

  // Legend: right of the plot area, one row per labelled series, long labels wrapped.
  if (!labelled.empty()) {
    const double lx = kLeft + pw + 10, ly = kTop;
    out += fmt::format("<g class=\"legend\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#fff\" "
                       "stroke=\"#bbb\"/>",
                       Num(lx), Num(ly), Num(legend_w), Num(legend_h));
    double row = ly + 15;
    for (std::size_t n = 0; n < labelled.size(); ++n) {
      const std::size_t k = labelled[n];
      const auto& s = series_[k];
      const auto& c = colors[k];
      if (s.kind == Kind::kBand)
        out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"22\" height=\"10\" fill=\"{}\" fill-opacity=\"{}\"/>",
                           Num(lx + 6), Num(row - 9), c, Num(std::max(0.3, s.style.fill_opacity)));
      else if (s.kind == Kind::kPoints)
        out += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"{}\"/>", Num(lx + 17), Num(row - 4), c);
      else
        out += fmt::format("<line x1=\"{0}\" y1=\"{2}\" x2=\"{1}\" y2=\"{2}\" stroke=\"{3}\" stroke-width=\"2\"{4}/>",
                           Num(lx + 6), Num(lx + 28), Num(row - 4), c, dashes[k]);
      const auto& lines = legend_lines[n];
      out += fmt::format("<text x=\"{}\" y=\"{}\">", Num(lx + 34), Num(row));
      for (std::size_t i = 0; i < lines.size(); ++i)
        out += i == 0 ? fmt::format("<tspan>{}</tspan>", EscapeHtml(lines[i]))
                      : fmt::format("<tspan x=\"{}\" dy=\"{}\">{}</tspan>", Num(lx + 34), Num(kLegendLinePx),
                                    EscapeHtml(lines[i]));
      out += "</text>";
      row += kLegendRowPx + kLegendLinePx * static_cast<double>(lines.size() - 1);
    }
    out += "</g>\n";
  }
  out += "</svg>\n";
  return out;
}

}  // namespace trueaxis::report
