// Five-axis machine TOML reader (docs/fiveaxis.md, "Machine file").
#include "trueaxis/fiveaxis/machine.hpp"

#include <cmath>
#include <numbers>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::fiveaxis {

double DriveParams::MotorRadPerSi() const {
  // Linear: 2π rad per lead; rotary: gear ratio.
  return rotary ? transmission : 2 * std::numbers::pi / (transmission * 1e-3);
}
double DriveParams::MotorRadPerUnit() const { return MotorRadPerSi() / UnitPerSi(); }
double DriveParams::TotalInertiaKgM2() const {
  const double n = MotorRadPerSi();
  return motor_inertia_kg_m2 + load_inertia / (n * n);
}
double DriveParams::TotalViscousNmsPerRad() const {
  const double n = MotorRadPerSi();
  return motor_viscous_n_m_s_per_rad + load_viscous / (n * n);
}
double DriveParams::CoulombAtMotorNm() const { return coulomb / MotorRadPerSi(); }

namespace {

void ReadDrive(TomlTableReader& r, DriveParams& d) {
  r.Double("kp_per_s", d.kp_per_s, 0.1, 1000);
  r.Double("kv_a_s_per_rad", d.kv_a_s_per_rad, 1e-6, 1e4);
  double ti_ms = d.ti_s * 1e3, lag_ms = d.current_lag_s * 1e3;
  r.Double("ti_ms", ti_ms, 0.1, 1e4);
  r.Double("current_lag_ms", lag_ms, 0.0, 10);
  d.ti_s = ti_ms * 1e-3;
  d.current_lag_s = lag_ms * 1e-3;
  r.Double("kt_nm_per_a", d.kt_nm_per_a, 1e-3, 1e3);
  r.Double("current_limit_a", d.current_limit_a, 1e-3, 1e4);
  r.Double("motor_inertia_kg_m2", d.motor_inertia_kg_m2, 1e-7, 100);
  r.Double("motor_viscous_n_m_s_per_rad", d.motor_viscous_n_m_s_per_rad, 0, 100);
  // The load keys differ by unit only.
  struct LoadKeys {
    const char *inertia, *viscous, *coulomb, *transmission, *velocity;
    double viscous_max, coulomb_max, transmission_min, transmission_max;
  };
  static constexpr LoadKeys kLinear{"load_mass_kg", "load_viscous_n_s_per_m", "coulomb_n", "lead_mm",
                                    "max_velocity_mm_per_min", 1e7, 1e6, 0.1, 1000};
  static constexpr LoadKeys kRotary{"load_inertia_kg_m2", "load_viscous_n_m_s_per_rad", "coulomb_n_m", "gear_ratio",
                                    "max_velocity_deg_per_min", 1e6, 1e5, 1, 1e4};
  const LoadKeys& k = d.rotary ? kRotary : kLinear;
  r.Double(k.inertia, d.load_inertia, 0, 1e5);
  r.Double(k.viscous, d.load_viscous, 0, k.viscous_max);
  r.Double(k.coulomb, d.coulomb, 0, k.coulomb_max);
  r.Double(k.transmission, d.transmission, k.transmission_min, k.transmission_max);
  double per_min = d.max_velocity_per_s * 60;
  r.Double(k.velocity, per_min, 1, 1e6);
  d.max_velocity_per_s = per_min / 60;
  r.RejectUnknown();
}

DriveParams DefaultRotaryDrive() {
  DriveParams d;
  d.rotary = true;
  d.kp_per_s = 40;
  d.load_inertia = 3;     // kg·m²
  d.load_viscous = 5;     // N·m·s/rad
  d.coulomb = 20;         // N·m
  d.transmission = 100;   // gear
  d.max_velocity_per_s = 90;
  return d;
}

}  // namespace

