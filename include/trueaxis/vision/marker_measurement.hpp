#pragma once
// Reads the seed-001 marker from one grey image (docs/vision.md, "Measurement"):
//   1. spindle silhouette (column profile, then sub-pixel limb points per row),
//   2. ink mask (grey closing = local background, Otsu on the darkness),
//      rings = horizontal runs, lines = vertical runs (morphological opening),
//   3. sub-pixel stroke centres: per column (rings) / row (lines), the two
//      edges of the ink stroke located by the centroid of the gradient lobe,
//      the centre = their midpoint (blur, light level and ink width cancel),
//   4. points undistorted with the camera model; roll from the lines' slope,
//   5. a cylinder model: the limbs give the axis direction, the visible lines
//      give r = R/D and the rotation (two or more lines 90° apart), every ring
//      point is mapped back onto the cylinder and the ring heights averaged,
//   6. CB1 = ring spacing, CB2 = chord between adjacent lines (√2·R),
//      K1 = CB1/CBb1, K2 = CB2/CBb2, credible when |K1/K2 − 1| ≤ ε,
//      Czs = Czb·K1, Δz = Czs − Czb; with a reference scale in view ([scale]),
//      K1 and K2 are divided by its reading first.
// Bad input (empty image, wrong size) throws InputError; a frame without a
// usable marker returns a reading whose status says why (it counts towards the
// stop rule, CredibilityMonitor).
#include <deque>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "trueaxis/vision/camera_model.hpp"
#include "trueaxis/vision/marker.hpp"

namespace trueaxis::vision {

enum class ReadingStatus {
  kCredible,     // K1 and K2 agree within ε: Δz is valid
  kNotCredible,  // measured, but K1 and K2 disagree
  kTooFewLines,  // fewer than two axial lines could be measured
  kNoMarker,     // no spindle or no pair of rings found
  kOutOfFrame,   // the marker (or the spindle's outline) runs out of the image
};
std::string_view ReadingStatusName(ReadingStatus s);

struct MarkerReading {
  ReadingStatus status = ReadingStatus::kNoMarker;
  std::string reason;      // why not credible / not measured
  double cb1_mm = 0, cb2_mm = 0;  // CBs1, CBs2 (at the marker file's camera distance)
  double k1 = 0, k2 = 0;
  double czs_mm = 0, growth_um = 0;  // Czs = Czb·K1, Δz = Czs − Czb
  // geometry and precision (pixels)
  double scale_raw = 1;             // reference scale: measured spacing / scale_spacing_mm (1 without a scale)
  double roll_deg = 0;
  double radius_ratio = 0;          // r = R / D from the lines
  double radius_ratio_limb = 0;     // r from the silhouette (a cross-check)
  double angle_deg = 0;             // rotation: ψ of the leftmost measured line
  double ring_height_px[2] = {0, 0};    // ring heights at the axis (px from the principal point)
  double ring_height_se_px[2] = {0, 0}; // their standard errors from the residuals
  std::vector<double> line_x_px;        // each line's position (px from the principal point)
  std::vector<double> line_x_se_px;
  double stroke_rms_px = 0;         // RMS of single stroke centres about the fitted model (rings and lines)
  double edge_rms_px = 0;           // scatter of single sub-pixel edges along each ring and line (σ, px)
  int ring_points = 0, line_points = 0;
  // for drawing (pixel coordinates)
  std::vector<cv::Point2d> ring_pixels[2];
  std::vector<std::vector<cv::Point2d>> line_pixels;
  double limb_u_px[2] = {0, 0};

  bool measured() const { return status == ReadingStatus::kCredible || status == ReadingStatus::kNotCredible; }
  bool credible() const { return status == ReadingStatus::kCredible; }
};

// gray: CV_8U (or CV_32F grey levels; a colour image is converted). `source` names the image in errors.
MarkerReading MeasureMarker(const cv::Mat& gray, const CameraModel& camera, const MarkerDescription& marker,
                            const std::string& source);

// Recomputes K1, K2, Czs, Δz and the credibility of a measured reading against
// another reading of the reference scale (MeasureMarker applies the frame's own).
void ApplyScale(MarkerReading& reading, double scale_raw, const MarkerDescription& marker);

// The reference scale moves slowly (a camera mount warming), but one frame reads
// it from few points: the mean of its last `frames` readings is applied instead.
class ScaleAverager {
 public:
  explicit ScaleAverager(int frames);
  void Apply(MarkerReading& reading, const MarkerDescription& marker);  // no-op without a scale

 private:
  int frames_;
  std::deque<double> recent_;
};

// The image with what was found drawn on it (colour, for reports).
cv::Mat DrawReading(const cv::Mat& gray, const MarkerReading& reading);

}  // namespace trueaxis::vision
