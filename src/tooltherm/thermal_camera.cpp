#include "trueaxis/tooltherm/thermal_camera.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::tooltherm {
namespace {

double RadiometricC(double surface_c, const CameraScene& s, const ThermalCameraOptions& o) {
  return s.ambient_c + (o.emissivity_true / o.emissivity_set) * (surface_c - s.ambient_c);
}

double RowZ(int r, const ThermalCameraOptions& o) { return (r + 0.5) * o.mm_per_px - o.margin_mm; }

}  // namespace

cv::Size ThermalImageSize(const ToolDescription& t, const ThermalCameraOptions& o) {
  const int rows = static_cast<int>(std::ceil((t.GaugeLengthMm() + 2 * o.margin_mm) / o.mm_per_px));
  const int cols = static_cast<int>(std::ceil((t.holder_diameter_mm + 2 * o.margin_mm) / o.mm_per_px));
  return {cols, rows};
}

std::vector<PixelZone> ImageZonesFor(const ToolDescription& t, const ThermalCameraOptions& o) {
  const cv::Size size = ThermalImageSize(t, o);
  std::vector<PixelZone> out;
  for (const ToolZone& z : t.zones) {
    PixelZone p;
    p.name = z.name;
    p.area_mm2 = z.area_mm2;
    const double mid = 0.5 * (z.from_mm + z.to_mm);
    const double d = mid < t.length_mm ? t.diameter_mm : t.holder_diameter_mm;
    // Pixels whose centre lies inside the band (at least the one holding its middle).
    p.row_from = static_cast<int>(std::ceil((z.from_mm + o.margin_mm) / o.mm_per_px - 0.5));
    p.row_to = static_cast<int>(std::floor((z.to_mm + o.margin_mm) / o.mm_per_px - 0.5));
    if (p.row_to < p.row_from) p.row_from = p.row_to = static_cast<int>((mid + o.margin_mm) / o.mm_per_px);
    const double half = 0.3 * d;
    const double centre_px = 0.5 * size.width;
    p.col_from = static_cast<int>(std::ceil(centre_px - half / o.mm_per_px - 0.5));
    p.col_to = static_cast<int>(std::floor(centre_px + half / o.mm_per_px - 0.5));
    if (p.col_to < p.col_from) p.col_from = p.col_to = static_cast<int>(centre_px);
    p.row_from = std::clamp(p.row_from, 0, size.height - 1);
    p.row_to = std::clamp(p.row_to, 0, size.height - 1);
    p.col_from = std::clamp(p.col_from, 0, size.width - 1);
    p.col_to = std::clamp(p.col_to, 0, size.width - 1);
    out.push_back(p);
  }
  return out;
}

cv::Mat RenderThermalImage(const VirtualTool& vt, const CameraScene& scene, const ThermalCameraOptions& o,
                           std::mt19937_64& rng) {
  const ToolDescription& t = vt.tool();
  const cv::Size size = ThermalImageSize(t, o);
  cv::Mat img(size, CV_32F);
  std::normal_distribution<double> noise(0.0, o.noise_c);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double half_w = 0.5 * size.width * o.mm_per_px;
  // A reflection this frame: a disc of 2–4 px radius somewhere on the part.
  const bool reflect = u(rng) < o.reflection_probability;
  const double refl_r = u(rng) * (size.height - 1), refl_c = 0.5 * size.width + (u(rng) - 0.5) * 0.5 * t.diameter_mm / o.mm_per_px;
  const double refl_radius = 2 + 2 * u(rng);
  for (int r = 0; r < size.height; ++r) {
    const double z = RowZ(r, o);
    const bool on_part = z >= 0 && z <= t.GaugeLengthMm();
    const double radius = z < t.length_mm ? 0.5 * t.diameter_mm : 0.5 * t.holder_diameter_mm;
    const double surface = on_part ? RadiometricC(vt.SurfaceC(z), scene, o) : scene.ambient_c;
    const bool wetted = on_part && scene.coolant && z < t.length_mm + 0.5 * t.holder_length_mm;
    for (int c = 0; c < size.width; ++c) {
      const double x = (c + 0.5) * o.mm_per_px - half_w;
      double v = scene.ambient_c;
      if (on_part && std::abs(x) <= radius) {
        v = surface;
        if (wetted && u(rng) < o.coolant_film_fraction) v = scene.coolant_c;
        if (reflect && std::hypot(r - refl_r, c - refl_c) <= refl_radius) v += o.reflection_c;
      }
      img.at<float>(r, c) = static_cast<float>(v + noise(rng));
    }
  }
  return img;
}

std::vector<SpotReading> ReadPyrometers(const VirtualTool& vt, const CameraScene& scene, const ThermalCameraOptions& o,
                                        std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, o.pyrometer_noise_c);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const ToolDescription& t = vt.tool();
  std::vector<SpotReading> spots;
  const int n = std::max(1, o.pyrometer_spots_per_zone);
  for (std::size_t zi = 0; zi < t.zones.size(); ++zi) {
    const ToolZone& z = t.zones[zi];
    for (int k = 0; k < n; ++k) {
      const double pos = z.from_mm + (k + 0.5) / n * (z.to_mm - z.from_mm);
      double v = RadiometricC(vt.SurfaceC(pos), scene, o);
      if (scene.coolant && pos < t.length_mm + 0.5 * t.holder_length_mm && u(rng) < o.coolant_film_fraction)
        v = scene.coolant_c;
      spots.push_back({static_cast<int>(zi), v + noise(rng)});
    }
  }
  return spots;
}

}  // namespace trueaxis::tooltherm
