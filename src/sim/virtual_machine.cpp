#include "trueaxis/sim/virtual_machine.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::sim {

namespace {
constexpr double kSteelDensity = 7850, kSteelHeat = 460, kSteelConductivity = 45;  // SI
constexpr double kReferenceC = 20.0;  // ISO 1: lengths are true at 20 °C

std::string Lower(const std::string& s) {
  std::string o;
  for (char c : s) o += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return o;
}

std::uint64_t Mix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = a + 0x9E3779B97F4A7C15ull * (b + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
}  // namespace

struct VirtualMachine::Axis {
  enum class Mode { kIdle, kMove, kReciprocate };
  AxisDescription d;
  PitchErrorProfile pitch;
  double screw_len_mm = 0, seg_len_mm = 0, end_gap_mm = 0;
  int away = 1;  // +1: growth pushes towards + (fixed end at min)
  // thermal nodes and edges
  std::size_t nut = 0, bearing = 0, floating = 0, motor = 0;
  std::vector<std::size_t> seg, nut_seg_edge, seg_cool_edge, seg_air_edge;
  std::size_t nut_cool_edge = 0;
  double seg_area_m2 = 0;
  // motion
  Mode mode = Mode::kIdle;
  double cmd_mm = 0, target_mm = 0, feed = 0, return_feed = 0, lo = 0, hi = 0, duty = 1, pause_left_s = 0;
  int recip_dir = 1;
  int servo_dir = 0;
  double speed_now = 0;
  double correction_um = 0;
  double play_mm = 0, last_motor_mm = 0;
  double homing_offset_um = 0;
  double extra_error_um = 0;  // SetExtraErrorUm: e.g. the spindle's growth at the tool on Z
  // accumulated over the current thermal step
  double dist_mm = 0;
  double travel_mm = 0;  // whole path of the motor since the start (TravelMm)
  std::vector<double> occupancy_s;

  Axis(const AxisDescription& desc, std::uint64_t serial_seed) : d(desc), pitch(desc, serial_seed) {}

