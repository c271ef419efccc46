#include "trueaxis/pitch/model_table.hpp"

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::pitch {

namespace {

void Put(const PitchErrorTable& t, model::AxisModel& a) {
  for (Direction d : {Direction::kForward, Direction::kReverse}) {
    model::GeometricError& g = a.directions[DirectionIndex(d)].geometric;
    g = model::GeometricError{};
    g.kind = model::GeometricError::Kind::kTable;
    g.table_position_mm = t.position_mm;
    g.table_error_um = d == Direction::kForward ? t.error_up_um : t.error_down_um;
  }
  a.measured_range_mm = {t.VouchedFromMm(), t.VouchedToMm()};
  for (auto& f : a.fallbacks) Put(t, f);  // the model and its fallbacks share Er(x)
}

}  // namespace

void PutTableIntoModel(const PitchErrorTable& table, model::CompositeModel& m, const std::string& model_source) {
  for (auto& a : m.axes)
    if (a.axis == table.axis) {
      Put(table, a);
      return;
    }
  std::string known;
  for (const auto& a : m.axes) known += (known.empty() ? "" : ", ") + a.axis;
  throw InputError(model_source, 0, "axis", fmt::format("the model has no axis '{}' (it has: {})", table.axis, known));
}

}  // namespace trueaxis::pitch
