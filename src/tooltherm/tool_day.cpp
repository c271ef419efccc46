#include "trueaxis/tooltherm/tool_day.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::tooltherm {
namespace {

constexpr double kToolChangeS = 8.0;

double CuttingSpeedMPerMin(const std::string& material, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  if (material == "hss") return 25 + 35 * u(rng);
  return 120 + 180 * u(rng);  // carbide and others
}

}  // namespace

std::vector<ToolOperation> DrawToolDayProgram(const ToolTable& table, double hours, std::uint64_t seed,
                                              ToolDayProgramKind kind) {
  const bool blocks = kind == ToolDayProgramKind::kBlocks;
  if (table.tools.empty()) throw std::invalid_argument("tool day: the tool table is empty");
  if (!(hours > 0 && hours <= 72)) throw std::invalid_argument("tool day: hours must be in (0, 72]");
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<ToolOperation> ops;
  const double end_s = hours * 3600;
  double t = 0;
  int last = -1;
  // Start soaked and idle for a few minutes, as a shift does.
  const double idle0 = 60 + 240 * u(rng);
  ops.push_back({0, idle0, table.tools.front().number, 0, 0, false, 60, 15});
  t = idle0;
  while (t < end_s) {
    std::size_t k = static_cast<std::size_t>(u(rng) * static_cast<double>(table.tools.size())) % table.tools.size();
    if (table.tools.size() > 1 && static_cast<int>(k) == last) k = (k + 1) % table.tools.size();
    last = static_cast<int>(k);
    const ToolDescription& tool = table.tools[k];
    // The change itself: spindle stopped, the new tool in it (the offset ramps meanwhile).
    ops.push_back({t, std::min(end_s, t + kToolChangeS), tool.number, 0, 0, false, 60, 15});
    t += kToolChangeS;
    ToolOperation op;
    op.tool = tool.number;
    op.start_s = t;
    op.end_s = std::min(end_s, t + 60 * (blocks ? 40 + 50 * u(rng) : 4 + 26 * u(rng)));
    op.rpm = std::clamp(CuttingSpeedMPerMin(tool.material, rng) * 1000 / (std::numbers::pi * tool.diameter_mm), 500.0, 20000.0);
    op.power_w = (0.3 + 0.7 * u(rng)) * 150 * tool.diameter_mm;
    op.coolant = u(rng) < 0.5;
    op.cut_s = blocks ? 300 + 300 * u(rng) : 20 + 160 * u(rng);
    op.air_s = 5 + 35 * u(rng);
    ops.push_back(op);
    t = op.end_s;
    if (t < end_s && (blocks || u(rng) < 0.35)) {  // a stop: the tool stays in the spindle and cools
      ToolOperation stop = op;
      stop.start_s = t;
      stop.end_s = std::min(end_s, t + 60 * (blocks ? 30 + 60 * u(rng) : 3 + 37 * u(rng)));
      stop.rpm = 0;
      stop.power_w = 0;
      stop.coolant = false;
      ops.push_back(stop);
      t = stop.end_s;
    }
  }
  return ops;
}

ToolTable RandomToolTable(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed * 0xD1B54A32D192ED03ull + 7);
  std::uniform_real_distribution<double> u(0, 1);
  ToolTable table;
  for (int i = 0; i < count; ++i) {
    ToolDescription t;
    t.number = i + 1;
    t.diameter_mm = std::round(4 + 21 * u(rng));
    t.length_mm = std::round(std::max(2.5 * t.diameter_mm, 30.0) + 60 * u(rng));
    t.material = u(rng) < 0.7 ? "carbide" : "hss";
    t.holder_length_mm = std::round(40 + 60 * u(rng));
    t.holder_diameter_mm = std::round(std::max(t.diameter_mm + 12, 25 + 38 * u(rng)));
    t.holder_material = "steel";
    t.cutting_heat_share = 0.002 + 0.004 * u(rng);
    t.name = fmt::format("random D{:.0f} L{:.0f} {}", t.diameter_mm, t.length_mm, t.material);
    t.zones = DefaultToolZones(t);
    table.tools.push_back(t);
  }
  return table;
}

