// Randomly varied five-axis machines (for tests and the bench).
#include "trueaxis/fiveaxis/machine_variation.hpp"

#include <cmath>
#include <random>

#include <fmt/format.h>

namespace trueaxis::fiveaxis {

FiveAxisMachine VaryMachine(const FiveAxisMachine& base, unsigned seed) {
  std::mt19937 rng(seed);
  auto factor = [&](double lo, double hi) {  // log-uniform
    std::uniform_real_distribution<double> u(std::log(lo), std::log(hi));
    return std::exp(u(rng));
  };
  FiveAxisMachine m = base;
  m.name = fmt::format("{} varied #{}", base.name, seed);
  const double rates[] = {1000, 2000, 4000};
  m.servo_rate_hz = rates[std::uniform_int_distribution<int>(0, 2)(rng)];
  for (DriveParams& d : m.drives) {
    d.kp_per_s *= factor(0.6, 1.5);
    d.kv_a_s_per_rad *= factor(0.6, 1.5);
    d.ti_s *= factor(0.6, 1.5);
    d.current_lag_s *= factor(0.5, 2);
    d.motor_inertia_kg_m2 *= factor(0.5, 2);
    d.motor_viscous_n_m_s_per_rad *= factor(0.3, 3);
    d.load_inertia *= factor(0.3, 3);
    d.load_viscous *= factor(0.3, 3);
    d.coulomb *= factor(0.3, 3);
  }
  return m;
}

}  // namespace trueaxis::fiveaxis
