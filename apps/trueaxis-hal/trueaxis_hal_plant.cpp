// trueaxis-hal-plant: the virtual machine tool (sim::VirtualMachine) as the PLANT of a LinuxCNC
// machine, for closing the loop in simulation (docs/linuxcnc.md, *Closed loop*):
//
//   LinuxCNC joint.N.motor-pos-cmd ─► C.L.motor-pos-cmd ─► the virtual machine's motor
//   (the encoder sits on the motor: the HAL file loops motor-pos-cmd back to motor-pos-fb in the
//   servo thread, so a late plant process never makes a following error)
//   the table = motor + pitch + backlash + thermal growth ─► the virtual laser (sim::LaserInterferometer)
//   C.temp.<sensor> ─► trueaxis.temp.<sensor>   (trueaxis-hal --temperatures hal)
//
// The laser is triggered from G-code: M68 E0 Q<target>, E1 Q<run>, E2 Q<±1 direction of approach>
// (motion.analog-out-00/01/02 → C.laser-target / C.laser-run / C.laser-direction), M64/M65 P0 pulses C.laser-read
// (motion.digital-out-00), P1 zeroes the laser at the axis's reference (C.laser-zero), P2 writes the
// measurement so far as out/measurement_<k>.csv (C.laser-save, k counts from 1 on C.laser-saved).
//
// Time: before the component is ready, the machine is brought to its state in machine time, as fast
// as the CPU runs it (the demo's working day: `--day` days after the campaign, cold start, then
// `--warmup-h` hours of machining with the demo's duty); from then on it advances in real time with
// LinuxCNC (the laser cycle's moves and dwells heat and cool it as they take).
//
// --reference RUN.toml: the same machine, state, laser cycle and compensator (run config) in
// process — the compensator cycling inside the machine's time, as in `trueaxis demo` — for the
// comparison with the LinuxCNC run; writes reference_on.csv / reference_off.csv.
#include <atomic>
#include <chrono>
#include <csignal>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/linuxcnc/hal_component.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/virtual_machine.hpp"
#include "trueaxis/station/installation.hpp"

