#include "trueaxis/tooltherm/virtual_tool.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace trueaxis::tooltherm {
namespace {

constexpr double kAirStillW = 8.0;          // W/(m²K), at rest
constexpr double kAirRotatingW = 60.0;      // extra at 10000 rpm (∝ rpm^0.8)
constexpr double kCoolantW = 2500.0;        // W/(m²K), flood coolant on the tool
constexpr double kClampW = 4000.0;          // contact conductance of the clamp, W/(m²K)
constexpr double kTaperW = 600.0;           // contact conductance holder ↔ spindle nose

double Area(double d_mm, double l_mm) { return std::numbers::pi * d_mm * l_mm * 1e-6; }
double Section(double d_mm) { return std::numbers::pi * 0.25 * d_mm * d_mm * 1e-6; }

}  // namespace

VirtualTool::VirtualTool(ToolDescription tool, double standard_temp_c, double ambient_c)
    : tool_(std::move(tool)), standard_temp_c_(standard_temp_c) {
  const ToolMaterial& tm = *FindToolMaterial(tool_.material);
  const ToolMaterial& hm = *FindToolMaterial(tool_.holder_material);
  const double l3 = tool_.length_mm / 3.0, h2 = tool_.holder_length_mm / 2.0;
  from_mm_ = {0, l3, 2 * l3, tool_.length_mm, tool_.length_mm + h2};
  to_mm_ = {l3, 2 * l3, tool_.length_mm, tool_.length_mm + h2, tool_.GaugeLengthMm()};
  ambient_ = net_.AddNode("ambient", 0, ambient_c);
  nose_ = net_.AddNode("nose", 0, ambient_c);
  coolant_ = net_.AddNode("coolant", 0, ambient_c);
  const char* names[kSegments] = {"tip", "middle", "shank", "holder_front", "holder_taper"};
  for (int s = 0; s < kSegments; ++s) {
    const bool on_tool = s < 3;
    const double d = on_tool ? tool_.diameter_mm : tool_.holder_diameter_mm;
    const double len = to_mm_[s] - from_mm_[s];
    const ToolMaterial& m = on_tool ? tm : hm;
    seg_[s] = net_.AddNode(names[s], m.heat_capacity_j_per_m3_k * Section(d) * len * 1e-3, ambient_c);
    area_m2_[s] = Area(d, len) + (s == 0 ? Section(d) : 0.0);
    expansion_[s] = m.expansion_per_k;
    air_edge_[s] = net_.AddEdge(seg_[s], ambient_, kAirStillW * area_m2_[s]);
    coolant_edge_[s] = net_.AddEdge(seg_[s], coolant_, 0);
  }
  for (int s = 0; s + 1 < kSegments; ++s) {
    if (s == 2) {  // the clamp: tool shank inside the holder front, over min(3·d, holder length / 2)
      const double grip_mm = std::min(3.0 * tool_.diameter_mm, h2);
      net_.AddEdge(seg_[2], seg_[3], kClampW * Area(tool_.diameter_mm, grip_mm));
      continue;
    }
    const bool on_tool = s < 2;
    const ToolMaterial& m = on_tool ? tm : hm;
    const double d = on_tool ? tool_.diameter_mm : tool_.holder_diameter_mm;
    const double pitch_mm = 0.5 * (to_mm_[s] - from_mm_[s] + to_mm_[s + 1] - from_mm_[s + 1]);
    net_.AddEdge(seg_[s], seg_[s + 1], m.conductivity_w_per_m_k * Section(d) / (pitch_mm * 1e-3));
  }
  taper_w_per_k_ = kTaperW * Area(tool_.holder_diameter_mm * 0.8, h2);
  taper_edge_ = net_.AddEdge(seg_[4], nose_, 0);
}

void VirtualTool::Advance(double dt_s, const ToolConditions& c) {
  net_.SetTemperature(ambient_, c.ambient_c);
  net_.SetTemperature(nose_, c.nose_c);
  net_.SetTemperature(coolant_, c.coolant_c);
  net_.SetConductance(taper_edge_, c.mounted ? taper_w_per_k_ : 0.0);
  const double turning = c.mounted ? std::pow(std::max(c.rpm, 0.0) / 10000.0, 0.8) : 0.0;
  for (int s = 0; s < kSegments; ++s) {
    net_.SetConductance(air_edge_[s], (kAirStillW + kAirRotatingW * turning) * area_m2_[s]);
    // Coolant reaches the stick-out and the holder's front, not the taper.
    net_.SetConductance(coolant_edge_[s], c.mounted && c.coolant && s < 4 ? kCoolantW * area_m2_[s] : 0.0);
    net_.SetHeat(seg_[s], 0);
  }
  if (c.mounted) net_.SetHeat(seg_[0], tool_.cutting_heat_share * std::max(c.cutting_power_w, 0.0));
  net_.Step(dt_s);
}

double VirtualTool::GrowthUm() const {
  double um = 0;
  for (int s = 0; s < kSegments; ++s)
    um += expansion_[s] * (to_mm_[s] - from_mm_[s]) * 1e3 * (net_.Temperature(seg_[s]) - standard_temp_c_);
  return um;
}

double VirtualTool::SurfaceC(double z_mm) const {
  // Piecewise linear between segment centres, flat beyond the end centres.
  std::array<double, kSegments> centre{};
  for (int s = 0; s < kSegments; ++s) centre[s] = 0.5 * (from_mm_[s] + to_mm_[s]);
  if (z_mm <= centre[0]) return SegmentC(0);
  for (int s = 0; s + 1 < kSegments; ++s) {
    // No blending across the tool/holder step: each part keeps its own temperature.
    if (z_mm <= centre[s + 1]) {
      if (s == 2) return z_mm < tool_.length_mm ? SegmentC(2) : SegmentC(3);
      const double w = (z_mm - centre[s]) / (centre[s + 1] - centre[s]);
      return (1 - w) * SegmentC(s) + w * SegmentC(s + 1);
    }
  }
  return SegmentC(kSegments - 1);
}

}  // namespace trueaxis::tooltherm
