#pragma once
// The seed-001 deformation marker and the set-up it is read in (docs/vision.md):
// two rings coaxial with the spindle, `circle_spacing_mm` apart (CBb1), joined
// by `line_count` (4) evenly spaced axial lines; CBb2 = the chord between two
// adjacent lines = diameter·sin(π/line_count). Sizes are at standard_temp_c.
#include <string>

namespace trueaxis::vision {

struct MarkerDescription {
  // [marker]
  double circle_spacing_mm = 40.0;  // CBb1: ring centre line to ring centre line
  double diameter_mm = 80.0;        // spindle diameter at the marker
  int line_count = 4;
  double ink_width_mm = 1.0;
  // [spindle]
  double spindle_length_mm = 300.0;  // Czb: the spindle's standard size (fixed bearing to nose)
  double standard_temp_c = 20.0;
  // [camera]
  double distance_mm = 250.0;  // camera centre to the spindle axis, at the standard state
  // [credibility]
  double epsilon = 0.001;      // credible when |K1/K2 − 1| ≤ ε (seed: 0.1 % ≤ ε ≤ 5 %)
  int max_rejected_in_row = 5;  // more than this many non-credible readings in a row: stop
  // [scale] optional reference scale of low expansion (invar) in the field of view,
  // beside the spindle in the plane of its axis: two bars scale_spacing_mm apart on
  // a light strip scale_width_mm wide, centred scale_x_mm to the right of the axis
  // (spacing measured vertically at the strip's centre line).
  // K1 and K2 are divided by its reading, which removes changes of magnification
  // (camera-mount drift, focus) that the ε test cannot see. 0 = no scale.
  double scale_spacing_mm = 0.0;
  double scale_x_mm = 50.0;
  double scale_width_mm = 8.0;
  double scale_tilt_deg = 5.0;  // bars slanted against the pixel rows (spreads the sub-pixel phase, as a slanted-edge target)
  bool has_scale() const { return scale_spacing_mm > 0; }
  // [reference] raw K1, K2 read from images at the standard temperature
  // (`trueaxis vision reference`); readings are divided by them, which removes
  // the set-up's constant bias (camera distance, perspective of the ink width).
  double reference_k1 = 1.0;
  double reference_k2 = 1.0;

  double Cbb1Mm() const { return circle_spacing_mm; }
  double Cbb2Mm() const;  // chord between adjacent lines
  bool IsValid(std::string* why) const;
  // True when ε lies inside the seed's range [0.1 %, 5 %].
  bool EpsilonInSeedRange() const { return epsilon >= 0.001 - 1e-12 && epsilon <= 0.05 + 1e-12; }
};

// Reads a marker TOML file; InputError names file, line and key.
MarkerDescription ReadMarkerFile(const std::string& path);
MarkerDescription ParseMarkerToml(const std::string& text, const std::string& source);
std::string MarkerToml(const MarkerDescription& m);

}  // namespace trueaxis::vision
