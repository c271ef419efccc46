// Seed-001 marker measurement (include/trueaxis/vision/marker_measurement.hpp, docs/vision.md).
#include "trueaxis/vision/marker_measurement.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::vision {

std::string_view ReadingStatusName(ReadingStatus s) {
  switch (s) {
    case ReadingStatus::kCredible: return "credible";
    case ReadingStatus::kNotCredible: return "not credible";
    case ReadingStatus::kTooFewLines: return "too few lines";
    case ReadingStatus::kNoMarker: return "no marker";
    case ReadingStatus::kOutOfFrame: return "out of frame";
  }
  return "?";
}

namespace {

constexpr double kPi = std::numbers::pi;

struct Run {
  int begin, end;  // [begin, end)
  double centre() const { return 0.5 * (begin + end - 1); }
};

// Runs of indices where counts[i] ≥ threshold.
std::vector<Run> Runs(const std::vector<int>& counts, int threshold) {
  std::vector<Run> runs;
  for (int i = 0; i < static_cast<int>(counts.size());) {
    if (counts[i] < threshold) {
      ++i;
      continue;
    }
    int j = i;
    while (j < static_cast<int>(counts.size()) && counts[j] >= threshold) ++j;
    runs.push_back({i, j});
    i = j;
  }
  return runs;
}

// Sub-pixel position of the gradient peak at index `peak` of g: the three-point
// Gaussian fit (exact for a Gaussian-blurred step, whose sampled derivative is a
// Gaussian), falling back to the parabola when a neighbour is not on the same lobe.
double PeakPosition(const std::vector<double>& g, int peak) {
  if (peak <= 0 || peak + 1 >= static_cast<int>(g.size())) return peak;
  const double sign = g[peak] > 0 ? 1.0 : -1.0;
  const double a = sign * g[peak - 1], b = sign * g[peak], c = sign * g[peak + 1];
  if (a > 0 && c > 0) {
    const double la = std::log(a), lb = std::log(b), lc = std::log(c);
    const double den = la - 2 * lb + lc;
    if (den < 0) return peak + std::clamp(0.5 * (la - lc) / den, -0.5, 0.5);
  }
  const double den = a - 2 * b + c;
  return den < 0 ? peak + std::clamp(0.5 * (a - c) / den, -0.5, 0.5) : peak;
}

struct Stroke {
  double centre, left_edge, right_edge;
};

// A dark stroke in profile p (grey levels) near index `guess`: falling and rising
// edges located by the centroid of their gradient lobes; the stroke centre is their midpoint.
std::optional<Stroke> FindStroke(const std::vector<double>& p, double guess, double expected_width, double min_step) {
  const int n = static_cast<int>(p.size());
  if (n < 5) return std::nullopt;
  std::vector<double> g(n - 1);  // g[i] = p[i+1] − p[i], located at i + 0.5
  for (int i = 0; i + 1 < n; ++i) g[i] = p[i + 1] - p[i];
  const int c = std::clamp(static_cast<int>(std::lround(guess)), 1, n - 2);
  const int reach = static_cast<int>(std::ceil(expected_width)) + 3;
  int fall = -1, rise = -1;
  for (int i = std::max(0, c - reach); i < std::min(n - 1, c + 1); ++i)
    if (fall < 0 || g[i] < g[fall]) fall = i;
  for (int i = std::max(0, c - 1); i < std::min(n - 1, c + reach + 1); ++i)
    if (rise < 0 || g[i] > g[rise]) rise = i;
  if (fall < 0 || rise < 0 || rise <= fall) return std::nullopt;
  if (-g[fall] < min_step || g[rise] < min_step) return std::nullopt;
  if (fall < 1 || rise > n - 3) return std::nullopt;  // a lobe cut by the window
  const double left = PeakPosition(g, fall) + 0.5, right = PeakPosition(g, rise) + 0.5;
  const double width = right - left;
  if (width < 0.3 * expected_width || width > 3.0 * expected_width + 3) return std::nullopt;
  // Centre: centroid of the darkness below a straight background line through
  // both sides of the stroke, in a window symmetric about the current estimate
  // (fractional end pixels), iterated. The blurred, pixel-integrated stroke is
  // nearly band-limited, so the centroid of its samples has no pixel-locking
  // bias, unlike a peak or threshold estimate (docs/vision.md).
  double centre = 0.5 * (left + right);
  const double half = 0.5 * width + 3.0;
  for (int it = 0; it < 3; ++it) {
    const double a = centre - half, b = centre + half;
    const int ia = static_cast<int>(std::floor(a)), ib = static_cast<int>(std::ceil(b));
    if (ia - 3 < 0 || ib + 3 >= n) return std::nullopt;
    const double bl = 0.5 * (p[ia - 3] + p[ia - 2]), br = 0.5 * (p[ib + 2] + p[ib + 3]);
    const double xl = ia - 2.5, xr = ib + 2.5;
    double sw = 0, swx = 0;
    for (int i = ia; i <= ib; ++i) {
      // Overlap of pixel i ([i − ½, i + ½]) with the window [a, b].
      const double w = std::clamp(std::min(b, i + 0.5) - std::max(a, i - 0.5), 0.0, 1.0);
      const double base = bl + (br - bl) * (i - xl) / (xr - xl);
      const double d = base - p[i];
      sw += w * d, swx += w * d * i;
    }
    if (sw <= 0) return std::nullopt;
    centre = swx / sw;
  }
  return Stroke{centre, left, right};
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Indices of values within 3 robust σ of the median (MAD); keeps at least half.
std::vector<std::size_t> Inliers(const std::vector<double>& v) {
  const double med = Median(v);
  std::vector<double> dev;
  for (double x : v) dev.push_back(std::abs(x - med));
  const double mad = std::max(1.4826 * Median(dev), 1e-12);
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::abs(v[i] - med) <= 3.0 * mad) keep.push_back(i);
  return keep;
}

struct MeanSe {
  double mean = 0, se = 0, sd = 0;
  int n = 0;
};
MeanSe RobustMean(const std::vector<double>& v) {
  MeanSe r;
  const auto keep = Inliers(v);
  r.n = static_cast<int>(keep.size());
  if (r.n == 0) return r;
  for (auto i : keep) r.mean += v[i];
  r.mean /= r.n;
  double ss = 0;
  for (auto i : keep) ss += (v[i] - r.mean) * (v[i] - r.mean);
  r.sd = r.n > 1 ? std::sqrt(ss / (r.n - 1)) : 0;
  r.se = r.n > 1 ? r.sd / std::sqrt(r.n) : 0;
  return r;
}

// Scatter of single sub-pixel positions sampled along a smooth edge: from the
// second difference e[i] − (e[i−1] + e[i+1])/2 of neighbouring samples (which
// removes the edge's own smooth course), σ² = mean(d²)/1.5; outliers (3 MAD) dropped.
void AddSecondDifferences(const std::vector<std::pair<int, double>>& e, std::vector<double>& out) {
  for (std::size_t i = 1; i + 1 < e.size(); ++i)
    if (e[i - 1].first + 1 == e[i].first && e[i].first + 1 == e[i + 1].first)
      out.push_back((e[i].second - 0.5 * (e[i - 1].second + e[i + 1].second)) / std::sqrt(1.5));
}
double RmsOfInliers(const std::vector<double>& v) {
  double ss = 0;
  const auto keep = Inliers(v);
  for (auto i : keep) ss += v[i] * v[i];
  return keep.empty() ? 0 : std::sqrt(ss / keep.size());
}

// Ray angle γ from the axis direction of a point on the cylinder at ψ (units of D).
double RayAngle(double r, double psi) { return std::atan2(r * std::sin(psi), 1 - r * std::cos(psi)); }

std::vector<double> Column(const cv::Mat& img, int u, int v0, int v1) {
  std::vector<double> p;
  for (int v = v0; v < v1; ++v) p.push_back(img.at<float>(v, u));
  return p;
}
std::vector<double> Row(const cv::Mat& img, int v, int u0, int u1) {
  std::vector<double> p;
  const float* row = img.ptr<float>(v);
  for (int u = u0; u < u1; ++u) p.push_back(row[u]);
  return p;
}

}  // namespace

