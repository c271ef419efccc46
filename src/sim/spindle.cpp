// Virtual motor spindle: heat, RC network, axial growth, marker strain
// (include/trueaxis/sim/spindle.hpp, docs/vision.md).
#include "trueaxis/sim/spindle.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::sim {

bool SpindleDescription::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (!(length_mm > 0 && length_mm < 5000)) return fail("length_mm must be in (0, 5000)");
  if (!(front_length_mm > 0 && front_length_mm <= length_mm)) return fail("front_length_mm must be in (0, length_mm]");
  if (!(diameter_mm > 1 && diameter_mm < 1000)) return fail("diameter_mm must be in (1, 1000)");
  if (!(expansion_per_k > 0 && expansion_per_k < 1e-4)) return fail("expansion_per_k must be in (0, 1e-4)");
  if (!(reference_rpm > 0)) return fail("reference_rpm must be > 0");
  if (!(ramp_rpm_per_s > 0)) return fail("ramp_rpm_per_s must be > 0");
  for (double c : {shaft_front_capacity_j_per_k, shaft_rear_capacity_j_per_k, bearing_capacity_j_per_k,
                   motor_capacity_j_per_k, housing_capacity_j_per_k})
    if (!(c > 0)) return fail("every capacity must be > 0");
  for (double g : {bearing_to_shaft_w_per_k, bearing_to_housing_w_per_k, motor_to_shaft_w_per_k,
                   motor_to_housing_w_per_k, shaft_segments_w_per_k, housing_to_ambient_w_per_k,
                   shaft_to_ambient_w_per_k, shaft_to_ambient_rotating_w_per_k, front_bearing_heat_w,
                   rear_bearing_heat_w, motor_heat_w, motor_idle_heat_w})
    if (!(g >= 0 && std::isfinite(g))) return fail("conductances and heats must be finite and ≥ 0");
  return true;
}

SpindleSpeedProgram::SpindleSpeedProgram(std::vector<SpindleSpeedStep> steps) : steps_(std::move(steps)) {
  for (std::size_t i = 0; i < steps_.size(); ++i) {
    const auto& s = steps_[i];
    if (!(s.start_s >= 0) || !std::isfinite(s.start_s))
      throw std::invalid_argument(fmt::format("speed step {}: start {} s must be ≥ 0", i + 1, s.start_s));
    if (!(s.rpm >= 0 && s.rpm <= 60000))
      throw std::invalid_argument(fmt::format("speed step {}: {} rpm is outside 0…60000", i + 1, s.rpm));
    if (i > 0 && !(s.start_s > steps_[i - 1].start_s))
      throw std::invalid_argument(fmt::format("speed step {}: start {} s is not after the step before", i + 1, s.start_s));
  }
}

SpindleSpeedProgram SpindleSpeedProgram::Parse(const std::string& text) {
  std::vector<SpindleSpeedStep> steps;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto colon = item.find(':');
    SpindleSpeedStep s;
    try {
      if (colon == std::string::npos) throw std::invalid_argument("");
      std::size_t used = 0;
      s.start_s = std::stod(item.substr(0, colon), &used);
      s.rpm = std::stod(item.substr(colon + 1));
    } catch (const std::exception&) {
      throw std::invalid_argument("speed step '" + item + "' is not seconds:rpm");
    }
    steps.push_back(s);
  }
  if (steps.empty()) throw std::invalid_argument("speed program is empty (want e.g. 0:0,1800:9000)");
  return SpindleSpeedProgram(std::move(steps));
}

SpindleSpeedProgram SpindleSpeedProgram::HeatingCoolingDay(double hours) {
  const double h = 3600.0 * hours;
  return SpindleSpeedProgram({{0, 0},
                              {0.04 * h, 10000},   // warm-up at high speed
                              {0.30 * h, 6000},    // machining mix
                              {0.42 * h, 8000},
                              {0.60 * h, 0}});     // stop: cooling
}

double SpindleSpeedProgram::RpmAt(double t_s) const {
  double rpm = 0;
  for (const auto& s : steps_) {
    if (s.start_s > t_s) break;
    rpm = s.rpm;
  }
  return rpm;
}

std::string SpindleSpeedProgram::ToString() const {
  std::string out;
  for (const auto& s : steps_) out += fmt::format("{}{:g}:{:g}", out.empty() ? "" : ",", s.start_s, s.rpm);
  return out;
}

