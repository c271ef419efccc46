// Marker file reader/writer (docs/vision.md).
#include "trueaxis/vision/marker.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::vision {

double MarkerDescription::Cbb2Mm() const { return diameter_mm * std::sin(std::numbers::pi / line_count); }

bool MarkerDescription::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (!(circle_spacing_mm > 0)) return fail("circle_spacing_mm must be > 0");
  if (!(diameter_mm > 0)) return fail("diameter_mm must be > 0");
  if (line_count != 4) return fail("line_count must be 4 (seed 001: four lines, at least two in any side view)");
  if (!(ink_width_mm > 0 && ink_width_mm < 0.25 * circle_spacing_mm)) return fail("ink_width_mm must be in (0, spacing/4)");
  if (!(distance_mm > 0.5 * diameter_mm)) return fail("distance_mm must exceed the spindle radius");
  if (!(epsilon > 0 && epsilon <= 0.05)) return fail("epsilon must be in (0, 0.05] (seed: 0.1 % … 5 %)");
  if (max_rejected_in_row < 1) return fail("max_rejected_in_row must be ≥ 1");
  if (has_scale() && std::abs(scale_x_mm) < 0.5 * diameter_mm + 0.5 * scale_width_mm + 2 + 2 * ink_width_mm)
    return fail("the reference scale (scale.x_mm) must lie beside the spindle, clear of its outline by 2 mm + 2 ink widths");
  return true;
}

MarkerDescription ParseMarkerToml(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  MarkerDescription m;
  TomlTableReader top(root, source, "");
  auto section = [&](std::string_view key, auto&& read) {
    if (const toml::table* t = top.Table(key)) {
      TomlTableReader r(*t, source, std::string(key));
      read(r);
      r.RejectUnknown();
    }
  };
  section("marker", [&](TomlTableReader& r) {
    r.Double("circle_spacing_mm", m.circle_spacing_mm, 1, 2000, true);
    r.Double("diameter_mm", m.diameter_mm, 5, 2000, true);
    r.Int("line_count", m.line_count, 4, 4);
    r.Double("ink_width_mm", m.ink_width_mm, 0.01, 50);
  });
  section("spindle", [&](TomlTableReader& r) {
    r.Double("length_mm", m.spindle_length_mm, 1, 5000, true);
    r.Double("standard_temp_c", m.standard_temp_c, -10, 60);
  });
  section("camera", [&](TomlTableReader& r) { r.Double("distance_mm", m.distance_mm, 1, 1e5, true); });
  section("credibility", [&](TomlTableReader& r) {
    r.Double("epsilon", m.epsilon, 1e-6, 0.05);
    r.Int("max_rejected_in_row", m.max_rejected_in_row, 1, 1000);
  });
  section("scale", [&](TomlTableReader& r) {
    r.Double("spacing_mm", m.scale_spacing_mm, 1, 2000, true);
    r.Double("x_mm", m.scale_x_mm, -5000, 5000, true);
    r.Double("width_mm", m.scale_width_mm, 0.5, 500);
    r.Double("tilt_deg", m.scale_tilt_deg, -30, 30);
  });
  section("reference", [&](TomlTableReader& r) {
    r.Double("k1", m.reference_k1, 0.9, 1.1);
    r.Double("k2", m.reference_k2, 0.9, 1.1);
  });
  if (!root.contains("marker")) throw InputError(source, 0, "marker", "missing [marker] table");
  top.RejectUnknown();
  std::string why;
  if (!m.IsValid(&why)) throw InputError(source, 0, "", why);
  return m;
}

MarkerDescription ReadMarkerFile(const std::string& path) { return ParseMarkerToml(ReadTextFile(path), path); }

std::string MarkerToml(const MarkerDescription& m) {
  return fmt::format(
      "# seed-001 deformation marker (docs/vision.md); sizes at standard_temp_c\n"
      "[marker]\ncircle_spacing_mm = {}   # CBb1\ndiameter_mm = {}         # lines on this diameter: CBb2 = chord = {:.4f} mm\n"
      "line_count = {}\nink_width_mm = {}\n\n[spindle]\nlength_mm = {}           # Czb\nstandard_temp_c = {}\n\n"
      "[camera]\ndistance_mm = {}         # camera centre to spindle axis\n\n"
      "[credibility]\nepsilon = {}             # credible when |K1/K2 - 1| <= epsilon\nmax_rejected_in_row = {}\n\n"
      "{}"
      "[reference]              # raw K1, K2 at the standard temperature (trueaxis vision reference)\nk1 = {:.9f}\nk2 = {:.9f}\n",
      m.circle_spacing_mm, m.diameter_mm, m.Cbb2Mm(), m.line_count, m.ink_width_mm, m.spindle_length_mm,
      m.standard_temp_c, m.distance_mm, m.epsilon, m.max_rejected_in_row,
      m.has_scale() ? fmt::format("[scale]                  # invar reference scale beside the spindle\nspacing_mm = {}\nx_mm = {}\nwidth_mm = {}\ntilt_deg = {}\n\n",
                                  m.scale_spacing_mm, m.scale_x_mm, m.scale_width_mm, m.scale_tilt_deg)
                    : std::string(),
      m.reference_k1, m.reference_k2);
}

}  // namespace trueaxis::vision
