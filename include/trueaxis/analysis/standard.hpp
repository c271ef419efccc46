#pragma once
// The evaluation standards trueaxis knows, and their national adoptions.
//
// ISO 230-2 editions differ (for the quantities computed here) only in the
// coverage factor k used in accuracy and repeatability: k = 2 since 1997,
// k = 3 in 1988 (R = 6s). VDI/DGQ 3441 defines its own quantities
// (P, Pa, Ps, U) with a fixed 6s scatter; when it is selected the ISO
// quantities are still computed, with k = 2.
//
// National adoptions are aliases of the edition they adopt (docs/analysis.md):
//   GB/T 17421.2-2016 = ISO 230-2:2014 (IDT)   GB/T 17421.2-2000 = ISO 230-2:1997 (IDT)
//   JIS B 6192:1999   = ISO 230-2:1997 (MOD, same formulas)
//   bare "GB/T 17421.2" means the current 2016 edition; bare "JIS B 6192" the 1999 edition.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace trueaxis::analysis {

enum class StandardId { kIso230_2_2014, kIso230_2_2006, kIso230_2_1997, kIso230_2_1988, kVdi3441 };

struct Standard {
  StandardId id = StandardId::kIso230_2_2014;
  std::string name;             // canonical name, e.g. "ISO 230-2:2014"
  std::string requested_as;     // what the user typed (alias), e.g. "GB/T 17421.2"
  double coverage_factor = 2;   // k in A = max(x̄+k·s) − min(x̄−k·s), R↑ = 2k·s
  bool is_vdi = false;
};

// Looks a name up case- and punctuation-insensitively ("iso230-2:2006",
// "ISO 230-2 2006", "vdi3441", "GB/T 17421.2-2000", "jis b 6192").
std::optional<Standard> FindStandard(std::string_view name);
// Names accepted by FindStandard, canonical names first, for help texts and errors.
std::vector<std::string> StandardNames();

}  // namespace trueaxis::analysis
