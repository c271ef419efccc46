#pragma once
// Synthetic sensor signals for the signal tests: a true temperature, white
// noise, occasional spikes (vibration, EMI bursts) and 12-bit ADC
// quantisation through the seed's 0-50 °C / 0-5 V transmitter.
#include <cmath>
#include <random>

#include "trueaxis/signal/conversions.hpp"

namespace trueaxis::signal::testing {

struct NoisySensor {
  double noise_sigma_c = 0.15;
  double spike_probability = 0.02;
  double spike_min_c = 2.0;
  double spike_max_c = 8.0;
  std::mt19937 rng{12345};

  double Sample(double true_c) {
    std::normal_distribution<double> noise(0.0, noise_sigma_c);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double v = true_c + noise(rng);
    if (u(rng) < spike_probability) {
      const double size = spike_min_c + (spike_max_c - spike_min_c) * u(rng);
      v += u(rng) < 0.5 ? -size : size;
    }
    const AnalogChannelOptions adc;
    return ConvertAdcCount(VoltsToAdcCount(CelsiusToTransmitterVolts(v, adc), adc), adc).temp_c;
  }
};

}  // namespace trueaxis::signal::testing
