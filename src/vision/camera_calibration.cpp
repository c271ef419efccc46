// Chessboard camera calibration (include/trueaxis/vision/camera_calibration.hpp).
#include "trueaxis/vision/camera_calibration.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::vision {

CalibrationResult CalibrateCamera(const std::vector<std::pair<std::string, cv::Mat>>& images, const ChessboardSpec& b) {
  if (b.cols < 3 || b.rows < 3 || !(b.square_mm > 0))
    throw InputError("command line", 0, "--board", "the board needs ≥ 3×3 inner corners and a square size > 0");
  std::vector<cv::Point3f> object;
  for (int j = 0; j < b.rows; ++j)
    for (int i = 0; i < b.cols; ++i) object.emplace_back(static_cast<float>(i * b.square_mm), static_cast<float>(j * b.square_mm), 0.f);
  std::vector<std::vector<cv::Point3f>> objects;
  std::vector<std::vector<cv::Point2f>> corners_all;
  CalibrationResult out;
  cv::Size size;
  // OpenCV's board search needs a few pixels per square (its adaptive threshold fails below that).
  constexpr int kMinPixelsPerSquare = 4;
  const cv::Size smallest((b.cols + 1) * kMinPixelsPerSquare, (b.rows + 1) * kMinPixelsPerSquare);
  for (const auto& [name, img] : images) {
    if (img.empty()) throw InputError(name, "empty image (unreadable or not an image file)");
    if (std::min(img.cols, img.rows) < std::min(smallest.width, smallest.height) ||
        std::max(img.cols, img.rows) < std::max(smallest.width, smallest.height))
      throw InputError(name, 0, "image size",
                       fmt::format("{}×{} px cannot hold a {}×{}-corner chessboard (at least {}×{} px)", img.cols,
                                   img.rows, b.cols, b.rows, smallest.width, smallest.height));
    if (size.area() == 0) size = img.size();
    if (img.size() != size)
      throw InputError(name, 0, "image size", fmt::format("{}×{} px, but the first image is {}×{}", img.cols, img.rows, size.width, size.height));
    cv::Mat gray = img;
    if (img.channels() == 3) cv::cvtColor(img, gray, cv::COLOR_BGR2GRAY);
    else if (img.channels() == 4) cv::cvtColor(img, gray, cv::COLOR_BGRA2GRAY);
    if (gray.depth() == CV_16U) gray.convertTo(gray, CV_8U, 255.0 / 65535.0);
    std::vector<cv::Point2f> corners;
    bool found = false;
    try {
      found = cv::findChessboardCorners(gray, cv::Size(b.cols, b.rows), corners,
                                        cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
    } catch (const cv::Exception&) {
      throw InputError(name, 0, "image", "OpenCV's chessboard search cannot run on this image (size or pixel format)");
    }
    if (!found) {
      out.skipped.push_back(name + ": no " + std::to_string(b.cols) + "×" + std::to_string(b.rows) + " board found");
      continue;
    }
    cv::cornerSubPix(gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 100, 1e-4));
    objects.push_back(object);
    corners_all.push_back(corners);
  }
  if (objects.size() < 3)
    throw InputError(images.empty() ? "command line" : images.front().first, 0, "images",
                     fmt::format("the board was found in {} image(s); calibration needs at least 3", objects.size()));
  cv::Mat k, d;
  std::vector<cv::Mat> rv, tv;
  const double rms = cv::calibrateCamera(objects, corners_all, size, k, d, rv, tv, cv::CALIB_FIX_K3);
  out.camera.width_px = size.width;
  out.camera.height_px = size.height;
  out.camera.fx = k.at<double>(0, 0);
  out.camera.fy = k.at<double>(1, 1);
  out.camera.cx = k.at<double>(0, 2);
  out.camera.cy = k.at<double>(1, 2);
  out.camera.k1 = d.at<double>(0, 0);
  out.camera.k2 = d.at<double>(0, 1);
  out.camera.p1 = d.at<double>(0, 2);
  out.camera.p2 = d.at<double>(0, 3);
  out.camera.k3 = d.at<double>(0, 4);
  out.camera.rms_reprojection_px = rms;
  out.images_used = static_cast<int>(objects.size());
  return out;
}

std::vector<std::pair<cv::Vec3d, cv::Vec3d>> CalibrationPoses(const ChessboardSpec& b, double distance_mm, int count) {
  std::vector<std::pair<cv::Vec3d, cv::Vec3d>> poses;
  const double w = (b.cols - 1) * b.square_mm, h = (b.rows - 1) * b.square_mm;
  for (int i = 0; i < count; ++i) {
    const double a = 2 * 3.14159265358979 * i / count;
    const double tilt = 0.55 * (0.4 + 0.6 * ((i % 3) / 2.0));
    const cv::Vec3d rvec(tilt * std::cos(a), tilt * std::sin(a), 0.1 * std::sin(3 * a));
    // The board's centre lands at `centre` (camera frame): t = centre − R·board_centre.
    const double spread = 0.06 * distance_mm;
    const cv::Vec3d centre(spread * std::cos(a + 1), 0.7 * spread * std::sin(a + 1), distance_mm * (0.95 + 0.15 * ((i % 4) / 3.0)));
    cv::Matx33d R;
    cv::Rodrigues(rvec, R);
    const cv::Vec3d tvec = centre - R * cv::Vec3d(0.5 * w, 0.5 * h, 0);
    poses.emplace_back(rvec, tvec);
  }
  return poses;
}

}  // namespace trueaxis::vision
