#include "trueaxis/tooltherm/tool_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::tooltherm {
namespace {

const std::array<ToolMaterial, 4> kMaterials{{
    {"carbide", 5.5e-6, 80.0, 2.9e6},
    {"hss", 11.0e-6, 25.0, 3.7e6},
    {"steel", 11.5e-6, 45.0, 3.6e6},
    {"aluminium", 23.0e-6, 160.0, 2.4e6},
}};

}  // namespace

const ToolMaterial* FindToolMaterial(const std::string& name) {
  for (const auto& m : kMaterials)
    if (m.name == name) return &m;
  return nullptr;
}

std::string ToolMaterialNames() {
  std::string s;
  for (const auto& m : kMaterials) s += (s.empty() ? "" : ", ") + m.name;
  return s;
}

std::vector<double> ZoneGrowthUmPerC(const ToolDescription& tool) {
  const ToolMaterial* body = FindToolMaterial(tool.material);
  const ToolMaterial* holder = FindToolMaterial(tool.holder_material);
  const std::size_t nz = tool.zones.size();
  if (!body || !holder || nz == 0 || !(tool.GaugeLengthMm() > 0)) return {};
  std::vector<double> growth(nz, 0.0);
  constexpr int kSteps = 2000;  // midpoint rule along the gauge length
  const double dz = tool.GaugeLengthMm() / kSteps;
  for (int i = 0; i < kSteps; ++i) {
    const double z = (i + 0.5) * dz;
    const double alpha = z < tool.length_mm ? body->expansion_per_k : holder->expansion_per_k;
    // Distance of z to each band (0 inside); the nearest band(s) share this slice.
    double nearest = INFINITY;
    std::vector<double> dist(nz);
    for (std::size_t r = 0; r < nz; ++r) {
      dist[r] = std::max({tool.zones[r].from_mm - z, z - tool.zones[r].to_mm, 0.0});
      nearest = std::min(nearest, dist[r]);
    }
    std::size_t ties = 0;
    for (double d : dist) ties += d <= nearest + 1e-12 ? 1 : 0;
    for (std::size_t r = 0; r < nz; ++r)
      if (dist[r] <= nearest + 1e-12) growth[r] += 1e3 * alpha * dz / static_cast<double>(ties);
  }
  return growth;
}

double ZoneAreaMm2(const ToolDescription& tool, double from_mm, double to_mm) {
  constexpr double kTol = 1e-9;
  if (!(from_mm >= 0 && to_mm > from_mm && to_mm <= tool.GaugeLengthMm() + kTol))
    throw std::invalid_argument(fmt::format("band [{}, {}] mm must satisfy 0 ≤ from < to ≤ {} (tool + holder)", from_mm,
                                            to_mm, tool.GaugeLengthMm()));
  if (to_mm <= tool.length_mm + kTol) return std::numbers::pi * tool.diameter_mm * (to_mm - from_mm);
  if (from_mm >= tool.length_mm - kTol) return std::numbers::pi * tool.holder_diameter_mm * (to_mm - from_mm);
  throw std::invalid_argument(
      fmt::format("band [{}, {}] mm straddles the tool/holder step at {} mm: split it in two", from_mm, to_mm, tool.length_mm));
}

std::vector<ToolZone> DefaultToolZones(const ToolDescription& t) {
  const double third = t.length_mm / 3.0;
  std::vector<ToolZone> z = {{"tip", 0, third, 0}, {"middle", third, 2 * third, 0}, {"shank", 2 * third, t.length_mm, 0},
                             {"holder", t.length_mm, t.GaugeLengthMm(), 0}};
  for (auto& zone : z) zone.area_mm2 = ZoneAreaMm2(t, zone.from_mm, zone.to_mm);
  return z;
}

bool ToolDescription::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (number < 1) return fail("number must be ≥ 1");
  if (!(length_mm > 0 && diameter_mm > 0 && holder_length_mm > 0 && holder_diameter_mm > 0))
    return fail("lengths and diameters must be > 0");
  if (!(holder_diameter_mm >= diameter_mm)) return fail("holder_diameter_mm must be ≥ diameter_mm");
  if (!FindToolMaterial(material)) return fail("material '" + material + "' unknown (" + ToolMaterialNames() + ")");
  if (!FindToolMaterial(holder_material))
    return fail("holder_material '" + holder_material + "' unknown (" + ToolMaterialNames() + ")");
  if (!(cutting_heat_share >= 0 && cutting_heat_share <= 1)) return fail("cutting_heat_share must be in [0, 1]");
  if (zones.empty()) return fail("no zones");
  for (const auto& z : zones)
    if (!(z.area_mm2 > 0)) return fail("zone '" + z.name + "' has no area");
  return true;
}