namespace {

using namespace trueaxis;
namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void OnStopSignal(int) { g_stop.store(true); }

struct Options {
  std::string machine;
  std::uint64_t seed = 1;     // the demo's --seed: its working day runs the machine with seed + 1000
  std::string axis = "X";
  std::string name = "taplant";
  int day = 30;               // the demo's day_offset
  double warmup_h = 3;        // machining before the laser tests (the demo's "warm" state: 3 h)
  std::string coolant = "off";
  // The laser cycle (the G-code's targets, F and G4 come from targets.txt): the feed 12000 mm/min
  // and dwell 0.3 s keep a LinuxCNC run in minutes (the demo's laser: 2000 mm/min, 3 s).
  sim::LaserOptions laser = [] {
    sim::LaserOptions lo;
    lo.runs = 3;
    lo.feed_mm_min = 12000;
    lo.dwell_s = 0.3;
    return lo;
  }();
  std::string out_dir = ".";
  std::string reference;       // run config: run the in-process reference instead of the HAL plant
};

struct Plant {
  sim::VirtualMachine vm;
  sim::LaserInterferometer laser;
  std::size_t axis;
  double datum_mm;
};

// The demo's working day up to the laser tests: cold start at 07:00 `day` days after the
// campaign, then machining (every axis reciprocating over 10–90 % of its travel, 70 % duty,
// 3000/4000 mm/min) for warmup_h; the axis back at its reference, the laser zeroed there.
std::unique_ptr<Plant> Prepare(const Options& o) {
  const auto md = sim::ReadMachineFile(o.machine);
  const int axis = md.AxisIndex(o.axis);
  if (axis < 0) throw InputError(o.machine, 0, "axis", fmt::format("the machine has no axis '{}'", o.axis));
  auto p = std::unique_ptr<Plant>(new Plant{sim::VirtualMachine(md, o.seed + 1000),
                                            sim::LaserInterferometer(o.laser, o.seed * 7919 + 4242),
                                            static_cast<std::size_t>(axis), md.axes[axis].reference_mm});
  p->vm.IdleUntil(o.day * 86400.0);
  p->vm.Advance(60);
  const auto coolant = ParseCoolantState(o.coolant);
  if (!coolant) throw InputError("--coolant", 0, "coolant", "off, flood, mist or air");
  p->vm.SetCoolant(*coolant);
  for (std::size_t i = 0; i < p->vm.AxisCount(); ++i) {
    const double travel = md.axes[i].travel_mm;
    p->vm.CommandReciprocate(i, 0.1 * travel, 0.9 * travel, 3000, 0.7, 4000);
  }
  for (double t = 0; t < o.warmup_h * 3600 - 1e-9; t += 60) p->vm.Advance(std::min(60.0, o.warmup_h * 3600 - t));
  for (std::size_t i = 0; i < p->vm.AxisCount(); ++i) p->vm.CommandStop(i);
  p->vm.SetCompensationEnabled(false);  // the HAL plant: LinuxCNC puts the correction into the motor command
  return p;
}

void WriteTargets(const Options& o, Plant& p) {
  fs::create_directories(o.out_dir);
  std::ofstream f(fs::path(o.out_dir) / "targets.txt");
  f << "# laser targets (mm), then: overrun_mm runs datum_mm feed_mm_min dwell_s\n";
  for (double t : p.laser.Targets(p.vm, p.axis)) f << fmt::format("{:.3f}\n", t);
  f << fmt::format("# {} {} {} {} {}\n", o.laser.overrun_mm, o.laser.runs, p.datum_mm, o.laser.feed_mm_min,
                   o.laser.dwell_s);
}

std::string Brief(const measure::Measurement& m) {
  try {
    const auto e = analysis::Evaluate(m);
    return fmt::format("A = {:.2f} µm (repeatability R = {:.2f} µm)", e.axis.A_um, e.axis.R_um);
  } catch (const std::exception& e) {
    return fmt::format("not evaluable: {}", e.what());
  }
}

int RunHalPlant(const Options& o) {
  auto p = Prepare(o);
  Plant& pl = *p;
  pl.laser.Setup(pl.vm, pl.axis, pl.datum_mm);  // the axis at its reference (LinuxCNC homes there); re-zeroed by P1
  WriteTargets(o, pl);
  linuxcnc::HalComponent hal(o.name);
  using linuxcnc::PinDirection;
  const std::string l = o.axis == "X" ? "x" : o.axis == "Y" ? "y" : o.axis == "Z" ? "z" : o.axis;
  auto cmd = hal.FloatPin(l + ".motor-pos-cmd", PinDirection::kIn);
  auto table = hal.FloatPin(l + ".table-mm", PinDirection::kOut);
  auto time_s = hal.FloatPin("time-s", PinDirection::kOut);
  auto target = hal.FloatPin("laser-target", PinDirection::kIn);
  auto run = hal.FloatPin("laser-run", PinDirection::kIn);
  auto direction = hal.FloatPin("laser-direction", PinDirection::kIn);
  auto read = hal.BitPin("laser-read", PinDirection::kIn);
  auto zero = hal.BitPin("laser-zero", PinDirection::kIn);
  auto save = hal.BitPin("laser-save", PinDirection::kIn);
  auto readings = hal.S32Pin("laser-readings", PinDirection::kOut);
  auto saved = hal.S32Pin("laser-saved", PinDirection::kOut);
  auto flood = hal.BitPin("coolant-flood", PinDirection::kIn);
  std::vector<linuxcnc::Pin<double>> temp;
  std::vector<linuxcnc::Pin<bool>> fault;
  for (std::size_t i = 0; i < pl.vm.ChannelCount(); ++i) {
    temp.push_back(hal.FloatPin("temp." + pl.vm.ChannelName(i), PinDirection::kOut));
    fault.push_back(hal.BitPin("temp." + pl.vm.ChannelName(i) + "-fault", PinDirection::kOut));
  }
  std::vector<hw::RawTemperature> raw(pl.vm.ChannelCount());
  auto publish = [&] {
    pl.vm.Read(std::span<hw::RawTemperature>(raw));
    for (std::size_t i = 0; i < raw.size(); ++i) {
      temp[i].Set(raw[i].temp_c);
      fault[i].Set(raw[i].hardware_fault);
    }
    table.Set(pl.vm.ActualMm(pl.axis));
    time_s.Set(pl.vm.TimeS());
  };
  publish();
  g_stop = false;
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
  hal.Ready();
  fmt::print(stderr, "trueaxis-hal-plant: {} seed {} axis {} at {} (warmed {} h), {} laser targets → {}\n",
             pl.vm.description().name, o.seed, o.axis, pl.vm.IsoTime(), o.warmup_h,
             pl.laser.Targets(pl.vm, pl.axis).size(), o.out_dir);
  measure::Measurement m = pl.laser.StartMeasurement(pl.vm);
  double t0 = pl.vm.TimeS();
  bool last_read = false, last_zero = false, last_save = false;
  int n_saved = 0;
  std::uint64_t clamped_updates = 0;
  const double travel_mm = pl.vm.description().axes[pl.axis].travel_mm;
  using Clock = std::chrono::steady_clock;
  auto last = Clock::now();
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::microseconds(500));
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    // The motor goes where LinuxCNC commands it, at the speed that takes (machine time = real time).
    // The virtual machine refuses positions beyond its travel: a correction at the very end of the
    // travel (µm beyond 0 or the travel) is held at the end, and counted.
    double to = cmd.Get();
    const double clamped_to = std::clamp(to, 0.0, travel_mm);
    if (clamped_to != to) ++clamped_updates;
    to = clamped_to;
    const double dist = std::abs(to - pl.vm.CommandedMm(pl.axis));
    if (dist > 0) pl.vm.CommandMove(pl.axis, to, std::max(1.0, dist / dt * 60.0));
    pl.vm.SetCoolant(flood.Get() ? CoolantState::kFlood : CoolantState::kOff);
    pl.vm.Advance(dt);
    if (zero.Get() && !last_zero) {
      pl.laser.Setup(pl.vm, pl.axis, pl.datum_mm);  // the axis stands at the datum (the G-code put it there)
      m = pl.laser.StartMeasurement(pl.vm);
      t0 = pl.vm.TimeS();
    }
    if (read.Get() && !last_read) {
      const Direction d = direction.Get() >= 0 ? Direction::kForward : Direction::kReverse;
      m.points.push_back(pl.laser.Reading(pl.vm, static_cast<int>(std::lround(run.Get())), d, target.Get(), t0));
      readings.Set(static_cast<std::int32_t>(m.points.size()));
    }
    if (save.Get() && !last_save) {
      ++n_saved;
      const auto path = fs::path(o.out_dir) / fmt::format("measurement_{}.csv", n_saved);
      measure::WriteMeasurementCsv(m, path.string());
      fmt::print(stderr, "trueaxis-hal-plant: {} ({} readings) {}\n", path.string(), m.points.size(), Brief(m));
      saved.Set(n_saved);
    }
    last_zero = zero.Get();
    last_read = read.Get();
    last_save = save.Get();
    publish();
  }
  if (clamped_updates)
    fmt::print(stderr, "trueaxis-hal-plant: {} motor commands beyond the travel were held at its end\n", clamped_updates);
  return 0;
}