FiveAxisMachine ParseFiveAxisMachineToml(const std::string& text, const std::string& source) {
  const toml::table root = ParseTomlOrThrow(text, source);
  FiveAxisMachine m;
  m.source = source;
  m.drives[kTilt] = DefaultRotaryDrive();
  m.drives[kRot] = DefaultRotaryDrive();
  TomlTableReader r(root, source, "");
  const toml::table* mt = r.Table("machine");
  if (!mt) throw InputError(source, 1, "machine", "a [machine] table with family = table_ac | table_bc | head_bc is required");
  {
    TomlTableReader mr(*mt, source, "machine");
    mr.String("name", m.name);
    const int family = mr.Choice("family", {"table_ac", "table_bc", "head_bc"});
    if (family < 0) mr.Fail("family", nullptr, "required: table_ac, table_bc or head_bc");
    m.kinematics.family = static_cast<Family>(family);
    mr.Double("servo_rate_hz", m.servo_rate_hz, 1000, 4000);
    mr.RejectUnknown();
  }
  if (auto* t = r.Table("kinematics")) {
    TomlTableReader kr(*t, source, "kinematics");
    auto& k = m.kinematics;
    const double big = 1e4;
    kr.Double("pivot_x_mm", k.pivot_mm.x(), -big, big);
    kr.Double("pivot_y_mm", k.pivot_mm.y(), -big, big);
    kr.Double("pivot_z_mm", k.pivot_mm.z(), -big, big);
    kr.Double("offset_x_mm", k.offset_mm.x(), -big, big);
    kr.Double("offset_y_mm", k.offset_mm.y(), -big, big);
    kr.Double("offset_z_mm", k.offset_mm.z(), -big, big);
    kr.Double("tool_length_mm", k.tool_length_mm, 0, 2000);
    kr.Double("pivot_length_mm", k.pivot_length_mm, 0, 2000);
    kr.Bool("conventional_directions", k.conventional_directions);
    kr.Double("tilt_min_deg", m.tilt_min_deg, -360, 360);
    kr.Double("tilt_max_deg", m.tilt_max_deg, -360, 360);
    kr.Double("rot_min_deg", m.rot_min_deg, -1e6, 1e6);
    kr.Double("rot_max_deg", m.rot_max_deg, -1e6, 1e6);
    for (int k = 0; k < 3; ++k) {
      const std::string axis(1, static_cast<char>('x' + k));
      kr.Double(axis + "_min_mm", m.travel_min_mm[k], -1e5, 1e5);
      kr.Double(axis + "_max_mm", m.travel_max_mm[k], -1e5, 1e5);
      if (m.travel_min_mm[k] >= m.travel_max_mm[k])
        kr.Fail(axis + "_max_mm", kr.Node(axis + "_max_mm"), "must exceed " + axis + "_min_mm");
    }
    if (m.tilt_min_deg >= m.tilt_max_deg) kr.Fail("tilt_max_deg", kr.Node("tilt_max_deg"), "must exceed tilt_min_deg");
    if (m.rot_min_deg >= m.rot_max_deg) kr.Fail("rot_max_deg", kr.Node("rot_max_deg"), "must exceed rot_min_deg");
    if (k.family == Family::kHeadBC && (k.pivot_mm.norm() > 0 || k.offset_mm.norm() > 0))
      kr.Fail("pivot_x_mm", nullptr, "a head_bc machine has no table pivot/offset (use pivot_length_mm)");
    if (k.family == Family::kHeadBC && !k.conventional_directions)
      kr.Fail("conventional_directions", kr.Node("conventional_directions"), "head_bc supports conventional directions only");
    kr.RejectUnknown();
  }
  if (auto* t = r.Table("interpolator")) {
    TomlTableReader ir(*t, source, "interpolator");
    auto& l = m.interpolator;
    ir.Double("path_accel_mm_per_s2", l.path_accel_mm_per_s2, 1, 1e6);
    ir.Double("path_jerk_mm_per_s3", l.path_jerk_mm_per_s3, 10, 1e9);
    ir.Double("corner_stop_deg", l.corner_stop_deg, 0.01, 180);
    ir.Double("rapid_feed_mm_per_min", l.rapid_feed_mm_per_min, 1, 1e6);
    ir.RejectUnknown();
  }
  if (auto* t = r.Table("drive")) {
    TomlTableReader dr(*t, source, "drive");
    const auto names = m.axis_names();
    for (int i = 0; i < kAxisCount; ++i)
      if (auto* at = dr.Table(names[i])) {
        TomlTableReader ar(*at, source, "drive." + names[i]);
        ReadDrive(ar, m.drives[i]);
      }
    dr.RejectUnknown();
  }
  r.RejectUnknown();
  return m;
}

FiveAxisMachine ReadFiveAxisMachineFile(const std::string& path) {
  return ParseFiveAxisMachineToml(ReadTextFile(path), path);
}

}  // namespace trueaxis::fiveaxis
