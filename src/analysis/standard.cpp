#include "trueaxis/analysis/standard.hpp"

#include <cctype>

namespace trueaxis::analysis {
namespace {

struct Entry {
  const char* name;        // as shown to users
  StandardId id;
};

// Canonical names first; aliases after. Order is the order of StandardNames().
constexpr Entry kEntries[] = {
    {"ISO 230-2:2014", StandardId::kIso230_2_2014},
    {"ISO 230-2:2006", StandardId::kIso230_2_2006},
    {"ISO 230-2:1997", StandardId::kIso230_2_1997},
    {"ISO 230-2:1988", StandardId::kIso230_2_1988},
    {"VDI/DGQ 3441", StandardId::kVdi3441},
    {"ISO 230-2", StandardId::kIso230_2_2014},
    {"VDI 3441", StandardId::kVdi3441},
    {"GB/T 17421.2-2016", StandardId::kIso230_2_2014},
    {"GB/T 17421.2-2000", StandardId::kIso230_2_1997},
    {"GB/T 17421.2", StandardId::kIso230_2_2014},
    {"JIS B 6192:1999", StandardId::kIso230_2_1997},
    {"JIS B 6192", StandardId::kIso230_2_1997},
};

// Lower-case letters and digits only: "GB/T 17421.2-2000" -> "gbt1742122000".
std::string Normalize(std::string_view s) {
  std::string out;
  for (char c : s)
    if (std::isalnum(static_cast<unsigned char>(c))) out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

Standard Make(StandardId id) {
  Standard s;
  s.id = id;
  switch (id) {
    case StandardId::kIso230_2_2014: s.name = "ISO 230-2:2014"; break;
    case StandardId::kIso230_2_2006: s.name = "ISO 230-2:2006"; break;
    case StandardId::kIso230_2_1997: s.name = "ISO 230-2:1997"; break;
    case StandardId::kIso230_2_1988: s.name = "ISO 230-2:1988"; s.coverage_factor = 3; break;
    case StandardId::kVdi3441: s.name = "VDI/DGQ 3441"; s.is_vdi = true; break;
  }
  return s;
}

}  // namespace

std::optional<Standard> FindStandard(std::string_view name) {
  const auto key = Normalize(name);
  if (key.empty()) return std::nullopt;
  for (const auto& e : kEntries) {
    if (Normalize(e.name) == key) {
      Standard s = Make(e.id);
      s.requested_as = std::string(name);
      return s;
    }
  }
  return std::nullopt;
}

std::vector<std::string> StandardNames() {
  std::vector<std::string> out;
  for (const auto& e : kEntries) out.emplace_back(e.name);
  return out;
}

}  // namespace trueaxis::analysis
