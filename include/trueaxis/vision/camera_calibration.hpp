#pragma once
// Camera calibration from chessboard images (OpenCV findChessboardCorners +
// cornerSubPix + calibrateCamera; ChArUco is avoided: OpenCV 4.6's has known
// layout and corner-interpolation problems). docs/vision.md.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "trueaxis/vision/camera_model.hpp"
#include "trueaxis/vision/virtual_camera.hpp"

namespace trueaxis::vision {

struct ChessboardSpec {
  int cols = 9, rows = 6;   // inner corners
  double square_mm = 8.0;
};

struct CalibrationResult {
  CameraModel camera;
  int images_used = 0;
  std::vector<std::string> skipped;  // images where the board was not found, with the reason
};

// images: (name, grey image); throws InputError when fewer than 3 boards are found
// or the images differ in size.
CalibrationResult CalibrateCamera(const std::vector<std::pair<std::string, cv::Mat>>& images, const ChessboardSpec& board);

// Board poses for a calibration set: tilted up to ±25°, spread over the field.
std::vector<std::pair<cv::Vec3d, cv::Vec3d>> CalibrationPoses(const ChessboardSpec& board, double distance_mm, int count);

}  // namespace trueaxis::vision
