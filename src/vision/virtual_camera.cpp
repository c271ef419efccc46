// Virtual camera: ray-cast marker and chessboard renders with the disturbances
// of a shop floor (include/trueaxis/vision/virtual_camera.hpp, docs/vision.md).
#include "trueaxis/vision/virtual_camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace trueaxis::vision {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kSurfaceGrey = 200, kInkGrey = 30, kBackgroundGrey = 30;

double Ramp(double inside_mm, double footprint_mm) { return std::clamp(inside_mm / footprint_mm + 0.5, 0.0, 1.0); }

double WrapRad(double a) {
  a = std::fmod(a + kPi, 2 * kPi);
  if (a < 0) a += 2 * kPi;
  return a - kPi;
}

// Deterministic hash of a cell → [0, 1): where a worn marker has lost its ink.
double CellHash(std::uint64_t seed, int a, long b) {
  std::uint64_t x = seed * 0x9E3779B97F4A7C15ull ^ (static_cast<std::uint64_t>(a) << 40) ^ static_cast<std::uint64_t>(b);
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdull;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ull;
  x ^= x >> 33;
  return static_cast<double>(x >> 11) / static_cast<double>(1ull << 53);
}

struct Glint {
  double psi_rad, sigma_rad, grey;
};

}  // namespace

VirtualCamera::VirtualCamera(CameraModel camera) : camera_(std::move(camera)) {
  std::string why;
  if (!camera_.IsValid(&why)) throw std::invalid_argument("camera: " + why);
  std::vector<cv::Point2d> pixels;
  pixels.reserve(static_cast<std::size_t>(camera_.width_px) * camera_.height_px);
  for (int v = 0; v < camera_.height_px; ++v)
    for (int u = 0; u < camera_.width_px; ++u) pixels.emplace_back(u, v);
  const auto n = UndistortToNormalised(camera_, pixels);
  rays_.create(camera_.height_px, camera_.width_px, CV_64FC2);
  for (int v = 0, i = 0; v < camera_.height_px; ++v)
    for (int u = 0; u < camera_.width_px; ++u, ++i) rays_.at<cv::Vec2d>(v, u) = {n[i].x, n[i].y};
}

