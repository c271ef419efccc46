#pragma once
// VirtualSensor: one temperature measuring chain (probe, transmitter,
// converter) with the imperfections a real one has: first-order lag of the
// probe, offset and gain error (so calibration against a reference sensor has
// something to find), noise, the converter's quantisation, and faults that
// tests and demos inject at run time.
//
// Quantisation by kind:
//   Pt100 + 0–50 °C → 0–5 V transmitter + 12-bit ADC: 50/4095 = 0.01221 °C per count;
//     open wire drives the transmitter up-scale (reads 50 °C), a short down-scale (0 °C);
//     a plain ADC has no fault flag.
//   DS18B20: 0.0625 °C steps (12-bit mode); open line → hardware_fault (driver's −127);
//     a shorted/brown-out sensor returns its power-on value 85 °C without a flag.
//   RTD module: 16-bit over −50…150 °C (0.00305 °C); open/short → hardware_fault.
#include <cstdint>
#include <optional>
#include <random>
#include <string_view>

#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::sim {

enum class SensorFaultKind { kNone, kOpen, kShort, kStuck, kSpikes, kDrift };

struct SensorFault {
  SensorFaultKind kind = SensorFaultKind::kNone;
  double spike_probability = 0.05;   // kSpikes: chance per sample
  double spike_amplitude_c = 8;      // kSpikes: size of a spike (sign random)
  double drift_c_per_hour = 0.5;     // kDrift: offset growth since the fault was set
};

std::string_view SensorFaultKindName(SensorFaultKind k);
std::optional<SensorFaultKind> ParseSensorFaultKind(std::string_view name);

// Resolution of a kind's converter, °C per step.
double SensorStepC(SensorKind kind);
// What a kind's measuring chain can report (transmitter span, module range, datasheet range).
hw::MeasuringRange SensorMeasuringRange(SensorKind kind);

class VirtualSensor {
 public:
  // `description` must have offset/gain/noise/time constant filled (FinishMachineDescription does).
  VirtualSensor(SensorDescription description, std::uint64_t noise_seed, double initial_true_c);

  const SensorDescription& description() const { return d_; }
  // Advances the probe lag by dt with the true temperature at its location and
  // takes a new sample (noise, quantisation, fault) at time t_s.
  void Sample(double true_c, double dt_s, double t_s);
  // Jumps the probe to equilibrium at true_c (soak); the next Sample reads it.
  void Reset(double true_c);
  hw::RawTemperature Latest() const { return latest_; }
  double ProbeC() const { return probe_c_; }  // lagged temperature before errors

  void SetFault(const SensorFault& fault, double t_s);
  const SensorFault& fault() const { return fault_; }

 private:
  hw::RawTemperature Convert(double indicated_c) const;

  SensorDescription d_;
  std::mt19937_64 rng_;
  double probe_c_ = 20;
  hw::RawTemperature latest_;
  SensorFault fault_;
  double fault_since_s_ = 0;
};

}  // namespace trueaxis::sim
