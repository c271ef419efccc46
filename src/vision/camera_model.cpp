// Camera model, YAML file, (un)distortion (include/trueaxis/vision/camera_model.hpp).
#include "trueaxis/vision/camera_model.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::vision {

bool CameraModel::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (width_px < 16 || height_px < 16 || width_px > 20000 || height_px > 20000)
    return fail("image size must be 16…20000 px");
  if (!(fx > 0 && fy > 0 && std::isfinite(fx) && std::isfinite(fy))) return fail("focal lengths must be > 0");
  if (!(cx > 0 && cx < width_px && cy > 0 && cy < height_px)) return fail("principal point must lie inside the image");
  for (double k : {k1, k2, p1, p2, k3})
    if (!std::isfinite(k) || std::abs(k) > 50) return fail("distortion coefficients must be finite and |k| ≤ 50");
  return true;
}

CameraModel CameraModel::ForField(int width, int height, double field_mm, double distance_mm, double k1) {
  CameraModel c;
  c.width_px = width;
  c.height_px = height;
  c.fx = c.fy = width * distance_mm / field_mm;
  c.cx = 0.5 * (width - 1);
  c.cy = 0.5 * (height - 1);
  c.k1 = k1;
  return c;
}

std::vector<cv::Point2d> UndistortToNormalised(const CameraModel& cam, const std::vector<cv::Point2d>& pixels) {
  std::vector<cv::Point2d> out;
  if (pixels.empty()) return out;
  // Iterative undistortion to convergence (OpenCV's default 5 iterations leave ~1e-3 px at the corners).
  cv::undistortPoints(pixels, out, cv::Mat(cam.Matrix()), cam.Distortion(), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  return out;
}

cv::Point2d ProjectNormalised(const CameraModel& cam, cv::Point2d n) {
  const double r2 = n.x * n.x + n.y * n.y;
  const double radial = 1 + cam.k1 * r2 + cam.k2 * r2 * r2 + cam.k3 * r2 * r2 * r2;
  const double xd = n.x * radial + 2 * cam.p1 * n.x * n.y + cam.p2 * (r2 + 2 * n.x * n.x);
  const double yd = n.y * radial + cam.p1 * (r2 + 2 * n.y * n.y) + 2 * cam.p2 * n.x * n.y;
  return {cam.fx * xd + cam.cx, cam.fy * yd + cam.cy};
}

CameraModel ReadCameraFile(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "no such camera file");
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_AUTO);
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "", "not an OpenCV YAML/XML camera file: " + std::string(e.err));
  }
  if (!fs.isOpened()) throw InputError(path, "not an OpenCV YAML/XML camera file");
  CameraModel c;
  cv::Mat k, d;
  // Each field read on its own, so a malformed one is named (OpenCV's own text is an assertion).
  auto read = [&](const char* field, auto& out, const char* expected) {
    try {
      fs[field] >> out;
    } catch (const cv::Exception&) {
      throw InputError(path, 0, field, std::string("malformed: expected ") + expected);
    }
  };
  constexpr const char* kMatrix = "an !!opencv-matrix with rows, cols, dt and rows × cols data values";
  read("camera_matrix", k, kMatrix);
  read("distortion_coefficients", d, kMatrix);
  read("image_width", c.width_px, "a whole number of pixels");
  read("image_height", c.height_px, "a whole number of pixels");
  if (!fs["rms_reprojection_px"].empty()) read("rms_reprojection_px", c.rms_reprojection_px, "a number");
  if (k.rows != 3 || k.cols != 3) throw InputError(path, 0, "camera_matrix", "missing or not 3×3");
  if (d.total() != 4 && d.total() != 5 && d.total() != 8 && d.total() != 12 && d.total() != 14)
    throw InputError(path, 0, "distortion_coefficients", "missing or not 4/5/8 coefficients");
  k.convertTo(k, CV_64F);
  d = d.reshape(1, 1);
  d.convertTo(d, CV_64F);
  for (int i = 5; i < static_cast<int>(d.total()); ++i)
    if (d.at<double>(0, i) != 0)
      throw InputError(path, 0, "distortion_coefficients", "rational/thin-prism terms (k4…) are not supported: use k1 k2 p1 p2 k3");
  c.fx = k.at<double>(0, 0);
  c.fy = k.at<double>(1, 1);
  c.cx = k.at<double>(0, 2);
  c.cy = k.at<double>(1, 2);
  c.k1 = d.at<double>(0, 0);
  c.k2 = d.at<double>(0, 1);
  c.p1 = d.at<double>(0, 2);
  c.p2 = d.at<double>(0, 3);
  c.k3 = d.total() > 4 ? d.at<double>(0, 4) : 0.0;
  std::string why;
  if (!c.IsValid(&why)) throw InputError(path, 0, "", why);
  return c;
}

void WriteCameraFile(const std::string& path, const CameraModel& cam) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw InputError(path, "cannot write the camera file");
  fs << "image_width" << cam.width_px << "image_height" << cam.height_px;
  fs << "camera_matrix" << cv::Mat(cam.Matrix());
  fs << "distortion_coefficients" << cam.Distortion();
  fs << "rms_reprojection_px" << cam.rms_reprojection_px;
}

}  // namespace trueaxis::vision
