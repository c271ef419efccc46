#include "trueaxis/tooltherm/zone_temperature.hpp"

#include <cmath>
#include <filesystem>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/vision/image_file.hpp"

namespace trueaxis::tooltherm {

ZoneFile ParseZoneToml(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  TomlTableReader top(root, source, "");
  const toml::node* n = top.Node("zone");
  if (!n) throw InputError(source, 0, "zone", "no [[zone]] defined");
  const auto* arr = n->as_array();
  if (!arr || !arr->is_array_of_tables()) top.Fail("zone", n, "must be an array of tables ([[zone]])");
  top.RejectUnknown();
  ZoneFile file{source, {}};
  std::set<std::string> names;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::table& zt = *(*arr)[i].as_table();
    TomlTableReader r(zt, source, fmt::format("zone[{}]", i));
    PixelZone z;
    z.line = r.Line(&zt);
    r.String("name", z.name);
    if (z.name.empty()) z.name = fmt::format("zone{}", i + 1);
    if (!names.insert(z.name).second) r.Fail("name", zt.get("name"), "zone '" + z.name + "' is defined twice");
    for (auto [key, out] : {std::pair{"row_from", &z.row_from}, {"row_to", &z.row_to}, {"col_from", &z.col_from},
                            {"col_to", &z.col_to}}) {
      if (!zt.contains(key)) r.Fail(key, nullptr, "required (0-based pixel index, inclusive)");
      r.Int(key, *out, 0, 100000);
    }
    if (z.row_to < z.row_from) r.Fail("row_to", zt.get("row_to"), "must be ≥ row_from");
    if (z.col_to < z.col_from) r.Fail("col_to", zt.get("col_to"), "must be ≥ col_from");
    r.Double("area_mm2", z.area_mm2, 1e-9, 1e9, true);
    r.RejectUnknown();
    file.zones.push_back(z);
  }
  if (file.zones.empty()) throw InputError(source, 0, "zone", "no [[zone]] defined");
  return file;
}

ZoneFile ReadZoneFile(const std::string& path) { return ParseZoneToml(ReadTextFile(path), path); }

std::string ZoneToml(const std::vector<PixelZone>& zones) {
  std::string s = "# Zones of a thermal image (docs/tool-thermal.md): pixel rectangles, inclusive, and area Sr\n";
  for (const auto& z : zones)
    s += fmt::format("\n[[zone]]\nname = \"{}\"\nrow_from = {}\nrow_to = {}\ncol_from = {}\ncol_to = {}\narea_mm2 = {:.3f}\n",
                     z.name, z.row_from, z.row_to, z.col_from, z.col_to, z.area_mm2);
  return s;
}

bool PlausibleToolTemperatureC(double value_c) {
  return value_c >= kToolTemperatureMinC && value_c <= kToolTemperatureMaxC;
}

std::vector<double> ZoneMeansC(const cv::Mat& image_c, const ZoneFile& zf, const std::string& image_source) {
  if (image_c.channels() != 1 || (image_c.depth() != CV_32F && image_c.depth() != CV_64F))
    throw std::invalid_argument("ZoneMeansC: image must be one channel of float or double");
  cv::Mat img;
  image_c.convertTo(img, CV_64F);
  std::vector<double> means;
  for (std::size_t i = 0; i < zf.zones.size(); ++i) {
    const PixelZone& z = zf.zones[i];
    const std::string field = fmt::format("zone[{}]", i);
    if (z.row_to >= img.rows)
      throw InputError(zf.source, z.line, field + ".row_to",
                       fmt::format("{} is outside {} ({} rows)", z.row_to, image_source, img.rows));
    if (z.col_to >= img.cols)
      throw InputError(zf.source, z.line, field + ".col_to",
                       fmt::format("{} is outside {} ({} columns)", z.col_to, image_source, img.cols));
    double sum = 0;
    for (int r = z.row_from; r <= z.row_to; ++r)
      for (int c = z.col_from; c <= z.col_to; ++c) {
        const double v = img.at<double>(r, c);
        if (!std::isfinite(v))
          throw InputError(image_source, 0, fmt::format("pixel ({}, {})", r, c),
                           "is not a number, inside zone '" + z.name + "'");
        if (!PlausibleToolTemperatureC(v))
          throw InputError(image_source, 0, fmt::format("pixel ({}, {})", r, c),
                           fmt::format("{:g} °C inside zone '{}' is not a tool temperature ({:g}…{:g} °C): check "
                                       "--scale and --offset (raw counts? kelvin: --offset -273.15)",
                                       v, z.name, kToolTemperatureMinC, kToolTemperatureMaxC));
        sum += v;
      }
    means.push_back(sum / ((z.row_to - z.row_from + 1.0) * (z.col_to - z.col_from + 1.0)));
  }
  return means;
}

