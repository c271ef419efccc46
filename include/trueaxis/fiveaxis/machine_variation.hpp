#pragma once
// Machines not in the repository: a machine whose every drive parameter is
// scaled by a random factor (seeded, reproducible), to test the method on
// drives it was not written against. Gains ×0.6…1.5, inertias and frictions
// ×0.3…3, current lag ×0.5…2, Coulomb ×0.3…3; the servo rate one of 1, 2, 4 kHz.
#include "trueaxis/fiveaxis/machine.hpp"

namespace trueaxis::fiveaxis {

FiveAxisMachine VaryMachine(const FiveAxisMachine& base, unsigned seed);

}  // namespace trueaxis::fiveaxis