cv::Mat VirtualCamera::RenderMarker(const MarkerDescription& m, const MarkerScene& s, const ImageDisturbances& d,
                                    std::uint64_t seed) const {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double R = 0.5 * m.diameter_mm * s.scale;
  const double D = m.distance_mm + s.drift_distance_mm;
  const double ax = s.drift_x_mm;
  const double half_spacing = 0.5 * m.circle_spacing_mm * s.scale;
  const double ring_y[2] = {s.drift_y_mm - half_spacing, s.drift_y_mm + half_spacing};
  const double half_ink = 0.5 * m.ink_width_mm * s.scale;
  const double cr = std::cos(s.roll_rad), sr = std::sin(s.roll_rad);
  const double ink_grey = kInkGrey + s.wear * 0.6 * (kSurfaceGrey - kInkGrey);
  const double gap_probability = 0.5 * s.wear;
  const double gap_cell_mm = 1.5;
  std::vector<Glint> glints;
  for (int i = 0; i < d.glints; ++i)
    glints.push_back({(-50 + 100 * uni(rng)) * kPi / 180, (1.5 + 3 * uni(rng)) * kPi / 180, 120 + 150 * uni(rng)});
  std::vector<double> line_psi;
  for (int i = 0; i < m.line_count; ++i) line_psi.push_back((s.angle_deg + 360.0 * i / m.line_count) * kPi / 180);

  cv::Mat img(camera_.height_px, camera_.width_px, CV_32F);
  cv::Rect marker_box;  // where ink is, for droplets and chips
  int u0 = camera_.width_px, u1 = -1, v0 = camera_.height_px, v1 = -1;
  for (int v = 0; v < camera_.height_px; ++v) {
    const cv::Vec2d* ray = rays_.ptr<cv::Vec2d>(v);
    float* out = img.ptr<float>(v);
    for (int u = 0; u < camera_.width_px; ++u) {
      const double xr = cr * ray[u][0] - sr * ray[u][1];
      const double yr = sr * ray[u][0] + cr * ray[u][1];
      const double a = xr * xr + 1;
      const double dist_axis = std::abs(xr * D - ax) / std::sqrt(a);
      const double footprint = D * std::sqrt(a) / camera_.fx;  // mm per pixel across the ray near the axis
      const double silhouette = Ramp(R - dist_axis, footprint);
      double value = kBackgroundGrey * (0.9 + 0.2 * std::sin(0.05 * u + 0.03 * v));
      if (m.has_scale()) {  // the invar scale: a light strip with two dark bars, in the axis plane (z = D)
        const double X = xr * D, Y = yr * D, fp = D * std::sqrt(a) / camera_.fx;
        const double strip = Ramp(0.5 * m.scale_width_mm - std::abs(X - ax - m.scale_x_mm), fp);
        if (strip > 0) {
          double bar = 0;
          const double slope = std::tan(m.scale_tilt_deg * kPi / 180);
          const double along = X - ax - m.scale_x_mm;  // from the strip's centre line
          for (double yb : {s.drift_y_mm - 0.5 * m.scale_spacing_mm, s.drift_y_mm + 0.5 * m.scale_spacing_mm})
            bar = std::max(bar, Ramp(0.5 * m.ink_width_mm * std::sqrt(1 + slope * slope) - std::abs(Y - yb - slope * along), fp));
          value = (1 - strip) * value + strip * (kSurfaceGrey * (1 - bar) + kInkGrey * bar);
        }
      }
      if (silhouette > 0) {
        const double b = -2 * (xr * ax + D);
        const double c = ax * ax + D * D - R * R;
        const double disc = std::max(0.0, b * b - 4 * a * c);
        const double t = (-b - std::sqrt(disc)) / (2 * a);
        const double X = t * xr, Y = t * yr, Z = t;
        const double psi = std::atan2(X - ax, D - Z);
        const double cos_psi = std::max(std::cos(psi), 0.02);
        const double fp_axial = t * std::sqrt(a) / camera_.fy;
        const double fp_arc = t * std::sqrt(a) / camera_.fx / cos_psi;
        double ink = 0;
        for (int k = 0; k < 2; ++k) {
          double cov = Ramp(half_ink - std::abs(Y - ring_y[k]), fp_axial);
          if (cov > 0 && gap_probability > 0 &&
              CellHash(seed ^ 0x51ull, k, static_cast<long>(std::floor(psi * R / gap_cell_mm))) < gap_probability)
            cov = 0;
          ink = std::max(ink, cov);
        }
        const double span = Ramp(half_spacing + half_ink - std::abs(Y - s.drift_y_mm), fp_axial);
        if (span > 0)
          for (std::size_t i = 0; i < line_psi.size(); ++i) {
            double cov = span * Ramp(half_ink - R * std::abs(WrapRad(psi - line_psi[i])), fp_arc);
            if (cov > 0 && gap_probability > 0 &&
                CellHash(seed ^ 0xA7ull, 10 + static_cast<int>(i), static_cast<long>(std::floor(Y / gap_cell_mm))) <
                    gap_probability)
              cov = 0;
            ink = std::max(ink, cov);
          }
        if (ink > 0) u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
        const double shading = 0.6 + 0.4 * cos_psi;
        double surface = shading * (kSurfaceGrey * (1 - ink) + ink_grey * ink);
        for (const auto& g : glints) {
          const double z = WrapRad(psi - g.psi_rad) / g.sigma_rad;
          surface += g.grey * std::exp(-0.5 * z * z);
        }
        value = silhouette * surface + (1 - silhouette) * value;
      }
      out[u] = static_cast<float>(value * s.light);
    }
  }
  if (u1 >= u0) marker_box = cv::Rect(u0, v0, u1 - u0 + 1, v1 - v0 + 1);

  // Droplets (a milky lens: lighter and lower contrast, bright rim) and chips (dark flakes) on the marker.
  const double px_per_mm = camera_.fx / D;
  if (marker_box.area() > 0) {
    auto random_point = [&] {
      return cv::Point2d(marker_box.x + uni(rng) * marker_box.width, marker_box.y + uni(rng) * marker_box.height);
    };
    for (int i = 0; i < d.droplets; ++i) {
      const cv::Point2d c = random_point();
      const double r = (0.6 + 2.0 * uni(rng)) * px_per_mm;
      cv::Mat mask = cv::Mat::zeros(img.size(), CV_32F);
      cv::ellipse(mask, cv::Point(cvRound(c.x), cvRound(c.y)), cv::Size(cvRound(r), cvRound(r * (0.7 + 0.3 * uni(rng)))),
                  180 * uni(rng), 0, 360, cv::Scalar(1), cv::FILLED, cv::LINE_AA);
      cv::GaussianBlur(mask, mask, cv::Size(0, 0), 0.8);
      cv::Mat milky = img * 0.55 + 70.0;
      img = img.mul(1 - mask) + milky.mul(mask);
      cv::circle(img, cv::Point(cvRound(c.x - 0.4 * r), cvRound(c.y - 0.4 * r)), std::max(1, cvRound(0.2 * r)),
                 cv::Scalar(255), cv::FILLED, cv::LINE_AA);
    }
    for (int i = 0; i < d.chips; ++i) {
      const cv::Point2d c = random_point();
      const double size = (0.5 + 1.5 * uni(rng)) * px_per_mm;
      std::vector<cv::Point> poly;
      const int n = 5 + static_cast<int>(3 * uni(rng));
      for (int k = 0; k < n; ++k) {
        const double ang = 2 * kPi * (k + 0.3 * uni(rng)) / n;
        const double rad = size * (0.4 + 0.6 * uni(rng));
        poly.emplace_back(cvRound(c.x + rad * std::cos(ang)), cvRound(c.y + rad * std::sin(ang)));
      }
      cv::fillPoly(img, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(25 + 40 * uni(rng)), cv::LINE_AA);
    }
  }
  if (d.light_gradient != 0) {
    const double dir = 2 * kPi * uni(rng);
    for (int v = 0; v < img.rows; ++v) {
      float* p = img.ptr<float>(v);
      for (int u = 0; u < img.cols; ++u) {
        const double q = ((u - 0.5 * img.cols) * std::cos(dir) + (v - 0.5 * img.rows) * std::sin(dir)) / img.cols;
        p[u] = static_cast<float>(p[u] * (1 + d.light_gradient * q));
      }
    }
  }
  return Finish(img, d, rng());
}