const ToolDescription* ToolTable::Find(int number) const {
  for (const auto& t : tools)
    if (t.number == number) return &t;
  return nullptr;
}

ToolTable ParseToolToml(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  TomlTableReader top(root, source, "");
  ToolTable table;
  top.Double("standard_temp_c", table.standard_temp_c, -10, 60);
  const toml::node* n = top.Node("tool");
  if (!n) throw InputError(source, 0, "tool", "no [[tool]] defined");
  const auto* arr = n->as_array();
  if (!arr || !arr->is_array_of_tables()) top.Fail("tool", n, "must be an array of tables ([[tool]])");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::table& tt = *(*arr)[i].as_table();
    TomlTableReader r(tt, source, fmt::format("tool[{}]", i));
    ToolDescription t;
    r.Int("number", t.number, 1, 99999);
    if (!tt.contains("number")) r.Fail("number", nullptr, "required");
    if (table.Find(t.number)) r.Fail("number", tt.get("number"), fmt::format("tool {} is defined twice", t.number));
    r.String("name", t.name);
    r.Double("length_mm", t.length_mm, 1, 1000, true);
    r.Double("diameter_mm", t.diameter_mm, 0.1, 500, true);
    if (r.String("material", t.material) && !FindToolMaterial(t.material))
      r.Fail("material", tt.get("material"), "unknown material (" + ToolMaterialNames() + ")");
    r.Double("holder_length_mm", t.holder_length_mm, 1, 1000);
    r.Double("holder_diameter_mm", t.holder_diameter_mm, 1, 1000);
    if (r.String("holder_material", t.holder_material) && !FindToolMaterial(t.holder_material))
      r.Fail("holder_material", tt.get("holder_material"), "unknown material (" + ToolMaterialNames() + ")");
    r.Double("cutting_heat_share", t.cutting_heat_share, 0, 1);
    if (t.holder_diameter_mm < t.diameter_mm)
      r.Fail("holder_diameter_mm", tt.get("holder_diameter_mm"), "must be ≥ diameter_mm");
    if (const toml::node* zn = r.Node("zone")) {
      const auto* za = zn->as_array();
      if (!za || !za->is_array_of_tables()) r.Fail("zone", zn, "must be an array of tables ([[tool.zone]])");
      for (std::size_t k = 0; k < za->size(); ++k) {
        const toml::table& zt = *(*za)[k].as_table();
        TomlTableReader zr(zt, source, r.Key(fmt::format("zone[{}]", k)));
        ToolZone z;
        zr.String("name", z.name);
        if (z.name.empty()) z.name = fmt::format("zone{}", k + 1);
        zr.Double("from_mm", z.from_mm, 0, 2000, true);
        zr.Double("to_mm", z.to_mm, 0, 2000, true);
        zr.Double("area_mm2", z.area_mm2, 1e-6, 1e7);
        if (z.area_mm2 == 0) {
          try {
            z.area_mm2 = ZoneAreaMm2(t, z.from_mm, z.to_mm);
          } catch (const std::invalid_argument& e) {
            zr.Fail("to_mm", zt.get("to_mm"), e.what());
          }
        } else if (!(z.to_mm > z.from_mm && z.to_mm <= t.GaugeLengthMm())) {
          zr.Fail("to_mm", zt.get("to_mm"), "must be > from_mm and ≤ length_mm + holder_length_mm");
        }
        zr.RejectUnknown();
        t.zones.push_back(z);
      }
    }
    if (t.zones.empty()) t.zones = DefaultToolZones(t);
    r.RejectUnknown();
    std::string why;
    if (!t.IsValid(&why)) throw InputError(source, r.Line(&tt), fmt::format("tool[{}]", i), why);
    table.tools.push_back(std::move(t));
  }
  top.RejectUnknown();
  return table;
}

ToolTable ReadToolFile(const std::string& path) { return ParseToolToml(ReadTextFile(path), path); }

}  // namespace trueaxis::tooltherm
