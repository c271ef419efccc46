// libFuzzer target: the ecmc .dat importer must return a measurement or throw
// InputError for any bytes; accepted input must evaluate or be rejected with
// InputError, never crash.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/ecmc_dat.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto m = trueaxis::measure::ParseEcmcDat(text, "fuzz.dat");
    (void)trueaxis::analysis::Evaluate(m);
  } catch (const trueaxis::InputError&) {
  }
  return 0;
}