  // Distance of the nut from the fixed bearing for machine position x.
  double U(double x_mm) const {
    const double from_fixed_end = d.fixed_end == FixedEnd::kMin ? x_mm : d.travel_mm - x_mm;
    return end_gap_mm + from_fixed_end;
  }
  int Segment(double u) const {
    return std::clamp(static_cast<int>(std::floor(u / seg_len_mm)), 0, static_cast<int>(seg.size()) - 1);
  }
  // Spreads `dt` of nut presence over the segments its contact length
  // covered while moving (at constant speed) between motor positions m0 and
  // m1. Exact time average of the overlap of [u − L/2, u + L/2] with each
  // segment, so it adds up the same however the motion is sliced.
  void AddPath(double m0, double m1, double dt) {
    if (dt <= 0) return;
    double u0 = U(m0), u1 = U(m1);
    if (u0 > u1) std::swap(u0, u1);
    const double len = u1 - u0;
    const double h = d.thermal.nut_length_mm / 2;
    if (h <= 0) {  // point contact
      if (len < 1e-9) {
        occupancy_s[Segment(u0)] += dt;
        return;
      }
      for (int i = Segment(u0); i <= Segment(u1); ++i) {
        const double a = std::max(u0, i * seg_len_mm), b = std::min(u1, (i + 1) * seg_len_mm);
        if (b > a) occupancy_s[i] += dt * (b - a) / len;
      }
      return;
    }
    auto ramp = [](double x) { return x > 0 ? x : 0.0; };
    auto ramp_integral = [](double x) { return x > 0 ? 0.5 * x * x : 0.0; };
    for (int i = Segment(u0 - h); i <= Segment(u1 + h); ++i) {
      const double a = i * seg_len_mm, b = (i + 1) * seg_len_mm;
      double w;
      if (len < 1e-9) {
        w = ramp(u0 + h - a) - ramp(u0 + h - b) - ramp(u0 - h - a) + ramp(u0 - h - b);
      } else {
        auto F = [&](double u) {
          return ramp_integral(u + h - a) - ramp_integral(u + h - b) - ramp_integral(u - h - a) + ramp_integral(u - h - b);
        };
        w = (F(u1) - F(u0)) / len;
      }
      if (w > 0) occupancy_s[i] += dt * w / (2 * h);
    }
  }
};

VirtualMachine::VirtualMachine(MachineDescription description, std::uint64_t seed)
    : d_(std::move(description)), seed_(seed), rng_(Mix(seed, 0x51)), ambient_(d_.ambient, Mix(seed, 0xA)) {
  if (d_.sensors.empty() || std::isnan(d_.sensors.front().offset_c)) FinishMachineDescription(d_);
  start_unix_s_ = ParseIsoTime(d_.start_iso);
  step_s_ = d_.thermal_step_s;
  const double t_amb = ambient_.TemperatureC(start_unix_s_);
  ambient_node_ = net_.AddNode("ambient", 0, t_amb);
  coolant_node_ = net_.AddNode("coolant", 0, t_amb);
  bed_node_ = net_.AddNode("bed", d_.bed.capacity_j_per_k, t_amb);
  net_.AddEdge(bed_node_, ambient_node_, d_.bed.to_ambient_w_per_k);

  for (const auto& ad : d_.axes) {
    auto a = std::make_unique<Axis>(ad, d_.serial_seed);
    const auto& th = ad.thermal;
    const std::string p = Lower(ad.name);
    a->screw_len_mm = ad.travel_mm + ad.screw_overhang_mm;
    a->end_gap_mm = ad.screw_overhang_mm / 2;
    a->away = ad.fixed_end == FixedEnd::kMin ? 1 : -1;
    const int n = th.screw_segments;
    a->seg_len_mm = a->screw_len_mm / n;
    const double dia_m = ad.screw_diameter_mm * 1e-3, ds_m = a->seg_len_mm * 1e-3;
    const double area = M_PI * dia_m * dia_m / 4;
    a->seg_area_m2 = M_PI * dia_m * ds_m;
    for (int i = 0; i < n; ++i)
      a->seg.push_back(net_.AddNode(fmt::format("{}_screw_{:02}", p, i), kSteelDensity * kSteelHeat * area * ds_m, t_amb));
    for (int i = 0; i + 1 < n; ++i) net_.AddEdge(a->seg[i], a->seg[i + 1], kSteelConductivity * area / ds_m);
    for (int i = 0; i < n; ++i)
      a->seg_air_edge.push_back(net_.AddEdge(a->seg[i], ambient_node_, th.screw_convection_w_per_m2_k * a->seg_area_m2));
    a->nut = net_.AddNode(p + "_nut", th.nut_capacity_j_per_k, t_amb);
    a->bearing = net_.AddNode(p + "_bearing", th.bearing_capacity_j_per_k, t_amb);
    a->floating = net_.AddNode(p + "_floating_bearing", th.bearing_capacity_j_per_k, t_amb);
    a->motor = net_.AddNode(p + "_motor", th.motor_capacity_j_per_k, t_amb);
    for (int i = 0; i < n; ++i) a->nut_seg_edge.push_back(net_.AddEdge(a->nut, a->seg[i], 0));
    for (int i = 0; i < n; ++i) a->seg_cool_edge.push_back(net_.AddEdge(a->seg[i], coolant_node_, 0));
    a->nut_cool_edge = net_.AddEdge(a->nut, coolant_node_, 0);
    net_.AddEdge(a->nut, ambient_node_, th.nut_to_ambient_w_per_k);
    net_.AddEdge(a->bearing, a->seg.front(), th.bearing_to_screw_w_per_k);
    net_.AddEdge(a->floating, a->seg.back(), th.bearing_to_screw_w_per_k);
    for (auto b : {a->bearing, a->floating}) {
      net_.AddEdge(b, bed_node_, th.bearing_to_bed_w_per_k);
      net_.AddEdge(b, ambient_node_, th.bearing_to_ambient_w_per_k);
    }
    net_.AddEdge(a->motor, a->bearing, th.motor_to_bearing_w_per_k);
    net_.AddEdge(a->motor, ambient_node_, th.motor_to_ambient_w_per_k);
    a->occupancy_s.assign(n, 0.0);
    a->cmd_mm = ad.reference_mm;
    a->last_motor_mm = a->cmd_mm;
    a->play_mm = -ad.backlash_um / 2000.0;  // homed approaching forward
    a->servo_dir = 0;
    axes_.push_back(std::move(a));
  }
  for (std::size_t i = 0; i < d_.sensors.size(); ++i) {
    const auto& s = d_.sensors[i];
    const std::size_t node = net_.FindNode(s.location);
    if (node == net_.NodeCount()) throw std::invalid_argument("sensor location '" + s.location + "' is not a node");
    sensor_node_.push_back(node);
    sensors_.push_back(std::make_unique<VirtualSensor>(s, Mix(seed, 1000 + i), net_.Temperature(node)));
  }
  std::normal_distribution<double> nd(0, 1);
  for (auto& a : axes_) a->homing_offset_um = nd(rng_) * a->d.homing_repeatability_um;

  // Soak: the machine stood idle overnight. Start at the mean ambient of the
  // previous day, then integrate that day so bed and screws lag the air as
  // they would.
  double sum = 0;
  for (int h = 0; h < 24; ++h) sum += ambient_.TemperatureC(start_unix_s_ - 86400 + h * 3600);
  net_.SetAllTemperatures(sum / 24);
  for (std::size_t i = 0; i < sensors_.size(); ++i) sensors_[i]->Reset(sum / 24);
  t_s_ = -86400;
  IdleCoarse(86400);
  t_s_ = 0;
  next_grid_s_ = step_s_;
}

void VirtualMachine::IdleCoarse(double duration_s) {
  // Standstill: no motion to resolve, so big steps (the network sub-steps
  // itself to stay stable) make days of idling cost milliseconds.
  const double h = 30.0;
  const double t_end = t_s_ + duration_s;
  while (t_s_ < t_end - 1e-9) {
    const double dt = std::min(h, t_end - t_s_);
    AdvanceMotion(dt);  // axes are idle: only records the nut's presence
    t_s_ += dt;
    ThermalStep(dt);
  }
  t_s_ = t_end;
  next_grid_s_ = t_s_ + step_s_;
  next_log_s_ = t_s_;
}

VirtualMachine::~VirtualMachine() = default;

std::string VirtualMachine::IsoTime() const { return FormatIsoTime(UnixTimeS()); }

void VirtualMachine::SetLogger(double interval_s, std::function<void(const VirtualMachine&)> logger) {
  log_interval_s_ = interval_s;
  logger_ = std::move(logger);
  next_log_s_ = t_s_;
}

void VirtualMachine::SetController(double interval_s, std::function<void(VirtualMachine&)> controller) {
  control_interval_s_ = interval_s;
  controller_ = std::move(controller);
  next_control_s_ = t_s_;
}

void VirtualMachine::Advance(double dt_s) {
  if (!(dt_s > 0)) return;
  const double t_end = t_s_ + dt_s;
  while (t_s_ < t_end - 1e-9) {
    // Events: thermal grid steps and, independently, the controller's own
    // period (a compensator may run much faster than the thermal step).
    double t_next = std::min(t_end, next_grid_s_);
    const bool control = controller_ && control_interval_s_ > 0;
    if (control) t_next = std::min(t_next, next_control_s_);
    if (t_next > t_s_) AdvanceMotion(t_next - t_s_);
    t_s_ = std::max(t_s_, t_next);
    if (t_s_ >= next_grid_s_ - 1e-9) {
      t_s_ = std::max(t_s_, next_grid_s_);
      ThermalStep(step_s_);
      next_grid_s_ += step_s_;
      if (logger_ && log_interval_s_ > 0 && t_s_ >= next_log_s_ - 1e-9) {
        logger_(*this);
        next_log_s_ += log_interval_s_ * std::max(1.0, std::floor((t_s_ - next_log_s_) / log_interval_s_ + 1));
      }
    }
    if (control && controller_ && t_s_ >= next_control_s_ - 1e-9) {
      next_control_s_ += control_interval_s_ * std::max(1.0, std::floor((t_s_ - next_control_s_) / control_interval_s_ + 1));
      controller_(*this);
    }
  }
  t_s_ = std::max(t_s_, t_end);
}

void VirtualMachine::IdleUntil(double t_s) {
  for (std::size_t i = 0; i < axes_.size(); ++i) CommandStop(i);
  coolant_ = CoolantState::kOff;
  if (t_s - t_s_ > 36 * 3600.0) {
    // Days of standstill: the machine ends up following the air with the
    // bed's lag. Jump to a day before, set everything to that day's mean air
    // temperature, and integrate the last day.
    const double restart = t_s - 86400;
    double sum = 0;
    for (int h = 0; h < 24; ++h) sum += ambient_.TemperatureC(start_unix_s_ + restart - 86400 + h * 3600);
    net_.SetAllTemperatures(sum / 24);
    for (auto& s : sensors_) s->Reset(sum / 24);
    t_s_ = restart;
  }
  if (t_s > t_s_) IdleCoarse(t_s - t_s_);
}

double VirtualMachine::MotorMm(const Axis& a) const { return a.cmd_mm + a.correction_um * 1e-3; }

void VirtualMachine::UpdatePlay(Axis& a) {
  const double m = MotorMm(a);
  const double half = a.d.backlash_um / 2000.0;
  a.play_mm = std::clamp(a.play_mm - (m - a.last_motor_mm), -half, half);
  a.last_motor_mm = m;
}

void VirtualMachine::AdvanceMotion(double dt) {
  for (auto& ap : axes_) {
    Axis& a = *ap;
    double left = dt;
    int guard = 0;
    while (left > 1e-12 && ++guard < 10000) {
      const double m0 = MotorMm(a);
      if (a.mode == Axis::Mode::kIdle || feed_hold_) {  // feed hold: the program waits in place
        a.AddPath(m0, m0, left);
        a.speed_now = 0;
        break;
      }
      if (a.mode == Axis::Mode::kReciprocate && a.pause_left_s > 0) {
        const double p = std::min(a.pause_left_s, left);
        a.AddPath(m0, m0, p);
        a.pause_left_s -= p;
        left -= p;
        a.speed_now = 0;
        continue;
      }
      const bool move = a.mode == Axis::Mode::kMove;
      const double target = move ? a.target_mm : (a.recip_dir > 0 ? a.hi : a.lo);
      const double feed = move || a.recip_dir > 0 ? a.feed : a.return_feed;
      const double v = feed / 60.0;
      const double dist = target - a.cmd_mm;
      if (std::abs(dist) < 1e-9) {  // within a picometre: arrived (absorbs rounding of t = d/v)
        a.cmd_mm = target;
        UpdatePlay(a);
        if (move) {
          a.mode = Axis::Mode::kIdle;
        } else {
          a.recip_dir = -a.recip_dir;
          a.pause_left_s = (a.hi - a.lo) / v * (1 - a.duty) / a.duty;
        }
        a.speed_now = 0;
        continue;
      }
      const double t_need = std::abs(dist) / v;
      const double tt = std::min(t_need, left);
      a.cmd_mm = tt >= t_need ? target : a.cmd_mm + (dist > 0 ? 1 : -1) * v * tt;
      a.servo_dir = dist > 0 ? 1 : -1;
      UpdatePlay(a);
      const double m1 = MotorMm(a);
      a.AddPath(m0, m1, tt);
      a.dist_mm += std::abs(m1 - m0);
      a.travel_mm += std::abs(m1 - m0);
      a.speed_now = feed;
      left -= tt;
      if (tt >= t_need) {  // arrived: settle now so Read() never shows a stale "moving"
        a.speed_now = 0;
        if (move) {
          a.mode = Axis::Mode::kIdle;
        } else {
          a.recip_dir = -a.recip_dir;
          a.pause_left_s = (a.hi - a.lo) / v * (1 - a.duty) / a.duty;
        }
      }
    }
  }
}

void VirtualMachine::ThermalStep(double h) {
  const double t_amb = ambient_.TemperatureC(start_unix_s_ + t_s_);
  const auto& cool = d_.coolant[static_cast<int>(coolant_)];
  net_.SetTemperature(ambient_node_, t_amb);
  net_.SetTemperature(coolant_node_, t_amb + cool.temperature_offset_c);
  for (auto& ap : axes_) {
    Axis& a = *ap;
    const auto& th = a.d.thermal;
    const double feed = a.dist_mm / h * 60.0;  // mean feed over the step
    const double f = feed > 0 ? std::pow(feed / th.reference_feed_mm_min, th.heat_speed_exponent) : 0.0;
    net_.SetHeat(a.nut, th.nut_heat_w * f);
    net_.SetHeat(a.bearing, th.fixed_bearing_heat_w * f);
    net_.SetHeat(a.floating, th.floating_bearing_heat_w * f);
    net_.SetHeat(a.motor, th.motor_idle_heat_w + th.motor_heat_w * f);
    // A spinning screw loses heat faster than a still one: cooling after a
    // warm-up is slower than the heating suggests.
    const double h_air = th.screw_convection_w_per_m2_k +
                         (feed > 0 ? th.screw_convection_rotating_w_per_m2_k * std::pow(feed / th.reference_feed_mm_min, 0.6) : 0.0);
    double occ_total = 0;
    for (double o : a.occupancy_s) occ_total += o;
    for (std::size_t i = 0; i < a.seg.size(); ++i) {
      const double share = occ_total > 0 ? a.occupancy_s[i] / occ_total : 0.0;
      net_.SetConductance(a.nut_seg_edge[i], th.nut_to_screw_w_per_k * share);
      net_.SetConductance(a.seg_cool_edge[i], cool.screw_w_per_m2_k * a.seg_area_m2);
      net_.SetConductance(a.seg_air_edge[i], h_air * a.seg_area_m2);
      a.occupancy_s[i] = 0;
    }
    net_.SetConductance(a.nut_cool_edge, cool.nut_w_per_k);
    a.dist_mm = 0;
  }
  net_.Step(h);
  for (auto it = scheduled_faults_.begin(); it != scheduled_faults_.end();) {
    if (t_s_ >= it->at_s - 1e-9) {
      sensors_[it->sensor]->SetFault(it->fault, it->at_s);
      it = scheduled_faults_.erase(it);
    } else {
      ++it;
    }
  }
  for (std::size_t i = 0; i < sensors_.size(); ++i) sensors_[i]->Sample(net_.Temperature(sensor_node_[i]), h, t_s_);
}

void VirtualMachine::CommandMove(std::size_t axis, double target_mm, double feed_mm_min) {
  Axis& a = *axes_.at(axis);
  if (!(target_mm >= -1e-9 && target_mm <= a.d.travel_mm + 1e-9))
    throw std::invalid_argument(fmt::format("axis {}: target {} mm is outside the travel 0–{} mm", a.d.name, target_mm, a.d.travel_mm));
  if (!(feed_mm_min > 0)) throw std::invalid_argument("feed must be positive");
  a.mode = Axis::Mode::kMove;
  a.target_mm = std::clamp(target_mm, 0.0, a.d.travel_mm);
  a.feed = feed_mm_min;
}

void VirtualMachine::CommandReciprocate(std::size_t axis, double lo_mm, double hi_mm, double feed_mm_min, double duty,
                                        double return_feed_mm_min) {
  Axis& a = *axes_.at(axis);
  if (!(lo_mm >= 0 && hi_mm <= a.d.travel_mm && hi_mm - lo_mm > 1e-3))
    throw std::invalid_argument(fmt::format("axis {}: reciprocation range {}–{} mm is not inside the travel", a.d.name, lo_mm, hi_mm));
  if (!(feed_mm_min > 0) || !(duty > 0 && duty <= 1)) throw std::invalid_argument("feed must be positive and duty in (0, 1]");
  a.mode = Axis::Mode::kReciprocate;
  a.lo = lo_mm;
  a.hi = hi_mm;
  a.feed = feed_mm_min;
  a.return_feed = return_feed_mm_min > 0 ? return_feed_mm_min : feed_mm_min;
  a.duty = duty;
  a.pause_left_s = 0;
  // Head for the farther end first; if outside the range, it travels into it on the way.
  a.recip_dir = a.cmd_mm < lo_mm ? 1 : (a.cmd_mm > hi_mm ? -1 : (hi_mm - a.cmd_mm > a.cmd_mm - lo_mm ? 1 : -1));
}

void VirtualMachine::CommandStop(std::size_t axis) {
  Axis& a = *axes_.at(axis);
  a.mode = Axis::Mode::kIdle;
  a.speed_now = 0;
}

bool VirtualMachine::IsMoving(std::size_t axis) const { return axes_.at(axis)->mode != Axis::Mode::kIdle; }

void VirtualMachine::MoveTo(std::size_t axis, double target_mm, double feed_mm_min) {
  if (feed_hold_) throw std::logic_error("MoveTo during feed hold would never arrive");
  CommandMove(axis, target_mm, feed_mm_min);
  const Axis& a = *axes_[axis];
  const double t_need = std::abs(a.target_mm - a.cmd_mm) / (feed_mm_min / 60.0);
  Advance(t_need);
  // Rounding can leave a hair of travel; finish it without advancing the clock noticeably.
  int guard = 0;
  while (a.mode == Axis::Mode::kMove && ++guard < 100) Advance(1e-6);
}

void VirtualMachine::Home(std::size_t axis) {
  Axis& a = *axes_.at(axis);
  const double ref = a.d.reference_mm;
  // Homing approaches the reference from the + side... then forward onto it.
  if (a.cmd_mm <= ref) MoveTo(axis, std::min(a.d.travel_mm, ref + 5), 3000);
  MoveTo(axis, std::max(0.0, ref - 5), 3000);
  MoveTo(axis, ref, 500);
  std::normal_distribution<double> nd(0, 1);
  a.homing_offset_um = nd(rng_) * a.d.homing_repeatability_um;
}

double VirtualMachine::HomingOffsetUm(std::size_t axis) const { return axes_.at(axis)->homing_offset_um; }
void VirtualMachine::SetHomingOffsetUm(std::size_t axis, double offset_um) { axes_.at(axis)->homing_offset_um = offset_um; }

double VirtualMachine::CommandedMm(std::size_t axis) const { return axes_.at(axis)->cmd_mm; }

double VirtualMachine::ThermalGrowthUm(std::size_t axis, double x_mm) const {
  const Axis& a = *axes_.at(axis);
  const double u = a.U(x_mm);
  const double alpha_um_per_mm = a.d.screw_cte_um_per_m_c * 1e-3;
  double integral = 0;  // ∫(T−20) ds over [0, u], mm·°C
  for (std::size_t i = 0; i < a.seg.size(); ++i) {
    const double covered = std::clamp(u - static_cast<double>(i) * a.seg_len_mm, 0.0, a.seg_len_mm);
    if (covered <= 0) break;
    integral += covered * (net_.Temperature(a.seg[i]) - kReferenceC);
  }
  return a.away * alpha_um_per_mm * integral;
}

double VirtualMachine::ErrorAtUm(std::size_t axis, double x_mm, int direction) const {
  const Axis& a = *axes_.at(axis);
  const double bed_um = a.away * a.d.bed_anchor_mm * d_.bed.cte_um_per_m_c * 1e-3 * (net_.Temperature(bed_node_) - kReferenceC);
  return a.pitch.ErrorUm(x_mm, direction) - direction * a.d.backlash_um / 2 + ThermalGrowthUm(axis, x_mm) + bed_um +
         a.homing_offset_um + a.extra_error_um;
}

double VirtualMachine::ActualMm(std::size_t axis) const {
  const Axis& a = *axes_.at(axis);
  const double m = MotorMm(a);
  const double half = a.d.backlash_um / 2000.0;
  int flank = a.servo_dir != 0 ? a.servo_dir : 1;
  if (half > 0 && a.play_mm <= -half + 1e-12) flank = 1;
  else if (half > 0 && a.play_mm >= half - 1e-12) flank = -1;
  const double bed_um = a.away * a.d.bed_anchor_mm * d_.bed.cte_um_per_m_c * 1e-3 * (net_.Temperature(bed_node_) - kReferenceC);
  const double err_um = a.pitch.ErrorUm(m, flank) + ThermalGrowthUm(axis, m) + bed_um + a.homing_offset_um + a.extra_error_um;
  return m + a.play_mm + err_um * 1e-3;
}

double VirtualMachine::CorrectionUm(std::size_t axis) const { return axes_.at(axis)->correction_um; }
void VirtualMachine::SetExtraErrorUm(std::size_t axis, double error_um) { axes_.at(axis)->extra_error_um = error_um; }
int VirtualMachine::ServoDirection(std::size_t axis) const { return axes_.at(axis)->servo_dir; }
double VirtualMachine::FeedNowMmMin(std::size_t axis) const { return axes_.at(axis)->speed_now; }

double VirtualMachine::TravelMm(std::size_t axis) const { return axes_.at(axis)->travel_mm; }

double VirtualMachine::NodeTemperatureC(const std::string& node) const {
  const std::size_t i = net_.FindNode(node);
  if (i == net_.NodeCount()) throw std::invalid_argument("no thermal node '" + node + "'");
  return net_.Temperature(i);
}

std::vector<std::string> VirtualMachine::NodeNames() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < net_.NodeCount(); ++i) out.push_back(net_.NodeName(i));
  return out;
}