VirtualSpindle::VirtualSpindle(SpindleDescription d, SpindleSpeedProgram program, double ambient_c)
    : d_(std::move(d)), program_(std::move(program)) {
  std::string why;
  if (!d_.IsValid(&why)) throw std::invalid_argument("spindle description: " + why);
  ambient_ = net_.AddNode("ambient", 0, ambient_c);
  housing_ = net_.AddNode("housing", d_.housing_capacity_j_per_k, ambient_c);
  front_bearing_ = net_.AddNode("front_bearing", d_.bearing_capacity_j_per_k, ambient_c);
  rear_bearing_ = net_.AddNode("rear_bearing", d_.bearing_capacity_j_per_k, ambient_c);
  motor_ = net_.AddNode("motor", d_.motor_capacity_j_per_k, ambient_c);
  shaft_front_ = net_.AddNode("shaft_front", d_.shaft_front_capacity_j_per_k, ambient_c);
  shaft_rear_ = net_.AddNode("shaft_rear", d_.shaft_rear_capacity_j_per_k, ambient_c);
  net_.AddEdge(front_bearing_, shaft_front_, d_.bearing_to_shaft_w_per_k);
  net_.AddEdge(front_bearing_, housing_, d_.bearing_to_housing_w_per_k);
  net_.AddEdge(rear_bearing_, shaft_rear_, d_.bearing_to_shaft_w_per_k);
  net_.AddEdge(rear_bearing_, housing_, d_.bearing_to_housing_w_per_k);
  net_.AddEdge(motor_, shaft_rear_, d_.motor_to_shaft_w_per_k);
  net_.AddEdge(motor_, housing_, d_.motor_to_housing_w_per_k);
  net_.AddEdge(shaft_front_, shaft_rear_, d_.shaft_segments_w_per_k);
  net_.AddEdge(housing_, ambient_, d_.housing_to_ambient_w_per_k);
  convection_front_ = net_.AddEdge(shaft_front_, ambient_, d_.shaft_to_ambient_w_per_k);
  convection_rear_ = net_.AddEdge(shaft_rear_, ambient_, 0.5 * d_.shaft_to_ambient_w_per_k);
}

void VirtualSpindle::SetAmbientC(double ambient_c) { net_.SetTemperature(ambient_, ambient_c); }

void VirtualSpindle::Advance(double dt_s) {
  constexpr double kMaxStepS = 1.0;  // speed ramps and heat are resolved to 1 s
  while (dt_s > 1e-12) {
    const double h = std::min(dt_s, kMaxStepS);
    Step(h);
    dt_s -= h;
  }
}

void VirtualSpindle::Step(double h) {
  const double target = hold_ ? 0.0 : program_.RpmAt(t_s_ + h);
  const double max_change = d_.ramp_rpm_per_s * h;
  const double rpm0 = rpm_;
  rpm_ = rpm0 + std::clamp(target - rpm0, -max_change, max_change);
  angle_deg_ = std::fmod(angle_deg_ + 0.5 * (rpm0 + rpm_) / 60.0 * 360.0 * h, 360.0);
  const double s = rpm_ / d_.reference_rpm;
  const double bearing = std::pow(s, d_.heat_speed_exponent);
  net_.SetHeat(front_bearing_, d_.front_bearing_heat_w * bearing);
  net_.SetHeat(rear_bearing_, d_.rear_bearing_heat_w * bearing);
  net_.SetHeat(motor_, rpm_ > 0 ? d_.motor_idle_heat_w + d_.motor_heat_w * s * s : 0.0);
  const double convection = d_.shaft_to_ambient_w_per_k + d_.shaft_to_ambient_rotating_w_per_k * std::pow(s, 0.8);
  net_.SetConductance(convection_front_, convection);
  net_.SetConductance(convection_rear_, 0.5 * convection);
  net_.Step(h);
  t_s_ += h;
}

double VirtualSpindle::GrowthUm() const {
  const double rear_mm = d_.length_mm - d_.front_length_mm;
  return 1000.0 * d_.expansion_per_k *
         (d_.front_length_mm * (FrontShaftC() - d_.standard_temp_c) + rear_mm * (RearShaftC() - d_.standard_temp_c));
}

double VirtualSpindle::MarkerStrain() const { return d_.expansion_per_k * (FrontShaftC() - d_.standard_temp_c); }
double VirtualSpindle::FrontShaftC() const { return net_.Temperature(shaft_front_); }
double VirtualSpindle::RearShaftC() const { return net_.Temperature(shaft_rear_); }
double VirtualSpindle::FrontBearingC() const { return net_.Temperature(front_bearing_); }
double VirtualSpindle::MotorC() const { return net_.Temperature(motor_); }
double VirtualSpindle::HousingC() const { return net_.Temperature(housing_); }

}  // namespace trueaxis::sim