double WeightedMeanTemperatureC(const std::vector<double>& tr, const std::vector<double>& sr) {
  if (tr.size() != sr.size() || tr.empty()) throw std::invalid_argument("Tv: one area per zone mean, at least one zone");
  double num = 0, den = 0;
  for (std::size_t i = 0; i < tr.size(); ++i) {
    if (!(sr[i] > 0)) throw std::invalid_argument("Tv: zone areas must be > 0");
    num += tr[i] * sr[i];
    den += sr[i];
  }
  return num / den;
}

std::vector<double> ZoneAreas(const std::vector<PixelZone>& zones) {
  std::vector<double> a;
  for (const auto& z : zones) a.push_back(z.area_mm2);
  return a;
}

std::vector<double> SpotZoneMeansC(const std::vector<SpotReading>& spots, std::size_t zone_count) {
  std::vector<double> sum(zone_count, 0.0), n(zone_count, 0.0);
  for (const auto& s : spots) {
    if (s.zone < 0 || static_cast<std::size_t>(s.zone) >= zone_count)
      throw std::invalid_argument(fmt::format("spot reading for zone {} of {}", s.zone, zone_count));
    sum[static_cast<std::size_t>(s.zone)] += s.temperature_c;
    n[static_cast<std::size_t>(s.zone)] += 1;
  }
  for (std::size_t z = 0; z < zone_count; ++z) {
    if (n[z] == 0) throw std::invalid_argument(fmt::format("zone {} has no spot (seed 001: at least one per zone)", z));
    sum[z] /= n[z];
  }
  return sum;
}

namespace {

cv::Mat ReadCsvMatrix(const std::string& path, double scale, double offset_c) {
  const std::string text = ReadTextFile(path);
  LineCursor cur(text);
  std::vector<std::vector<double>> rows;
  while (cur.Next()) {
    std::string line(cur.line());
    if (line.empty() || line[0] == '#') continue;
    for (char& ch : line)
      if (ch == ';' || ch == '\t') ch = ',';
    std::vector<double> row;
    int col = 0;
    for (std::string_view f : SplitCsvFields(line)) {
      ++col;
      const auto v = ParseDouble(f);
      if (!v || !std::isfinite(*v))
        throw InputError(path, cur.number(), fmt::format("column {}", col), fmt::format("'{}' is not a number", f));
      row.push_back(*v * scale + offset_c);
    }
    if (!rows.empty() && row.size() != rows.front().size())
      throw InputError(path, cur.number(), "columns",
                       fmt::format("{} values, the first row has {}: every row of the matrix needs the same count",
                                   row.size(), rows.front().size()));
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw InputError(path, "no numbers: expected a CSV matrix of the image's pixels");
  cv::Mat m(static_cast<int>(rows.size()), static_cast<int>(rows.front().size()), CV_64F);
  for (int r = 0; r < m.rows; ++r)
    for (int c = 0; c < m.cols; ++c) m.at<double>(r, c) = rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
  return m;
}

}  // namespace

cv::Mat ReadThermalImage(const std::string& path, double scale, double offset_c) {
  if (!(std::isfinite(scale) && scale > 0))
    throw InputError(path, 0, "--scale", fmt::format("{:g}: the scale must be a positive number (°C per count)", scale));
  if (!std::isfinite(offset_c)) throw InputError(path, 0, "--offset", "the offset must be a finite number of °C");
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, "no such file");
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".csv" || ext == ".txt") return ReadCsvMatrix(path, scale, offset_c);
  const cv::Mat raw = vision::DecodeImageFile(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (raw.empty())
    throw InputError(path, "not an image OpenCV can read (expected a 16-bit single-channel PNG/TIFF or a CSV matrix)");
  if (raw.depth() != CV_16U && raw.depth() != CV_8U)
    throw InputError(path, 0, "depth", "expected 16-bit (or 8-bit) pixels holding raw counts");
  if (raw.depth() == CV_8U)
    throw InputError(path, 0, "depth", "8-bit image: a thermal camera's raw counts need 16 bits (export a 16-bit PNG)");
  cv::Mat out;
  raw.convertTo(out, CV_64F, scale, offset_c);
  return out;
}

}  // namespace trueaxis::tooltherm