MarkerReading MeasureMarker(const cv::Mat& input, const CameraModel& cam, const MarkerDescription& marker,
                            const std::string& source) {
  if (input.empty()) throw InputError(source, "empty image (no pixels; unreadable or not an image file)");
  if (input.cols != cam.width_px || input.rows != cam.height_px)
    throw InputError(source, 0, "image size",
                     fmt::format("image is {}×{} px but the camera file is for {}×{} px", input.cols, input.rows,
                                 cam.width_px, cam.height_px));
  cv::Mat gray = input;
  if (gray.channels() == 3) cv::cvtColor(input, gray, cv::COLOR_BGR2GRAY);
  else if (gray.channels() == 4) cv::cvtColor(input, gray, cv::COLOR_BGRA2GRAY);
  cv::Mat img;
  if (gray.depth() == CV_16U) gray.convertTo(img, CV_32F, 255.0 / 65535.0);
  else gray.convertTo(img, CV_32F);

  MarkerReading out;
  auto fail = [&](ReadingStatus s, std::string why) {
    out.status = s;
    out.reason = std::move(why);
    return out;
  };
  const int W = img.cols, H = img.rows;
  const double px_per_mm = cam.fx / marker.distance_mm;
  const double ink_px = std::max(1.0, marker.ink_width_mm * px_per_mm);
  const double spacing_px = marker.circle_spacing_mm * cam.fy / marker.distance_mm;

  // 1. Spindle band: the bright run of the column-mean profile over the middle rows.
  std::vector<double> colmean(W, 0.0);
  {
    cv::Mat mid = img.rowRange(H / 5, H - H / 5);
    cv::Mat m;
    cv::reduce(mid, m, 0, cv::REDUCE_AVG, CV_64F);
    for (int u = 0; u < W; ++u) colmean[u] = m.at<double>(0, u);
  }
  std::vector<double> sorted = colmean;
  std::sort(sorted.begin(), sorted.end());
  const double dark = sorted[W / 20], bright = sorted[W - 1 - W / 10];
  if (bright - dark < 20) return fail(ReadingStatus::kNoMarker, "no spindle: the image has no bright band (contrast < 20 grey levels)");
  const double level = 0.5 * (dark + bright);
  // The spindle is the widest bright run (a reference scale is a narrow one beside it).
  std::vector<int> above(W);
  for (int u = 0; u < W; ++u) above[u] = colmean[u] >= level ? 1 : 0;
  // Merge runs split by the dark axial lines (gaps narrower than a few ink widths).
  std::vector<Run> bright_runs;
  for (const auto& r : Runs(above, 1)) {
    if (!bright_runs.empty() && r.begin - bright_runs.back().end < 4 * ink_px + 6) bright_runs.back().end = r.end;
    else bright_runs.push_back(r);
  }
  Run spindle_run{0, 0};
  for (const auto& r : bright_runs)
    if (r.end - r.begin > spindle_run.end - spindle_run.begin) spindle_run = r;
  const int left = spindle_run.begin, right = spindle_run.end - 1;
  if (right - left < 20) return fail(ReadingStatus::kNoMarker, "no spindle band found");
  if (left <= 2 || right >= W - 3)
    return fail(ReadingStatus::kOutOfFrame, std::string("the spindle's outline runs out of the image at the ") +
                                                (left <= 2 ? "left" : "right") + " edge: move or zoom the camera out");
  const int band = right - left;

  // 2. Ink mask: darkness below the local background (grey closing), Otsu threshold inside the band.
  cv::Mat background, darkness, mask8;
  const int k = 2 * static_cast<int>(std::ceil(1.5 * ink_px + 3)) + 1;
  cv::morphologyEx(img, background, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
  cv::subtract(background, img, darkness);
  cv::Mat d8;
  darkness.convertTo(d8, CV_8U);
  cv::Mat inner = cv::Mat::zeros(img.size(), CV_8U);
  const int margin = std::max(3, band / 30);
  inner(cv::Rect(left + margin, 0, band - 2 * margin, H)).setTo(255);
  const double otsu = cv::threshold(d8(cv::Rect(left + margin, 0, band - 2 * margin, H)), mask8, 0, 255,
                                    cv::THRESH_BINARY | cv::THRESH_OTSU);
  cv::threshold(d8, mask8, std::max(otsu, 10.0), 255, cv::THRESH_BINARY);
  cv::bitwise_and(mask8, inner, mask8);

  // Rings: horizontal structures.
  cv::Mat horiz;
  cv::morphologyEx(mask8, horiz, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(std::max(5, band / 12), 1)));
  std::vector<int> row_count(H, 0);
  for (int v = 0; v < H; ++v) row_count[v] = cv::countNonZero(horiz.row(v));
  auto ring_runs = Runs(row_count, std::max(3, band / 6));
  // The pair of runs whose spacing is nearest the expected one (±30 %).
  int best_a = -1, best_b = -1;
  double best = 0.3;
  for (std::size_t a = 0; a < ring_runs.size(); ++a)
    for (std::size_t b = a + 1; b < ring_runs.size(); ++b) {
      const double rel = std::abs((ring_runs[b].centre() - ring_runs[a].centre()) / spacing_px - 1);
      if (rel < best) best = rel, best_a = static_cast<int>(a), best_b = static_cast<int>(b);
    }
  if (best_a < 0) {
    // Axial ink reaching the top or bottom border: the marker continues outside the frame.
    cv::Mat vertical_all;
    cv::morphologyEx(mask8, vertical_all, cv::MORPH_OPEN,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(1, std::max(5, static_cast<int>(spacing_px / 4)))));
    const int border = std::max(2, static_cast<int>(ink_px));
    if (cv::countNonZero(vertical_all.rowRange(0, border)) > 0 || cv::countNonZero(vertical_all.rowRange(H - border, H)) > 0)
      return fail(ReadingStatus::kOutOfFrame, "the marker's lines run out of the image (top or bottom): the marker is partly out of frame");
    return fail(ReadingStatus::kNoMarker, fmt::format("no pair of rings {:.0f} px apart found ({} ring-like rows)",
                                                      spacing_px, ring_runs.size()));
  }
  const Run ring_run[2] = {ring_runs[best_a], ring_runs[best_b]};
  const int reach = static_cast<int>(std::ceil(1.5 * ink_px + 4));
  for (const auto& r : ring_run)
    if (r.begin - reach < 0 || r.end + reach > H)
      return fail(ReadingStatus::kOutOfFrame, "a ring touches the image border: the marker is partly out of frame");

  // Lines: vertical structures between the rings.
  cv::Mat vert;
  const int between0 = ring_run[0].end + reach, between1 = ring_run[1].begin - reach;
  if (between1 - between0 < 5) return fail(ReadingStatus::kNoMarker, "rings too close together");
  cv::morphologyEx(mask8, vert, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(1, std::max(5, (between1 - between0) / 8))));
  std::vector<int> col_count(W, 0);
  for (int u = 0; u < W; ++u) col_count[u] = cv::countNonZero(vert.col(u).rowRange(between0, between1));
  auto line_runs = Runs(col_count, std::max(3, (between1 - between0) / 4));

  // 3. Sub-pixel strokes.
  const double min_step = 3.0;  // grey levels per pixel
  std::vector<double> edge_d2;  // second differences of single edges along each ring and line
  std::vector<std::vector<cv::Point2d>> line_px;
  for (const auto& lr : line_runs) {
    std::vector<cv::Point2d> pts;
    std::vector<std::pair<int, double>> le, re;
    const int u0 = std::max(0, static_cast<int>(lr.centre()) - reach - 10);
    const int u1 = std::min(W, static_cast<int>(lr.centre()) + reach + 11);
    for (int v = between0; v < between1; ++v) {
      auto s = FindStroke(Row(img, v, u0, u1), lr.centre() - u0, ink_px, min_step);
      if (!s) continue;
      pts.emplace_back(u0 + s->centre, v);
      le.emplace_back(v, s->left_edge), re.emplace_back(v, s->right_edge);
    }
    if (static_cast<int>(pts.size()) >= std::max(5, (between1 - between0) / 4)) {
      line_px.push_back(std::move(pts));
      AddSecondDifferences(le, edge_d2);
      AddSecondDifferences(re, edge_d2);
    }
  }
  std::vector<cv::Point2d> ring_px[2];
  for (int k2 = 0; k2 < 2; ++k2) {
    std::vector<std::pair<int, double>> le, re;
    const int v0 = std::max(0, static_cast<int>(ring_run[k2].centre()) - reach - 10);
    const int v1 = std::min(H, static_cast<int>(ring_run[k2].centre()) + reach + 11);
    for (int u = left + margin; u < right - margin; ++u) {
      bool near_line = false;
      for (const auto& lr : line_runs) near_line |= std::abs(u - lr.centre()) < reach + 2;
      if (near_line) continue;
      auto s = FindStroke(Column(img, u, v0, v1), ring_run[k2].centre() - v0, ink_px, min_step);
      if (!s) continue;
      ring_px[k2].emplace_back(u, v0 + s->centre);
      le.emplace_back(u, s->left_edge), re.emplace_back(u, s->right_edge);
    }
    AddSecondDifferences(le, edge_d2);
    AddSecondDifferences(re, edge_d2);
    if (static_cast<int>(ring_px[k2].size()) < std::max(8, band / 8))
      return fail(ReadingStatus::kNoMarker, fmt::format("ring {} has only {} measurable points", k2 + 1, ring_px[k2].size()));
  }
  out.ring_pixels[0] = ring_px[0];
  out.ring_pixels[1] = ring_px[1];
  out.line_pixels = line_px;
  out.edge_rms_px = RmsOfInliers(edge_d2);

  // Limb points per row (outside the marker), for the axis direction: the
  // sub-pixel peak of the background→spindle gradient near each band edge.
  std::vector<cv::Point2d> limb_px[2];
  auto add_limb_points = [&](int v) {
    for (int side = 0; side < 2; ++side) {
      const int c = side == 0 ? left : right;
      const int u0 = std::max(0, c - 8), u1 = std::min(W, c + 9);
      const auto p = Row(img, v, u0, u1);
      std::vector<double> g(p.size() - 1);
      for (std::size_t i = 0; i + 1 < p.size(); ++i) g[i] = (side == 0 ? 1 : -1) * (p[i + 1] - p[i]);
      const int peak = static_cast<int>(std::max_element(g.begin(), g.end()) - g.begin());
      if (g[peak] < min_step || peak == 0 || peak + 1 >= static_cast<int>(g.size())) continue;
      limb_px[side].emplace_back(u0 + PeakPosition(g, peak) + 0.5, v);
    }
  };
  for (int v = 0; v < H; v += 2)
    if (v <= ring_run[0].begin - reach || v >= ring_run[1].end + reach) add_limb_points(v);
  if (limb_px[0].size() < 5 || limb_px[1].size() < 5)  // the marker fills the height: rows between the rings
    for (int v = between0; v < between1; v += 2) add_limb_points(v);
  if (limb_px[0].size() < 5 || limb_px[1].size() < 5)
    return fail(ReadingStatus::kNoMarker, "the spindle's outline (limbs) could not be measured");

  // 4. Undistort; roll from the lines (parallel to the axis).
  auto normalised = [&](const std::vector<cv::Point2d>& p) { return UndistortToNormalised(cam, p); };
  std::vector<std::vector<cv::Point2d>> line_n;
  for (const auto& l : line_px) line_n.push_back(normalised(l));
  std::vector<cv::Point2d> ring_n[2] = {normalised(ring_px[0]), normalised(ring_px[1])};
  std::vector<cv::Point2d> limb_n[2] = {normalised(limb_px[0]), normalised(limb_px[1])};
  double roll = 0;
  {
    std::vector<double> slopes;
    auto slope = [&](const std::vector<cv::Point2d>& pts) {
      cv::Vec4f fit;
      std::vector<cv::Point2f> f(pts.begin(), pts.end());
      cv::fitLine(f, fit, cv::DIST_HUBER, 0, 1e-7, 1e-7);
      if (std::abs(fit[1]) > 1e-6) slopes.push_back(fit[0] / fit[1]);
    };
    for (const auto& l : line_n) slope(l);
    slope(limb_n[0]);
    slope(limb_n[1]);
    if (!slopes.empty()) roll = std::atan(Median(slopes));
  }
  out.roll_deg = roll * 180 / kPi;
  const double cr = std::cos(roll), sr = std::sin(roll);
  auto rotate = [&](std::vector<cv::Point2d>& pts) {
    for (auto& p : pts) p = {cr * p.x - sr * p.y, sr * p.x + cr * p.y};
  };
  for (auto& l : line_n) rotate(l);
  rotate(ring_n[0]);
  rotate(ring_n[1]);
  rotate(limb_n[0]);
  rotate(limb_n[1]);

  // 5. Axis direction and r from the limbs.
  auto mean_x = [](const std::vector<cv::Point2d>& pts) {
    std::vector<double> x;
    for (const auto& p : pts) x.push_back(p.x);
    return RobustMean(x);
  };
  const double gl = std::atan(mean_x(limb_n[0]).mean), gr = std::atan(mean_x(limb_n[1]).mean);
  const double beta0 = 0.5 * (gl + gr);
  out.radius_ratio_limb = std::sin(0.5 * (gr - gl));
  out.limb_u_px[0] = left;
  out.limb_u_px[1] = right;

  // Lines: position, then (r, ψ) from two or more adjacent lines.
  struct LineFix {
    double gamma, se_px, x_px;
  };
  std::vector<LineFix> lines;
  std::vector<double> line_residuals;
  for (const auto& l : line_n) {
    const MeanSe m = mean_x(l);
    lines.push_back({std::atan(m.mean) - beta0, m.se * cam.fx, m.mean * cam.fx});
    for (const auto& p : l) line_residuals.push_back((p.x - m.mean) * cam.fx);
  }
  std::sort(lines.begin(), lines.end(), [](const LineFix& a, const LineFix& b) { return a.gamma < b.gamma; });
  if (lines.size() < 2)
    return fail(ReadingStatus::kTooFewLines, fmt::format("{} axial line(s) measurable, two are needed for CB2", lines.size()));
  for (const auto& l : lines) {
    out.line_x_px.push_back(l.x_px);
    out.line_x_se_px.push_back(l.se_px);
  }
  const double step = 2 * kPi / marker.line_count;
  double r = out.radius_ratio_limb;
  auto psi_of = [&](double gamma, double rr) {  // ψ of the point seen at ray angle γ (front side)
    const double t = std::tan(gamma);
    const double s = std::clamp(t / (rr * std::sqrt(1 + t * t)), -1.0, 1.0);
    return std::asin(s) - std::atan(t);
  };
  double psi0 = psi_of(lines[0].gamma, r);
  // Adjacent measured lines are one step apart unless a line in between was lost.
  std::vector<int> index(lines.size(), 0);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const double gap = psi_of(lines[i].gamma, r) - psi_of(lines[i - 1].gamma, r);
    index[i] = index[i - 1] + std::max(1, static_cast<int>(std::lround(gap / step)));
  }
  for (int it = 0; it < 30; ++it) {  // Gauss–Newton on (r, ψ0)
    double jtj[2][2] = {{0, 0}, {0, 0}}, jtr[2] = {0, 0};
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const double psi = psi0 + index[i] * step;
      const double res = lines[i].gamma - RayAngle(r, psi);
      const double h = 1e-7;
      const double dr = (RayAngle(r + h, psi) - RayAngle(r - h, psi)) / (2 * h);
      const double dp = (RayAngle(r, psi + h) - RayAngle(r, psi - h)) / (2 * h);
      jtj[0][0] += dr * dr, jtj[0][1] += dr * dp, jtj[1][1] += dp * dp;
      jtr[0] += dr * res, jtr[1] += dp * res;
    }
    const double det = jtj[0][0] * jtj[1][1] - jtj[0][1] * jtj[0][1];
    if (std::abs(det) < 1e-30) break;
    const double d_r = (jtj[1][1] * jtr[0] - jtj[0][1] * jtr[1]) / det;
    const double d_p = (jtj[0][0] * jtr[1] - jtj[0][1] * jtr[0]) / det;
    r += d_r, psi0 += d_p;
    if (std::abs(d_r) < 1e-15 && std::abs(d_p) < 1e-13) break;
  }
  if (!(r > 0 && r < 0.9))
    return fail(ReadingStatus::kNotCredible, "the lines do not fit a cylinder (r out of range)");
  out.radius_ratio = r;
  out.angle_deg = psi0 * 180 / kPi;

  // 6. Rings mapped back onto the cylinder: height = y·z on the surface (units of D).
  // The cylinder's r for this mapping is the marker's own r0 = R/D scaled by K1
  // (fixed point): the strain is isotropic, and this keeps K1 independent of the
  // line measurement, so K1 and K2 stay two independent readings for the test.
  double ring_h[2];
  std::vector<double> ring_residuals;
  const double r0 = 0.5 * marker.diameter_mm / marker.distance_mm;
  double k1_raw = 1.0;
  for (int pass = 0; pass < 3; ++pass) {
    const double rr = r0 * k1_raw;
    ring_residuals.clear();
    out.ring_points = 0;
    for (int k2 = 0; k2 < 2; ++k2) {
      std::vector<double> heights;
      for (const auto& p : ring_n[k2]) {
        const double gamma = std::atan(p.x) - beta0;
        const double psi = psi_of(gamma, rr);
        const double z = std::cos(beta0) * (1 - rr * std::cos(psi)) - std::sin(beta0) * rr * std::sin(psi);
        heights.push_back(p.y * z);
      }
      const MeanSe m = RobustMean(heights);
      ring_h[k2] = m.mean;
      const double z_front = 1 - rr;  // px per unit height at the front of the ring
      out.ring_height_px[k2] = m.mean / z_front * cam.fy;
      out.ring_height_se_px[k2] = m.se / z_front * cam.fy;
      for (double h : heights) ring_residuals.push_back((h - m.mean) / z_front * cam.fy);
      out.ring_points += m.n;
    }
    k1_raw = (ring_h[1] - ring_h[0]) * marker.distance_mm / marker.Cbb1Mm();
  }
  out.line_points = static_cast<int>(line_residuals.size());
  {
    std::vector<double> all = ring_residuals;
    all.insert(all.end(), line_residuals.begin(), line_residuals.end());
    out.stroke_rms_px = RmsOfInliers(all);
  }
  // Reference scale: the two bars on the strip beside the spindle (plane of the axis).
  if (marker.has_scale()) {
    Run strip{0, 0};
    const double expect_u = cam.cx + cam.fx * marker.scale_x_mm / marker.distance_mm;
    for (const auto& r : bright_runs)
      if (r.begin > right || r.end <= left)
        if (strip.end == 0 || std::abs(r.centre() - expect_u) < std::abs(strip.centre() - expect_u)) strip = r;
    const double strip_px = marker.scale_width_mm * cam.fx / marker.distance_mm;
    if (strip.end - strip.begin < 4 || std::abs(strip.centre() - expect_u) > strip_px + 10)
      return fail(ReadingStatus::kNoMarker,
                  fmt::format("the reference scale is not where [scale] x_mm puts it (around column {:.0f})", expect_u));
    const double scale_spacing_px = marker.scale_spacing_mm * cam.fy / marker.distance_mm;
    std::vector<cv::Point2d> bar_n[2];  // undistorted, roll removed
    for (int u = strip.begin + 2; u < strip.end - 2; ++u) {
      for (int b = 0; b < 2; ++b) {
        const double guess_v = 0.5 * (ring_run[0].centre() + ring_run[1].centre()) + (b == 0 ? -0.5 : 0.5) * scale_spacing_px;
        const int v0 = std::max(0, static_cast<int>(guess_v - 0.2 * scale_spacing_px));
        const int v1 = std::min(H, static_cast<int>(guess_v + 0.2 * scale_spacing_px));
        if (v1 - v0 < 8) continue;
        const auto p = Column(img, u, v0, v1);
        const int darkest = static_cast<int>(std::min_element(p.begin(), p.end()) - p.begin());
        auto st = FindStroke(p, darkest, ink_px, min_step);
        if (!st) continue;
        const auto n = UndistortToNormalised(cam, {cv::Point2d(u, v0 + st->centre)}).front();
        bar_n[b].emplace_back(cr * n.x - sr * n.y, sr * n.x + cr * n.y);
      }
    }
    if (bar_n[0].size() < 5 || bar_n[1].size() < 5)
      return fail(ReadingStatus::kNoMarker, "the reference scale's bars could not be measured");
    // Each (slanted) bar: a straight line y = a + b·x fitted to its points; heights compared at one x.
    double x_mid = 0;
    for (const auto& bar : bar_n)
      for (const auto& p : bar) x_mid += p.x;
    x_mid /= static_cast<double>(bar_n[0].size() + bar_n[1].size());
    double bar_y[2];
    for (int b = 0; b < 2; ++b) {
      cv::Vec4f fit;
      std::vector<cv::Point2f> f;
      for (const auto& p : bar_n[b]) f.emplace_back(static_cast<float>(p.x - x_mid), static_cast<float>(p.y));
      cv::fitLine(f, fit, cv::DIST_HUBER, 0, 1e-9, 1e-9);
      bar_y[b] = fit[3] - fit[2] * fit[1] / fit[0];  // y at x = x_mid
    }
    const double plane_depth = std::cos(beta0);  // the axis plane, in units of D
    out.scale_raw = (bar_y[1] - bar_y[0]) * plane_depth * marker.distance_mm /
                    marker.scale_spacing_mm;
  }

  out.cb1_mm = (ring_h[1] - ring_h[0]) * marker.distance_mm;
  out.cb2_mm = 2 * r * std::sin(kPi / marker.line_count) * marker.distance_mm;
  ApplyScale(out, out.scale_raw, marker);
  return out;
}