double VirtualMachine::AmbientC() const { return ambient_.TemperatureC(UnixTimeS()); }

void VirtualMachine::Soak(double temp_c) {
  net_.SetAllTemperatures(temp_c);
  for (std::size_t i = 0; i < sensors_.size(); ++i) sensors_[i]->Reset(temp_c);
}

int VirtualMachine::SensorIndex(const std::string& name) const {
  for (std::size_t i = 0; i < sensors_.size(); ++i)
    if (sensors_[i]->description().name == name) return static_cast<int>(i);
  return -1;
}

bool VirtualMachine::SetSensorFault(const std::string& name, const SensorFault& fault) {
  const int i = SensorIndex(name);
  if (i < 0) return false;
  sensors_[i]->SetFault(fault, t_s_);
  return true;
}

bool VirtualMachine::ScheduleSensorFault(const std::string& name, const SensorFault& fault, double at_s) {
  const int i = SensorIndex(name);
  if (i < 0) return false;
  if (at_s <= t_s_) sensors_[static_cast<std::size_t>(i)]->SetFault(fault, t_s_);
  else scheduled_faults_.push_back({static_cast<std::size_t>(i), fault, at_s});
  return true;
}

std::string VirtualMachine::AxisName(std::size_t axis) const { return axes_.at(axis)->d.name; }

