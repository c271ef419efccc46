#pragma once
// The tool table of the virtual (or a real) machine: per tool its number,
// geometry, material and holder, and the surface zones a non-contact
// temperature reading is averaged over (docs/tool-thermal.md, "Tool file").
//
// Geometry (all at the standard temperature): the tool sticks out of the
// holder by length_mm (gauge line of the holder = spindle nose face); the
// holder reaches holder_length_mm from the nose face to the holder's front.
// Zones are bands of the outer surface measured from the tool tip along the
// axis (from_mm < to_mm): a band lies on the tool (to_mm ≤ length_mm) or on
// the holder (from_mm ≥ length_mm). Its area Sr is the lateral surface
// π·d·(to − from) with d the diameter of the part it lies on, unless the file
// gives area_mm2. A tool without zones gets the default three tool bands
// (tip, middle, shank third) and one holder band.
#include <string>
#include <vector>

namespace trueaxis::tooltherm {

struct ToolMaterial {
  std::string name;
  double expansion_per_k = 0;             // α
  double conductivity_w_per_m_k = 0;      // λ
  double heat_capacity_j_per_m3_k = 0;    // ρ·c
};

// "carbide", "hss", "steel", "aluminium"; nullptr when unknown.
const ToolMaterial* FindToolMaterial(const std::string& name);
std::string ToolMaterialNames();  // "carbide, hss, steel, aluminium"

struct ToolZone {
  std::string name;
  double from_mm = 0;  // from the tip
  double to_mm = 0;
  double area_mm2 = 0;  // Sr
};

struct ToolDescription {
  int number = 0;                 // T / P number (1 …)
  std::string name;
  double length_mm = 0;           // stick-out from the holder's gauge line
  double diameter_mm = 0;
  std::string material = "carbide";
  double holder_length_mm = 60;   // nose face to the holder's front end
  double holder_diameter_mm = 40;
  std::string holder_material = "steel";
  double cutting_heat_share = 0.004;  // part of the cutting power that flows into the tool body (most leaves with the chip)
  std::vector<ToolZone> zones;

  double GaugeLengthMm() const { return length_mm + holder_length_mm; }  // nose face to tip
  bool IsValid(std::string* why) const;
};

// Default zones for a tool's geometry (see the header comment).
std::vector<ToolZone> DefaultToolZones(const ToolDescription& tool);
// Lateral area of the band [from, to] on the tool or holder (throws std::invalid_argument
// when the band straddles the tool/holder step or leaves the gauge length).
double ZoneAreaMm2(const ToolDescription& tool, double from_mm, double to_mm);

// Free growth per °C (µm/°C) of the part of the gauge length each zone stands for: every point of
// the axis belongs to the band that holds it (shared equally where bands overlap) or, between bands,
// to the nearest one; α is the tool's material on the stick-out and the holder's beyond it. The
// sum over the zones is the whole gauge length's free growth. Empty when a material is unknown or
// the tool has no zones.
std::vector<double> ZoneGrowthUmPerC(const ToolDescription& tool);

struct ToolTable {
  double standard_temp_c = 20.0;
  std::vector<ToolDescription> tools;

  const ToolDescription* Find(int number) const;
};

// [[tool]] number, name, length_mm, diameter_mm, material, holder_length_mm,
// holder_diameter_mm, holder_material, cutting_heat_share, and optional
// [[tool.zone]] name, from_mm, to_mm, area_mm2. InputError(file, line, field) on bad input.
ToolTable ParseToolToml(const std::string& text, const std::string& source);
ToolTable ReadToolFile(const std::string& path);

}  // namespace trueaxis::tooltherm