void ApplyScale(MarkerReading& out, double scale, const MarkerDescription& marker) {
  if (!(out.status == ReadingStatus::kCredible || out.status == ReadingStatus::kNotCredible || out.cb1_mm > 0)) return;
  out.k1 = out.cb1_mm / marker.Cbb1Mm() / scale / marker.reference_k1;
  out.k2 = out.cb2_mm / marker.Cbb2Mm() / scale / marker.reference_k2;
  out.czs_mm = marker.spindle_length_mm * out.k1;
  out.growth_um = (out.czs_mm - marker.spindle_length_mm) * 1000.0;
  const double disagreement = std::abs(out.k1 / out.k2 - 1);
  if (disagreement <= marker.epsilon) {
    out.status = ReadingStatus::kCredible;
    out.reason.clear();
  } else {
    out.status = ReadingStatus::kNotCredible;
    out.reason = fmt::format("|K1/K2 − 1| = {:.3g} % > ε = {:.3g} %", 100 * disagreement, 100 * marker.epsilon);
  }
}

ScaleAverager::ScaleAverager(int frames) : frames_(frames) {
  if (frames_ < 1) throw std::invalid_argument("the reference scale average needs ≥ 1 frame");
}

void ScaleAverager::Apply(MarkerReading& reading, const MarkerDescription& marker) {
  if (!marker.has_scale() || !reading.measured()) return;
  recent_.push_back(reading.scale_raw);
  if (static_cast<int>(recent_.size()) > frames_) recent_.pop_front();
  double sum = 0;
  for (double v : recent_) sum += v;
  ApplyScale(reading, sum / static_cast<double>(recent_.size()), marker);
}

