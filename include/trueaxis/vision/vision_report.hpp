#pragma once
// HTML report of a series of marker readings (docs/vision.md): Δz against the
// truth (when known), K1/K2 and credibility over time, a table, and example
// frames with the detected marker drawn on them (PNG data URIs).
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "trueaxis/report/html_page.hpp"
#include "trueaxis/vision/marker.hpp"
#include "trueaxis/vision/marker_measurement.hpp"

namespace trueaxis::vision {

struct ReportRow {
  std::string name;
  double time_s = 0;
  MarkerReading reading;
  std::optional<double> true_growth_um;  // the spindle's real Δz, when known
  bool stop = false;
  std::optional<double> marker_growth_um;  // Czb·(K_true − 1): a perfect reading of the marker, when known
};

struct ReportFrame {
  std::string caption;
  cv::Mat image;  // with the reading drawn on it (DrawReading)
};

// <img> element holding the image as an embedded PNG.
std::string PngDataUriImg(const cv::Mat& image, const std::string& alt);

report::HtmlPage BuildVisionReport(const std::string& title, const MarkerDescription& marker,
                                   const std::vector<ReportRow>& rows, const std::vector<ReportFrame>& frames,
                                   const std::vector<std::pair<std::string, std::string>>& summary);

}  // namespace trueaxis::vision
