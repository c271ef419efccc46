// HTML report of marker readings (include/trueaxis/vision/vision_report.hpp).
#include "trueaxis/vision/vision_report.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <sodium.h>

namespace trueaxis::vision {

std::string PngDataUriImg(const cv::Mat& image, const std::string& alt) {
  std::vector<unsigned char> png;
  cv::imencode(".png", image, png);
  std::string b64(sodium_base64_ENCODED_LEN(png.size(), sodium_base64_VARIANT_ORIGINAL), '\0');
  sodium_bin2base64(b64.data(), b64.size(), png.data(), png.size(), sodium_base64_VARIANT_ORIGINAL);
  b64.resize(b64.size() - 1);  // the terminating NUL
  return "<img alt=\"" + report::EscapeHtml(alt) + "\" style=\"max-width:100%\" src=\"data:image/png;base64," + b64 + "\">";
}

report::HtmlPage BuildVisionReport(const std::string& title, const MarkerDescription& marker,
                                   const std::vector<ReportRow>& rows, const std::vector<ReportFrame>& frames,
                                   const std::vector<std::pair<std::string, std::string>>& summary) {
  report::HtmlPage page(title);
  page.AddParagraph(
      "Seed 001: two rings and four axial lines drawn on the spindle, photographed from the side. K1 = CB1/CBb1 (ring "
      "spacing), K2 = CB2/CBb2 (chord between adjacent lines); a reading is credible when |K1/K2 − 1| ≤ ε; "
      "Czs = Czb·K1, Δz = Czs − Czb.");
  page.AddKeyValueTable(summary, "summary");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> t, dz, truth, marker_truth, k1, k2, rejected_t, rejected_y;
  for (const auto& r : rows) {
    const double th = r.time_s / 3600.0;
    t.push_back(th);
    dz.push_back(r.reading.credible() ? r.reading.growth_um : nan);
    truth.push_back(r.true_growth_um ? *r.true_growth_um : nan);
    marker_truth.push_back(r.marker_growth_um ? *r.marker_growth_um : nan);
    k1.push_back(r.reading.measured() ? (r.reading.k1 - 1) * 1e6 : nan);
    k2.push_back(r.reading.measured() ? (r.reading.k2 - 1) * 1e6 : nan);
    if (!r.reading.credible()) rejected_t.push_back(th), rejected_y.push_back(0.0);
  }
  report::SvgChartOptions o;
  o.title = "Spindle growth Δz: camera reading against the truth";
  o.x_label = "time (h)";
  o.y_label = "Δz (µm)";
  report::SvgChart c(o);
  if (!rows.empty() && rows.front().true_growth_um) c.AddLine("truth (virtual spindle)", t, truth);
  {
    report::SeriesStyle dashed;
    dashed.dashed = true;
    if (!rows.empty() && rows.front().marker_growth_um)
      c.AddLine("perfect marker reading Czb·(K_true − 1)", t, marker_truth, dashed);
  }
  c.AddPoints("camera, credible readings", t, dz);
  if (!rejected_t.empty()) {
    report::SeriesStyle red;
    red.color = "#c0392b";
    c.AddPoints("rejected frames", rejected_t, rejected_y, red);
  }
  page.AddChart(c);
  report::SvgChartOptions ko;
  ko.title = "Marker strain: K1 − 1 and K2 − 1";
  ko.x_label = "time (h)";
  ko.y_label = "strain (µm/m)";
  report::SvgChart kc(ko);
  kc.AddPoints("K1 − 1 (ring spacing)", t, k1);
  kc.AddPoints("K2 − 1 (line chord)", t, k2);
  page.AddChart(kc);
  if (!frames.empty()) {
    page.AddHeading("Example frames (green: ring points, blue: lines, red: spindle outline)");
    std::string html;
    for (const auto& f : frames)
      html += "<figure style=\"display:inline-block;margin:6px;max-width:48%\">" + PngDataUriImg(f.image, f.caption) +
              "<figcaption>" + report::EscapeHtml(f.caption) + "</figcaption></figure>";
    page.AddRawHtml(html);
  }
  report::HtmlTable table({"frame", "time (h)", "status", "K1", "K2", "Δz (µm)", "truth (µm)", "note"});
  for (const auto& r : rows)
    table.AddRow({r.name, fmt::format("{:.2f}", r.time_s / 3600.0), std::string(ReadingStatusName(r.reading.status)),
                  r.reading.measured() ? fmt::format("{:.7f}", r.reading.k1) : "",
                  r.reading.measured() ? fmt::format("{:.7f}", r.reading.k2) : "",
                  r.reading.measured() ? fmt::format("{:.1f}", r.reading.growth_um) : "",
                  r.true_growth_um ? fmt::format("{:.1f}", *r.true_growth_um) : "",
                  (r.stop ? "STOP: redraw the marker. " : "") + r.reading.reason});
  page.AddTable(table);
  page.AddNote(fmt::format("ε = {:g} %, stop after more than {} non-credible readings in a row; Czb = {} mm.",
                           100 * marker.epsilon, marker.max_rejected_in_row, marker.spindle_length_mm));
  return page;
}

}  // namespace trueaxis::vision