cv::Mat VirtualCamera::RenderChessboard(int cols, int rows, double sq, const cv::Vec3d& rvec, const cv::Vec3d& tvec,
                                        const ImageDisturbances& d, std::uint64_t seed) const {
  cv::Matx33d Rm;
  cv::Rodrigues(rvec, Rm);
  const cv::Matx33d Rt = Rm.t();
  const cv::Vec3d origin = -(Rt * tvec);  // camera centre in board coordinates
  cv::Mat img(camera_.height_px, camera_.width_px, CV_32F);
  for (int v = 0; v < camera_.height_px; ++v) {
    const cv::Vec2d* ray = rays_.ptr<cv::Vec2d>(v);
    float* out = img.ptr<float>(v);
    for (int u = 0; u < camera_.width_px; ++u) {
      const cv::Vec3d dir = Rt * cv::Vec3d(ray[u][0], ray[u][1], 1.0);
      double value = 60;
      if (std::abs(dir[2]) > 1e-9) {
        const double lambda = -origin[2] / dir[2];
        if (lambda > 0) {
          const double X = origin[0] + lambda * dir[0], Y = origin[1] + lambda * dir[1];
          const double fp = lambda * cv::norm(cv::Vec3d(ray[u][0], ray[u][1], 1.0)) / camera_.fx / std::max(0.2, std::abs(dir[2]) / cv::norm(dir));
          auto edge = [&](double w, int corners) {  // +1/−1 by square parity, smoothed over the pixel footprint
            const double tq = w / sq;
            const double frac = tq - std::floor(tq);
            double to_edge = std::min(frac, 1 - frac) * sq;
            if (w < 0) to_edge = -w;                                    // outer squares: only the inner line is an edge
            if (w > (corners - 1) * sq) to_edge = w - (corners - 1) * sq;
            const double parity = (static_cast<long>(std::floor(tq)) % 2 == 0) ? 1.0 : -1.0;
            return parity * std::min(1.0, 2 * to_edge / fp);
          };
          const bool in_squares = X >= -sq && X <= cols * sq && Y >= -sq && Y <= rows * sq;
          const bool in_board = X >= -1.6 * sq && X <= (cols + 0.6) * sq && Y >= -1.6 * sq && Y <= (rows + 0.6) * sq;
          if (in_squares) value = 120 + 90 * edge(X, cols) * edge(Y, rows);
          else if (in_board) value = 210;
        }
      }
      out[u] = static_cast<float>(value);
    }
  }
  return Finish(img, d, seed);
}

cv::Mat VirtualCamera::Finish(cv::Mat img, const ImageDisturbances& d, std::uint64_t seed) const {
  if (d.blur_sigma_px > 0) cv::GaussianBlur(img, img, cv::Size(0, 0), d.blur_sigma_px);
  if (d.noise_grey > 0 || d.shot_noise > 0) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    for (int v = 0; v < img.rows; ++v) {
      float* p = img.ptr<float>(v);
      for (int u = 0; u < img.cols; ++u) {
        const double var = d.noise_grey * d.noise_grey + d.shot_noise * std::max(0.0f, p[u]);
        p[u] += static_cast<float>(std::sqrt(var)) * normal(rng);
      }
    }
  }
  if (!d.quantise) return img;
  cv::Mat out;
  img.convertTo(out, CV_8U);  // rounds and saturates at 0 and 255, as a sensor's ADC does
  return out;
}

}  // namespace trueaxis::vision
