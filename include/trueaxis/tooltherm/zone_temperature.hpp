#pragma once
// Seed 001, step S4-1: the tool's outer surface split into m zones, each
// measured without contact at one or more points; Tr = mean of the zone's
// readings, Tv = Σ Tr·Sr / Σ Sr with Sr the zone's area
// (docs/tool-thermal.md, "Zones and Tv"). Pure: images in, numbers out.
//
// On an image a zone is a pixel rectangle [row_from, row_to] × [col_from,
// col_to] (inclusive, 0-based). Zone files (TOML):
//   [[zone]]
//   name = "tip"
//   row_from = 10
//   row_to = 29
//   col_from = 22
//   col_to = 27
//   area_mm2 = 628.3
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace trueaxis::tooltherm {

// The temperatures a tool's surface can show (°C): a hot tool just out of the cut reaches a few
// hundred °C, so the shop-floor bound of core/plausibility.hpp (150 °C) is too tight here. A value
// outside is a wrong --scale/--offset (raw counts, kelvin) or a broken file, never a reading.
inline constexpr double kToolTemperatureMinC = -50;
inline constexpr double kToolTemperatureMaxC = 600;
bool PlausibleToolTemperatureC(double value_c);

struct PixelZone {
  std::string name;
  int row_from = 0, row_to = 0, col_from = 0, col_to = 0;  // inclusive
  double area_mm2 = 0;                                       // Sr
  int line = 0;  // line in its zone file (0: made from geometry)
};

struct ZoneFile {
  std::string source;
  std::vector<PixelZone> zones;
};

// InputError(file, line, field) for bad syntax, missing or negative fields, empty or
// reversed rectangles, a non-positive area, duplicate names.
ZoneFile ParseZoneToml(const std::string& text, const std::string& source);
ZoneFile ReadZoneFile(const std::string& path);
std::string ZoneToml(const std::vector<PixelZone>& zones);

// Tr of every zone: the mean of its pixels (image in °C, CV_32F or CV_64F).
// A zone outside the image is an InputError naming the zone file's line and field; a pixel in a
// zone that is not a tool temperature (PlausibleToolTemperatureC: NaN, 1e308, −29 952 °C from a
// negative scale, 302 °C of kelvin read as °C is let through — Tv's range check catches that) is
// one naming the image and the pixel.
std::vector<double> ZoneMeansC(const cv::Mat& image_c, const ZoneFile& zones, const std::string& image_source);

// Tv = Σ Tr·Sr / Σ Sr (std::invalid_argument on size mismatch, empty or non-positive areas).
double WeightedMeanTemperatureC(const std::vector<double>& zone_means_c, const std::vector<double>& areas_mm2);
std::vector<double> ZoneAreas(const std::vector<PixelZone>& zones);

// Spot readings (IR pyrometers) grouped by zone: Tr = mean of the spots of the zone.
// Every zone needs at least one spot (std::invalid_argument otherwise).
struct SpotReading {
  int zone = 0;
  double temperature_c = 0;
};
std::vector<double> SpotZoneMeansC(const std::vector<SpotReading>& spots, std::size_t zone_count);

// A user's thermal image in °C: a 16-bit single-channel PNG/TIFF of raw counts read with OpenCV,
// or a CSV matrix (one image row per line, `,` or `;` separated); every value v becomes
// v·scale + offset_c. InputError naming the file (and line/column for CSV) on bad data.
cv::Mat ReadThermalImage(const std::string& path, double scale, double offset_c);

}  // namespace trueaxis::tooltherm
