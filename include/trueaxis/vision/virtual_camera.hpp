#pragma once
// VirtualCamera: renders the seed-001 marker on a spindle (or a calibration
// chessboard) as a real camera would record it (docs/vision.md):
// exact ray casting through the lens distortion onto the cylinder (every pixel
// is its own undistorted ray; edges anti-aliased over the pixel footprint),
// then optical blur, uneven and changing light, specular glints, coolant
// droplets, chips, a worn marker, sensor noise and 8-bit quantisation.
//
// Geometry (camera frame: x right, y down, z forward): the spindle axis is
// vertical (parallel to y) at x = drift_x, z = distance + drift_distance; the rings
// sit at y = drift_y ± CB1·K/2; line i lies at ψ = angle + 90°·i, ψ = 0 facing the
// camera, ψ growing to the image's right.
#include <cstdint>

#include <opencv2/core.hpp>

#include "trueaxis/vision/camera_model.hpp"
#include "trueaxis/vision/marker.hpp"

namespace trueaxis::vision {

// The physical state of marker, spindle and camera mount at one frame.
struct MarkerScene {
  double scale = 1.0;           // true K = 1 + strain of the marker (and spindle radius)
  double angle_deg = 45.0;      // rotation of the lines
  double drift_x_mm = 0;        // camera mount drift: where the axis moved in the camera frame
  double drift_y_mm = 0;
  double drift_distance_mm = 0;
  double roll_rad = 0;          // camera rotation about its optical axis
  double light = 1.0;           // global light level (1 = nominal)
  double wear = 0;              // 0 = fresh marker … 1 = worn away
};

// What spoils an image; all off = a clean render (blur and quantisation stay).
struct ImageDisturbances {
  double blur_sigma_px = 0.8;    // focus/optics blur (Gaussian σ)
  double noise_grey = 0.0;       // read noise σ in grey levels
  double shot_noise = 0.0;       // photon noise: σ² += shot_noise·grey
  double light_gradient = 0.0;   // relative brightness change across the image (uneven light)
  int glints = 0;                // specular highlights on the shaft
  int droplets = 0;              // coolant droplets on the marker zone
  int chips = 0;                 // chips stuck on the marker zone
  bool quantise = true;          // 8-bit output (false: keep the float image, for tests)
};

class VirtualCamera {
 public:
  explicit VirtualCamera(CameraModel camera);  // precomputes one ray per pixel
  const CameraModel& camera() const { return camera_; }

  // 8-bit grey image (CV_8U), or CV_32F in grey levels when !quantise.
  cv::Mat RenderMarker(const MarkerDescription& marker, const MarkerScene& scene, const ImageDisturbances& disturbances,
                       std::uint64_t seed) const;
  // A planar chessboard with `cols`×`rows` inner corners (squares of square_mm)
  // at pose (rvec, tvec) (board → camera, mm), as calibrateCamera expects.
  cv::Mat RenderChessboard(int cols, int rows, double square_mm, const cv::Vec3d& rvec, const cv::Vec3d& tvec,
                           const ImageDisturbances& disturbances, std::uint64_t seed) const;

 private:
  cv::Mat Finish(cv::Mat radiance, const ImageDisturbances& d, std::uint64_t seed) const;
  CameraModel camera_;
  cv::Mat rays_;  // CV_64FC2: undistorted normalised ray of each pixel centre
};

}  // namespace trueaxis::vision