bool VirtualMachine::Read(std::span<hw::AxisState> axes, hw::CncState& machine) {
  if (link_fault_ || axes.size() < axes_.size()) return false;
  for (std::size_t i = 0; i < axes_.size(); ++i) {
    axes[i].position_mm = axes_[i]->cmd_mm;
    axes[i].servo_direction = axes_[i]->servo_dir;
    axes[i].moving = axes_[i]->speed_now > 0;
    axes[i].travel_mm = TravelMm(i);
    axes[i].programmed_direction = axes_[i]->servo_dir;  // the commanded motion's, held at standstill
  }
  machine.coolant = coolant_;
  machine.compensation_enabled = compensation_enabled_;
  return true;
}

bool VirtualMachine::WriteCompensation(std::span<const double> correction_um) {
  if (link_fault_ || correction_um.size() != axes_.size()) return false;
  for (double c : correction_um)
    if (!std::isfinite(c)) return false;
  if (!compensation_enabled_) return true;
  for (std::size_t i = 0; i < axes_.size(); ++i) {
    axes_[i]->correction_um = correction_um[i];
    // The servo direction the CNC reports stays that of the programmed
    // motion: a compensation that flipped it would make a direction-dependent
    // compensator chase its own output.
    UpdatePlay(*axes_[i]);
  }
  return true;
}

hw::MeasuringRange VirtualMachine::ChannelMeasuringRange(std::size_t channel) const {
  return SensorMeasuringRange(sensors_.at(channel)->description().kind);
}

std::string VirtualMachine::ChannelName(std::size_t channel) const { return sensors_.at(channel)->description().name; }

bool VirtualMachine::Read(std::span<hw::RawTemperature> out) {
  if (link_fault_ || out.size() < sensors_.size()) return false;
  for (std::size_t i = 0; i < sensors_.size(); ++i) out[i] = sensors_[i]->Latest();
  return true;
}

}  // namespace trueaxis::sim
