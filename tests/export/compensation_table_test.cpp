#include "trueaxis/export/compensation_table.hpp"

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/export/csv_table.hpp"
#include "trueaxis/export/fanuc_table.hpp"
#include "trueaxis/export/heidenhain_table.hpp"
#include "trueaxis/export/linuxcnc_table.hpp"
#include "trueaxis/export/sinumerik_table.hpp"

namespace trueaxis::exporter {
namespace {

TEST(CompensationTable, InterpolatesAndHoldsEnds) {
  CompensationTable t;
  t.position_mm = {0, 10, 20};
  t.forward_um = {0, 10, 0};
  t.reverse_um = {1, 1, 1};
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, 5, Direction::kForward), 5);
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, 15, Direction::kForward), 5);
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, -5, Direction::kForward), 0);
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, 25, Direction::kReverse), 1);
}

// A correction no controller table holds (a 1e308 from a broken model, a value in nm) is refused
// by every writer before it writes: the HEIDENHAIN writer printed "-inf +inf", LinuxCNC a 300-digit
// number, into a file the controller would load.
TEST(CompensationTable, EveryWriterRefusesAnImplausibleCorrection) {
  CompensationTable t;
  t.axis = "X";
  t.position_mm = {0, 10, 20};
  t.forward_um = {0, 1e308, 0};
  t.reverse_um = {0, 1, 0};
  t.reference_position_mm = 0;
  const auto refused = [](const auto& write, const std::string& field) {
    try {
      write();
      ADD_FAILURE() << "written: " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "m.json");
      EXPECT_EQ(e.field(), field);
      EXPECT_NE(e.message().find("beyond ±10000 µm"), std::string::npos) << e.what();
    }
  };
  refused([&] { return WriteHeidenhainCom(t, "X_COLD", ValueSign::kCorrection, "m.json"); }, "forward_um[1]");
  refused([&] { return WriteLinuxCncCompFile(t, LinuxCncOptions{}, "m.json"); }, "forward_um[1]");
  refused([&] { return WriteSinumerikEec(t, SinumerikOptions{}, "m.json"); }, "forward_um[1]");
  refused([&] { return WriteFanucPitchTape(t, FanucOptions{}, "m.json"); }, "forward_um[1]");
  refused([&] { return WriteCsvTable(t, ValueSign::kCorrection, "m.json"); }, "forward_um[1]");
  t.forward_um[1] = 1;
  t.reverse_um[2] = -20000;  // 20 mm: a table in nm, or a broken model
  refused([&] { return WriteCsvTable(t, ValueSign::kCorrection, "m.json"); }, "reverse_um[2]");
  t.reverse_um[2] = -9000;  // large, but a table may hold it
  EXPECT_NO_THROW(WriteCsvTable(t, ValueSign::kCorrection, "m.json"));
  t.backlash_um = 1e300;
  refused([&] { return WriteCsvTable(t, ValueSign::kCorrection, "m.json"); }, "backlash_um");
}

}  // namespace
}  // namespace trueaxis::exporter
