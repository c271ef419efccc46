#include "trueaxis/drivers/modbus_cnc_link.hpp"

#include <modbus.h>

#include <cerrno>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/drivers/register_codec.hpp"

namespace trueaxis::drivers {

bool ModbusCncLinkOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (!endpoint.IsValid(why)) return false;
  if (unit_id < 0 || unit_id > 255) return fail(fmt::format("unit_id {} is outside 0..255", unit_id));
  if (axis_names.empty() || axis_names.size() > pmc::kMaxAxes)
    return fail(fmt::format("axis_names must name 1..{} axes", pmc::kMaxAxes));
  if (!(stale_after_s > 0)) return fail("stale_after_s must be > 0");
  return true;
}

ModbusCncLink::ModbusCncLink(ModbusCncLinkOptions options)
    : options_(std::move(options)), connection_(options_.endpoint) {
  const std::size_t n = std::min(options_.axis_names.size(), pmc::kMaxAxes);
  window_.assign(pmc::InputWindowLength(n), 0);
  out_.assign(pmc::kHrCompensationStride * n, 0);
  applied_um_.assign(n, 0.0);
  std::string why;
  options_valid_ = options_.IsValid(&why);
  if (!options_valid_) error_ = "invalid ModbusCncLink options: " + why;
}

bool ModbusCncLink::Configure(std::string* error) {
  if (!options_valid_ && error) *error = error_;
  return options_valid_;
}

bool ModbusCncLink::Activate(std::string* error) {
  const bool ok = Connect();
  if (!ok && error) *error = last_error();
  return ok;
}

void ModbusCncLink::Deactivate() { connection_.Close(); }

bool ModbusCncLink::Connect() {
  return EnsureReady(/*ignore_throttle=*/true);
}

// Connects if needed and, on a fresh connection, checks the window's layout.
bool ModbusCncLink::EnsureReady(bool ignore_throttle) {
  if (!options_valid_) return false;
  bool fresh = false;
  if (!connection_.Ensure(&fresh, ignore_throttle)) return false;
  if (!fresh) return true;
  std::uint16_t head[2];
  if (!connection_.ReadInputRegisters(options_.unit_id, pmc::kIrLayoutVersion, 2, head)) return false;
  if (head[0] != pmc::kLayoutVersion || head[1] != options_.axis_names.size()) {
    error_ = fmt::format("{}:{} unit {}: PMC window layout {} with {} axes, expected layout {} with {} axes",
                         options_.endpoint.host, options_.endpoint.port, options_.unit_id, head[0], head[1],
                         pmc::kLayoutVersion, options_.axis_names.size());
    errno = EMBBADDATA;
    connection_.Fault("handshake");
    return false;
  }
  error_.clear();
  have_heartbeat_ = false;
  return true;
}

bool ModbusCncLink::Read(std::span<hw::AxisState> axes, hw::CncState& machine) {
  const std::size_t n = AxisCount();
  if (axes.size() < n) return false;
  if (!EnsureReady()) return false;
  if (!connection_.ReadInputRegisters(options_.unit_id, 0, static_cast<int>(window_.size()), window_.data())) return false;
  const auto now = std::chrono::steady_clock::now();
  const std::uint32_t hb = JoinUint32(&window_[pmc::kIrHeartbeatHi]);
  if (!have_heartbeat_ || hb != heartbeat_) {
    heartbeat_ = hb;
    have_heartbeat_ = true;
    heartbeat_changed_ = now;
  } else if (std::chrono::duration<double>(now - heartbeat_changed_).count() > options_.stale_after_s) {
    return false;  // the terminal answers, but its machine side has stopped
  }
  const std::uint16_t status = window_[pmc::kIrStatus];
  if (!(status & pmc::kStatusMachineReadOk)) return false;
  const auto coolant = CoolantStateFromCode(window_[pmc::kIrCoolant]);
  if (!coolant) return false;
  for (std::size_t a = 0; a < n; ++a) {
    const std::uint16_t* r = &window_[pmc::InputAxisRegister(a, 0)];
    axes[a].position_mm = CountsToMillimetres(JoinInt32(r + pmc::kIrAxisPositionHi));
    axes[a].servo_direction = static_cast<std::int16_t>(r[pmc::kIrAxisDirection]);
    axes[a].moving = r[pmc::kIrAxisMoving] != 0;
    axes[a].programmed_direction = pmc::ProgrammedDirection(window_[pmc::kIrProgrammedDirection], a);
    axes[a].travel_mm = static_cast<double>(JoinUint32(r + pmc::kIrAxisTravelHi));
    applied_um_[a] = CountsToMicrometres(JoinInt32(r + pmc::kIrAxisAppliedHi));
    axes[a].applied_um = applied_um_[a];
  }
  machine.coolant = *coolant;
  machine.compensation_enabled = (status & pmc::kStatusCompensationEnabled) != 0;
  return true;
}

bool ModbusCncLink::WriteCompensation(std::span<const double> correction_um) {
  const std::size_t n = AxisCount();
  if (correction_um.size() != n) return false;
  for (std::size_t a = 0; a < n; ++a) {
    std::int32_t c = 0;
    if (!MicrometresToCounts(correction_um[a], &c)) return false;  // NaN or absurd: never sent
    SplitInt32(c, &out_[pmc::kHrCompensationStride * a]);
  }
  if (!EnsureReady()) return false;
  return connection_.WriteRegisters(options_.unit_id, pmc::kHrCompensationBase, static_cast<int>(out_.size()), out_.data());
}

}  // namespace trueaxis::drivers