ToolDayRecording RunToolDay(const ToolTable& table, const ToolDayOptions& o) {
  if (!(o.sample_s > 0 && o.step_s > 0 && o.step_s <= o.sample_s))
    throw std::invalid_argument("tool day: need 0 < step_s ≤ sample_s");
  ToolDayRecording day;
  day.program = DrawToolDayProgram(table, o.hours, o.seed, o.program);
  std::vector<sim::SpindleSpeedStep> steps;
  for (const auto& op : day.program) steps.push_back({op.start_s, op.rpm});
  sim::VirtualSpindle spindle(o.spindle, sim::SpindleSpeedProgram(steps), o.ambient_c);
  std::map<int, VirtualTool> tools;
  std::map<int, std::vector<PixelZone>> zones;
  for (const auto& t : table.tools) {
    tools.emplace(t.number, VirtualTool(t, table.standard_temp_c, o.ambient_c));
    zones.emplace(t.number, ImageZonesFor(t, o.camera));
  }
  std::mt19937_64 rng(o.seed * 0xA24BAED4963EE407ull + 3);
  const double end_s = o.hours * 3600;
  std::size_t op_index = 0;
  int mounted_before = 0;
  double next_sample_s = 0;
  for (double t = 0; t <= end_s + 1e-9;) {
    while (op_index + 1 < day.program.size() && day.program[op_index + 1].start_s <= t) ++op_index;
    const ToolOperation& op = day.program[op_index];
    const double ambient = o.ambient_c + o.ambient_swing_c * std::sin(2 * std::numbers::pi * (t / 86400.0 + 0.2));
    spindle.SetAmbientC(ambient);
    const bool turning = op.rpm > 0 && spindle.Rpm() > 0.9 * op.rpm;
    const bool cutting = turning && std::fmod(t - op.start_s, op.cut_s + op.air_s) < op.cut_s;
    if (t + 1e-9 >= next_sample_s) {
      VirtualTool& vt = tools.at(op.tool);
      const CameraScene scene{op.coolant && turning, o.coolant_c, ambient};
      std::vector<double> tr;
      if (o.sensor == TvSensor::kCamera) {
        const ZoneFile zf{"virtual camera", zones.at(op.tool)};
        tr = ZoneMeansC(RenderThermalImage(vt, scene, o.camera, rng), zf, "virtual camera");
      } else {
        tr = SpotZoneMeansC(ReadPyrometers(vt, scene, o.camera, rng), vt.tool().zones.size());
      }
      ToolDaySample s;
      s.time_s = t;
      s.tool = op.tool;
      s.tv_c = WeightedMeanTemperatureC(tr, ZoneAreas(zones.at(op.tool)));
      s.zone_c = tr;
      s.true_error_um = vt.TipErrorUm();
      s.restart = op.tool != mounted_before;
      s.rpm = spindle.Rpm();
      s.cutting = cutting;
      s.coolant = scene.coolant;
      day.samples.push_back(s);
      mounted_before = op.tool;
      next_sample_s += o.sample_s;
    }
    const double dt = std::min(o.step_s, end_s + o.step_s - t);
    spindle.Advance(dt);
    for (auto& [number, vt] : tools) {
      ToolConditions c;
      c.mounted = number == op.tool;
      c.nose_c = spindle.FrontShaftC();
      c.rpm = spindle.Rpm();
      c.cutting_power_w = c.mounted && cutting ? op.power_w : 0;
      c.coolant = c.mounted && op.coolant && turning;
      c.coolant_c = o.coolant_c;
      c.ambient_c = ambient;
      vt.Advance(dt, c);
    }
    t += dt;
  }
  return day;
}

std::vector<ToolRecord> ToolRecordsOf(const ToolDayRecording& day, int tool) {
  std::vector<ToolRecord> rows;
  bool was_mounted = false;
  for (const auto& s : day.samples) {
    const bool mounted = s.tool == tool;
    if (mounted) rows.push_back({s.time_s, s.tv_c, s.true_error_um, !was_mounted || s.restart, s.zone_c});
    was_mounted = mounted;
  }
  return rows;
}

}  // namespace trueaxis::tooltherm