// The same state and laser cycle in process, the compensator of the run config cycling in the
// machine's time (runtime::LoopRunner::StepSimulated, as the demo), compensation on then off.
int RunReference(const Options& o) {
  const station::InstallationConfig c = station::ReadSiteConfig(o.reference).installation;
  auto p = Prepare(o);
  Plant& pl = *p;
  pl.vm.SetCompensationEnabled(true);
  // The same installation as trueaxis-hal's (temperature pipeline, compensator, model), on the machine's clock.
  station::Installation installation(c, pl.vm, pl.vm, [&pl] { return pl.vm.TimeS(); }, "");
  runtime::Compensator* comp = &installation.compensator();
  runtime::LoopRunner runner(*comp, pl.vm, installation.temperatures(), runtime::LoopOptions{c.period_s, c.temperature_period_s});
  auto advance = [&](double dt) { pl.vm.Advance(dt); };
  auto cycles = [&](double seconds) {
    runner.StepSimulated(static_cast<std::uint64_t>(std::llround(seconds / c.period_s)), advance);
  };
  auto move = [&](double x) {
    pl.vm.CommandMove(pl.axis, x, o.laser.feed_mm_min);
    for (int guard = 0; pl.vm.IsMoving(pl.axis) && guard < 100'000'000; ++guard) cycles(c.period_s);
  };
  fs::create_directories(o.out_dir);
  for (bool on : {true, false}) {
    comp->SetEnabled(on);
    move(std::max(0.0, pl.datum_mm - std::max(o.laser.overrun_mm, 1.0)));
    move(pl.datum_mm);
    cycles(1.0);  // the ramp to the new state (≤ 100 µm at max_step per cycle)
    pl.laser.Setup(pl.vm, pl.axis, pl.datum_mm);
    measure::Measurement m = pl.laser.StartMeasurement(pl.vm);
    const double t0 = pl.vm.TimeS();
    sim::RunBidirectionalCycle(pl.laser.Targets(pl.vm, pl.axis), o.laser.runs, o.laser.overrun_mm, move,
                               [&](int run, Direction d, double t) {
                                 move(t);
                                 cycles(o.laser.dwell_s);
                                 m.points.push_back(pl.laser.Reading(pl.vm, run, d, t, t0));
                               });
    const auto path = fs::path(o.out_dir) / (on ? "reference_on.csv" : "reference_off.csv");
    measure::WriteMeasurementCsv(m, path.string());
    fmt::print("reference compensation {}: {} ({})\n", on ? "on " : "off", Brief(m), path.string());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"trueaxis-hal-plant: the virtual machine as LinuxCNC's plant, with the virtual laser (docs/linuxcnc.md)"};
  app.add_option("--machine", o.machine, "Machine description (TOML)")->required()->check(CLI::ExistingFile);
  app.add_option("--seed", o.seed, "The demo's seed (the machine runs with seed + 1000, as the demo's day)")->capture_default_str();
  app.add_option("--axis", o.axis, "The axis LinuxCNC drives (joint 0)")->capture_default_str();
  app.add_option("--name", o.name, "HAL component name")->capture_default_str();
  app.add_option("--day", o.day, "Days after the campaign (the demo's working day)")->capture_default_str();
  app.add_option("--warmup-h", o.warmup_h, "Hours of machining before the laser tests (machine time)")->capture_default_str();
  app.add_option("--coolant", o.coolant, "Coolant during the warm-up")->capture_default_str();
  app.add_option("--spacing-mm", o.laser.spacing_mm, "Laser target spacing")->capture_default_str();
  app.add_option("--first-mm", o.laser.first_mm, "First laser target (default: overrun)");
  app.add_option("--last-mm", o.laser.last_mm, "Last laser target (default: travel − overrun)");
  app.add_option("--runs", o.laser.runs, "Runs of the bidirectional cycle")->capture_default_str();
  app.add_option("--feed-mm-min", o.laser.feed_mm_min, "Feed of the laser cycle")->capture_default_str();
  app.add_option("--dwell-s", o.laser.dwell_s, "Dwell at each target before the reading")->capture_default_str();
  app.add_option("--out", o.out_dir, "Folder for targets.txt and the measurements")->capture_default_str();
  app.add_option("--reference", o.reference, "Run config: run the in-process reference instead of the HAL plant")
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);
  try {
    return o.reference.empty() ? RunHalPlant(o) : RunReference(o);
  } catch (const InputError& e) {
    fmt::print(stderr, "trueaxis-hal-plant: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "trueaxis-hal-plant: {}\n", e.what());
    return 1;
  }
}
