#pragma once
// The machine a calibration campaign is planned for (docs/real-machine.md "Machine file"): axes with
// their soft limits in machine coordinates, screw lead and fixed end, the sensors mounted and where,
// and the controller the laser programs are written for.
//
// Two files are read: the short real-machine file (a `[machine]` table with `controller = …`; axes
// from `min_mm` to `max_mm`, which may be negative as on most controllers), or the virtual machine's
// file (docs/machine-file.md; axes from 0 to travel_mm, no controller: programs for every one).
#include <optional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace trueaxis::campaign {

enum class Controller { kLinuxCnc, kFanuc, kSinumerik, kHeidenhain };
const std::vector<Controller>& AllControllers();
std::string_view ControllerName(Controller c);             // linuxcnc | fanuc | sinumerik | heidenhain
std::string_view ControllerTitle(Controller c);            // LinuxCNC | FANUC | SINUMERIK | HEIDENHAIN (Klartext)
std::optional<Controller> ParseController(std::string_view name);

struct CampaignAxis {
  std::string name;          // upper case
  double min_mm = 0, max_mm = 0;  // soft limits, machine coordinates
  double lead_mm = 0;
  bool fixed_at_min = true;  // the fixed (thrust) bearing at the min_mm end
  double reference_mm = 0;   // where the laser is zeroed (default: the fixed end)
  // CTE of the axis's position feedback, µm/m/°C (the ball screw's with a rotary encoder, the
  // scale's with a linear scale); NaN: not given. Stamped on the laser files by `campaign add`, it
  // gives the fit the room's physical soak ρ = −cte/1000, which holds in every season.
  double cte_um_per_m_c = std::numeric_limits<double>::quiet_NaN();
  double TravelMm() const { return max_mm - min_mm; }
};

struct CampaignSensor {
  std::string name;      // lower case, the log's t_<name>_c column
  std::string location;  // <axis>_nut, <axis>_bearing, <axis>_floating_bearing, <axis>_motor, <axis>_structure,
                         // bed, bed_top, bed_bottom, ambient, coolant, spindle
};

struct CampaignMachine {
  std::string source;    // file path
  std::string name = "machine";
  std::optional<Controller> controller;  // none: programs for every controller
  std::vector<CampaignAxis> axes;
  std::vector<CampaignSensor> sensors;
  bool virtual_machine_file = false;     // read from a `sim` machine file (axes 0…travel)

  int AxisIndex(std::string_view name) const;  // case-insensitive; -1 when absent
  std::vector<std::string> SensorsAt(const std::string& location) const;
};

// Reads either file; InputError(file, line, key, …) for a bad or unknown key, an axis without a nut
// sensor or a machine without a room (ambient) sensor — the warm-up tests are timed by the nut's rise
// and the model's reach is the room's range.
CampaignMachine ParseCampaignMachineToml(const std::string& text, const std::string& source);
CampaignMachine ReadCampaignMachineFile(const std::string& path);

}  // namespace trueaxis::campaign