cv::Mat DrawReading(const cv::Mat& gray, const MarkerReading& reading) {
  cv::Mat g8, colour;
  if (gray.depth() != CV_8U) gray.convertTo(g8, CV_8U);
  else g8 = gray;
  if (g8.channels() == 1) cv::cvtColor(g8, colour, cv::COLOR_GRAY2BGR);
  else colour = g8.clone();
  const cv::Scalar green(60, 220, 60), blue(255, 140, 0), red(40, 40, 255);
  for (const auto& ring : reading.ring_pixels)
    for (const auto& p : ring) cv::circle(colour, cv::Point(cvRound(p.x), cvRound(p.y)), 0, green, 1);
  for (const auto& line : reading.line_pixels)
    if (!line.empty()) cv::line(colour, line.front(), line.back(), blue, 1, cv::LINE_AA);
  for (double u : reading.limb_u_px)
    if (u > 0) cv::line(colour, cv::Point(cvRound(u), 0), cv::Point(cvRound(u), colour.rows - 1), red, 1);
  const std::string text = reading.measured()
                               ? fmt::format("K1 {:.6f} K2 {:.6f} dz {:+.1f} um {}", reading.k1, reading.k2,
                                             reading.growth_um, ReadingStatusName(reading.status))
                               : std::string(ReadingStatusName(reading.status));
  cv::putText(colour, text, cv::Point(6, 16), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              reading.credible() ? green : red, 1, cv::LINE_AA);
  return colour;
}

}  // namespace trueaxis::vision
