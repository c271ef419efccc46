// Bad input never crashes a reader or escapes as anything but InputError:
// the golden files, mutated deterministically (characters replaced, lines
// dropped or repeated, digits lengthened), go through every reader.
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/export/csv_table.hpp"
#include "trueaxis/export/fanuc_table.hpp"
#include "trueaxis/export/heidenhain_table.hpp"
#include "trueaxis/export/linuxcnc_table.hpp"
#include "trueaxis/export/sinumerik_table.hpp"

namespace trueaxis::exporter {
namespace {

const std::string kGolden = std::string(TRUEAXIS_SOURCE_DIR) + "/tests/export/golden/";

std::string Mutate(std::string s, std::mt19937& rng) {
  static const std::string kChars = "0123456789-+.,;:=[]% \nNAPX$*#e";
  std::uniform_int_distribution<int> kind(0, 4);
  const int mutations = 1 + static_cast<int>(rng() % 3);
  for (int m = 0; m < mutations && !s.empty(); ++m) {
    const std::size_t at = rng() % s.size();
    switch (kind(rng)) {
      case 0: s[at] = kChars[rng() % kChars.size()]; break;
      case 1: s.erase(at, 1); break;
      case 2: s.insert(at, std::string(1 + rng() % 25, '9')); break;  // huge numbers
      case 3: {  // drop a line
        const auto b = s.rfind('\n', at), e = s.find('\n', at);
        if (b != std::string::npos && e != std::string::npos) s.erase(b, e - b);
        break;
      }
      default: {  // repeat a line
        const auto b = s.rfind('\n', at), e = s.find('\n', at);
        if (b != std::string::npos && e != std::string::npos) s.insert(e, s.substr(b, e - b));
      }
    }
  }
  return s;
}

template <typename Reader>
void Hammer(const std::string& golden, Reader read) {
  const std::string text = ReadTextFile(kGolden + golden);
  ASSERT_NO_THROW(read(text)) << golden << " itself must read";
  std::mt19937 rng(1234);
  int rejected = 0;
  for (int i = 0; i < 400; ++i) {
    const std::string bad = Mutate(text, rng);
    try {
      read(bad);
    } catch (const InputError&) {
      ++rejected;
    } catch (const std::exception& e) {
      ADD_FAILURE() << golden << ": mutation " << i << " escaped as " << typeid(e).name() << ": " << e.what() << "\n"
                    << bad;
      return;
    }
  }
  EXPECT_GT(rejected, 100) << golden << ": most mutations should be rejected";
}

TEST(ReaderRobustness, MutatedFilesGiveInputErrorOrATable) {
  Hammer("x_comp_type1.txt", [](const std::string& t) { ReadLinuxCncCompFile(t, 1, "c"); });
  Hammer("X_EEC.INI", [](const std::string& t) { ReadSinumerikEec(t, "e"); });
  Hammer("x_pitch_fanuc.txt", [](const std::string& t) { ReadFanucPitchTape(t, 1, 1.0, 0.0, "f"); });
  Hammer("X_OFF.COM", [](const std::string& t) { ReadHeidenhainCom(t, ValueSign::kCorrection, "h"); });
  Hammer("X.CMA", [](const std::string& t) { ReadHeidenhainCma(t, "X", "h"); });
  Hammer("x_table.csv", [](const std::string& t) { ReadCsvTable(t, "c"); });
}

}  // namespace
}  // namespace trueaxis::exporter
