#pragma once
// CameraModel: pinhole intrinsics + Brown–Conrady distortion (k1 k2 p1 p2 k3),
// the model OpenCV's calibrateCamera fits. Stored as OpenCV FileStorage YAML
// (camera_matrix, distortion_coefficients, image_width, image_height) so a
// camera calibrated elsewhere with OpenCV reads as is (docs/vision.md).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace trueaxis::vision {

struct CameraModel {
  int width_px = 640;
  int height_px = 480;
  double fx = 1600, fy = 1600, cx = 319.5, cy = 239.5;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  double rms_reprojection_px = -1;  // from calibration; −1 when not calibrated

  cv::Matx33d Matrix() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
  cv::Mat Distortion() const { return (cv::Mat_<double>(1, 5) << k1, k2, p1, p2, k3); }
  bool IsValid(std::string* why) const;
  // A lens for a `width`×`height` sensor whose horizontal field covers `field_mm` at `distance_mm`.
  static CameraModel ForField(int width, int height, double field_mm, double distance_mm, double k1 = 0);
};

// Pixel (distorted) → normalised undistorted coordinates (x/z, y/z).
std::vector<cv::Point2d> UndistortToNormalised(const CameraModel& cam, const std::vector<cv::Point2d>& pixels);
// Normalised undistorted → pixel (applies distortion).
cv::Point2d ProjectNormalised(const CameraModel& cam, cv::Point2d normalised);

CameraModel ReadCameraFile(const std::string& path);  // InputError names file and field
void WriteCameraFile(const std::string& path, const CameraModel& cam);

}  // namespace trueaxis::vision
