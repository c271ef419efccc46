// libFuzzer target: the canonical CSV reader must either return a measurement
// or throw InputError — never crash, hang or throw anything else. Whatever it
// accepts must survive a write/read round trip and, when it validates, an
// ISO 230-2 evaluation.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/measurement_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view text(reinterpret_cast<const char*>(data), size);
  trueaxis::measure::Measurement m;
  try {
    m = trueaxis::measure::ParseMeasurementCsv(text, "fuzz.csv");
  } catch (const trueaxis::InputError&) {
    return 0;
  }
  const auto again = trueaxis::measure::ParseMeasurementCsv(trueaxis::measure::FormatMeasurementCsv(m), "again.csv");
  if (again.points.size() != m.points.size()) std::abort();
  try {
    (void)trueaxis::analysis::Evaluate(m);
  } catch (const trueaxis::InputError&) {
  }
  return 0;
}
