#include "trueaxis/export/linuxcnc_table.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::exporter {

bool LinuxCncOptions::IsValid(std::string* why) const {
  if (comp_file_type != 0 && comp_file_type != 1) {
    if (why) *why = "--comp-file-type: must be 0 (nominal, actual) or 1 (nominal, trim)";
    return false;
  }
  if (joint < 0 || joint > 15) {
    if (why) *why = "--joint: must be 0…15";
    return false;
  }
  return true;
}

namespace {
void CheckWritable(const CompensationTable& t, const LinuxCncOptions& o, const std::string& source) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError(source, 0, why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
  ValidateTable(t, source);
  if (t.size() > static_cast<std::size_t>(kLinuxCncMaxPoints))
    throw InputError(source, 0, "--spacing",
                     fmt::format("{} points exceed LinuxCNC's limit of {} per joint; choose a larger --spacing", t.size(),
                                 kLinuxCncMaxPoints));
  if (t.thermal_tan_beta_um_per_mm != 0)
    throw InputError(source, 0, "thermal", "LinuxCNC has no temperature line; the thermal part must be frozen into the table");
}
}  // namespace

std::string WriteLinuxCncCompFile(const CompensationTable& t, const LinuxCncOptions& o, const std::string& source) {
  CheckWritable(t, o, source);
  std::string out;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double x = t.position_mm[i];
    const double f_um = AppliedCorrectionUm(t, x, Direction::kForward);  // includes ±backlash/2 when unidirectional
    const double r_um = AppliedCorrectionUm(t, x, Direction::kReverse);
    double f = f_um / 1000.0, r = r_um / 1000.0;
    if (o.comp_file_type == 0) {  // actual = nominal − trim
      f = x - f;
      r = x - r;
    }
    out += fmt::format("{:.6f} {:.6f} {:.6f}\n", x, f, r);
  }
  return out;
}

std::string LinuxCncIniSnippet(const CompensationTable& t, const LinuxCncOptions& o) {
  std::string s = fmt::format("[JOINT_{}]\nCOMP_FILE = {}\nCOMP_FILE_TYPE = {}\n", o.joint, o.comp_file_name,
                              o.comp_file_type);
  if (!t.bidirectional)
    s += fmt::format(
        "# BACKLASH = {:.6f}  (not set: LinuxCNC ignores BACKLASH when COMP_FILE is given;\n"
        "#  the backlash is already in the file as +/-{:.6f} mm on the forward/reverse columns)\n",
        t.backlash_um / 1000.0, t.backlash_um / 2000.0);
  s += fmt::format("# file: {} points {}…{} mm, values in machine units (mm), trims = corrections\n", t.size(),
                   FormatShortest(t.position_mm.front()), FormatShortest(t.position_mm.back()));
  // The file itself holds no comments (LinuxCNC stops reading at the first one): what it was made
  // from, and the temperatures a thermal model was frozen at, go here.
  for (const auto& p : t.provenance) s += "# " + p + "\n";
  return s;
}

CompensationTable ReadLinuxCncCompFile(std::string_view text, int comp_file_type, const std::string& source) {
  if (comp_file_type != 0 && comp_file_type != 1)
    throw InputError(source, 0, "COMP_FILE_TYPE", "must be 0 or 1");
  CompensationTable t;
  int line_no = 0;
  std::vector<int> point_lines;
  LineCursor cursor(text);
  while (cursor.Next()) {
    line_no = cursor.number();
    std::string_view line = cursor.line();
    if (line.empty()) continue;
    std::vector<std::string_view> fields;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      std::size_t j = i;
      while (j < line.size() && !(line[j] == ' ' || line[j] == '\t' || line[j] == '\r')) ++j;
      if (j > i) fields.push_back(line.substr(i, j - i));
      i = j;
    }
    if (fields.size() != 3)
      throw InputError(source, line_no, "triplet",
                       fmt::format("expected 'nominal forward reverse', found {} fields (LinuxCNC stops reading here)",
                                   fields.size()));
    double v[3];
    static const char* kNames[3] = {"nominal", "forward", "reverse"};
    for (int k = 0; k < 3; ++k) {
      auto d = ParseDouble(fields[k]);
      if (!d || !std::isfinite(*d))
        throw InputError(source, line_no, kNames[k], fmt::format("'{}' is not a number", fields[k]));
      v[k] = *d;
    }
    if (!t.position_mm.empty() && !(v[0] > t.position_mm.back()))
      throw InputError(source, line_no, "nominal",
                       fmt::format("positions must ascend ({} follows {})", v[0], t.position_mm.back()));
    double f = v[1], r = v[2];
    if (comp_file_type == 0) {
      f = v[0] - v[1];
      r = v[0] - v[2];
    }
    t.position_mm.push_back(v[0]);
    point_lines.push_back(line_no);
    t.forward_um.push_back(f * 1000.0);
    t.reverse_um.push_back(r * 1000.0);
  }
  if (t.position_mm.empty()) throw InputError(source, 0, "triplet", "the file holds no compensation points");
  if (t.size() > static_cast<std::size_t>(kLinuxCncMaxPoints))
    throw InputError(source, 0, "triplet",
                     fmt::format("{} points exceed LinuxCNC's limit of {} per joint", t.size(), kLinuxCncMaxPoints));
  ValidateReadTable(t, source, point_lines);
  return t;
}

}  // namespace trueaxis::exporter
