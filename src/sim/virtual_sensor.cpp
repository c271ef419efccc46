#include "trueaxis/sim/virtual_sensor.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::sim {

std::string_view SensorFaultKindName(SensorFaultKind k) {
  switch (k) {
    case SensorFaultKind::kNone: return "none";
    case SensorFaultKind::kOpen: return "open";
    case SensorFaultKind::kShort: return "short";
    case SensorFaultKind::kStuck: return "stuck";
    case SensorFaultKind::kSpikes: return "spikes";
    case SensorFaultKind::kDrift: return "drift";
  }
  return "?";
}

std::optional<SensorFaultKind> ParseSensorFaultKind(std::string_view name) {
  for (auto k : {SensorFaultKind::kNone, SensorFaultKind::kOpen, SensorFaultKind::kShort, SensorFaultKind::kStuck,
                 SensorFaultKind::kSpikes, SensorFaultKind::kDrift})
    if (SensorFaultKindName(k) == name) return k;
  return std::nullopt;
}

namespace {
constexpr double kAdcSpanC = 50.0;      // transmitter 0–50 °C → 0–5 V
constexpr double kAdcCounts = 4095.0;   // 12 bit over 0–5 V
constexpr double kRtdLowC = -50.0, kRtdHighC = 150.0, kRtdCounts = 65535.0;
}  // namespace

hw::MeasuringRange SensorMeasuringRange(SensorKind kind) {
  switch (kind) {
    case SensorKind::kPt100Adc: return {0.0, kAdcSpanC};
    case SensorKind::kDs18b20: return {-55.0, 125.0};
    case SensorKind::kRtdModule: return {kRtdLowC, kRtdHighC};
  }
  return {};
}

double SensorStepC(SensorKind kind) {
  switch (kind) {
    case SensorKind::kPt100Adc: return kAdcSpanC / kAdcCounts;
    case SensorKind::kDs18b20: return 0.0625;
    case SensorKind::kRtdModule: return (kRtdHighC - kRtdLowC) / kRtdCounts;
  }
  return 0;
}

VirtualSensor::VirtualSensor(SensorDescription description, std::uint64_t noise_seed, double initial_true_c)
    : d_(std::move(description)), rng_(noise_seed), probe_c_(initial_true_c) {
  latest_ = Convert(probe_c_ * (1 + d_.gain_error) + d_.offset_c);
}

void VirtualSensor::Reset(double true_c) { probe_c_ = true_c; }

void VirtualSensor::SetFault(const SensorFault& fault, double t_s) {
  fault_ = fault;
  fault_since_s_ = t_s;
}

hw::RawTemperature VirtualSensor::Convert(double c) const {
  hw::RawTemperature r;
  switch (d_.kind) {
    case SensorKind::kPt100Adc: {
      // The transmitter clamps at its rails, the card quantises; the card
      // cannot tell an over-range from a real 50 °C: no flag.
      const double counts = std::clamp(std::round(c / kAdcSpanC * kAdcCounts), 0.0, kAdcCounts);
      r.temp_c = counts * kAdcSpanC / kAdcCounts;
      break;
    }
    case SensorKind::kDs18b20: {
      const double v = std::clamp(c, -55.0, 125.0);
      r.temp_c = std::round(v / 0.0625) * 0.0625;
      break;
    }
    case SensorKind::kRtdModule: {
      if (c < kRtdLowC || c > kRtdHighC) {  // module flags over/under range
        r.temp_c = std::numeric_limits<double>::quiet_NaN();
        r.hardware_fault = true;
        break;
      }
      const double counts = std::round((c - kRtdLowC) / (kRtdHighC - kRtdLowC) * kRtdCounts);
      r.temp_c = kRtdLowC + counts * (kRtdHighC - kRtdLowC) / kRtdCounts;
      break;
    }
  }
  return r;
}

void VirtualSensor::Sample(double true_c, double dt_s, double t_s) {
  // First-order probe lag, exact for a constant input over the step.
  if (d_.time_constant_s > 0) probe_c_ = true_c + (probe_c_ - true_c) * std::exp(-dt_s / d_.time_constant_s);
  else probe_c_ = true_c;
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double n = noise(rng_) * d_.noise_c;  // drawn every sample, fault or not, so faults do not shift the noise sequence
  const double spike_draw = u(rng_);
  const double spike_sign = u(rng_) < 0.5 ? -1 : 1;
  double indicated = probe_c_ * (1 + d_.gain_error) + d_.offset_c + n;
  switch (fault_.kind) {
    case SensorFaultKind::kNone: break;
    case SensorFaultKind::kStuck: return;  // the value stops changing
    case SensorFaultKind::kDrift: indicated += fault_.drift_c_per_hour * (t_s - fault_since_s_) / 3600.0; break;
    case SensorFaultKind::kSpikes:
      if (spike_draw < fault_.spike_probability) indicated += spike_sign * fault_.spike_amplitude_c;
      break;
    case SensorFaultKind::kOpen:
      switch (d_.kind) {
        case SensorKind::kPt100Adc: latest_ = Convert(1e3); return;  // burn-out drives up-scale
        case SensorKind::kDs18b20: latest_ = {std::numeric_limits<double>::quiet_NaN(), true}; return;  // no presence pulse
        case SensorKind::kRtdModule: latest_ = {std::numeric_limits<double>::quiet_NaN(), true}; return;  // wire-break flag
      }
      break;
    case SensorFaultKind::kShort:
      switch (d_.kind) {
        case SensorKind::kPt100Adc: latest_ = Convert(-1e3); return;  // 0 Ω → far below range → 0 V
        case SensorKind::kDs18b20: latest_ = {85.0, false}; return;   // power-on reset value, unflagged
        case SensorKind::kRtdModule: latest_ = {std::numeric_limits<double>::quiet_NaN(), true}; return;
      }
      break;
  }
  latest_ = Convert(indicated);
}

}  // namespace trueaxis::sim
