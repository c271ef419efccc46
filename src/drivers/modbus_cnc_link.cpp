#include "trueaxis/drivers/modbus_cnc_link.hpp"

#include <modbus.h>

#include <cerrno>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/drivers/terminal_registers.hpp"

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
  out_.assign(CommandBlockLength(n), 0);
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
  if (!PmcLayoutMatches(head, options_.axis_names.size())) {
    error_ = fmt::format("{}:{} unit {}: PMC window layout {} with {} axes, expected layout {} with {} axes",
                         options_.endpoint.host, options_.endpoint.port, options_.unit_id, head[0], head[1],
                         pmc::kLayoutVersion, options_.axis_names.size());
    errno = EMBBADDATA;
    connection_.Fault("handshake");
    return false;
  }
  error_.clear();
  heartbeat_.Reset();
  read_write_ = ReadWrite::kUnknown;  // the terminal behind the address may have changed
  return true;
}

bool ModbusCncLink::Read(std::span<hw::AxisState> axes, hw::CncState& machine) {
  const std::size_t n = AxisCount();
  if (axes.size() < n) return false;
  if (!EnsureReady()) return false;
  if (!connection_.ReadInputRegisters(options_.unit_id, 0, static_cast<int>(window_.size()), window_.data())) return false;
  return DecodeWindow(axes, machine);
}

bool ModbusCncLink::DecodeWindow(std::span<hw::AxisState> axes, hw::CncState& machine) {
  const std::size_t n = AxisCount();
  const double now_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  const std::uint32_t hb = JoinUint32(&window_[pmc::kIrHeartbeatHi]);
  // A frozen heartbeat: the terminal answers, but its machine side has stopped.
  if (!heartbeat_.Fresh(hb, now_s, options_.stale_after_s)) return false;
  if (!(window_[pmc::kIrStatus] & pmc::kStatusMachineReadOk) || !CoolantStateFromCode(window_[pmc::kIrCoolant]))
    return false;  // stale, or a coolant code no state has: `axes` and `machine` stay untouched
  DecodePmcWindow(window_.data(), axes.first(n), machine, applied_um_);
  for (std::size_t a = 0; a < n; ++a) axes[a].applied_um = applied_um_[a];  // what the CNC applies (pick-up)
  return true;
}

bool ModbusCncLink::WriteCompensation(std::span<const double> correction_um) {
  const std::size_t n = AxisCount();
  if (correction_um.size() != n) return false;
  if (!EncodeCommand(correction_um, out_.data())) return false;  // NaN or absurd: never sent
  if (!EnsureReady()) return false;
  return connection_.WriteRegisters(options_.unit_id, pmc::kHrCompensationBase, static_cast<int>(out_.size()), out_.data());
}

bool ModbusCncLink::WriteAndRead(std::span<const double> correction_um, std::span<hw::AxisState> axes,
                                 hw::CncState& machine) {
  const std::size_t n = AxisCount();
  if (correction_um.size() != n || axes.size() < n) return false;
  if (!EncodeCommand(correction_um, out_.data())) return false;  // NaN or absurd: never sent
  if (!EnsureReady()) return false;
  if (read_write_ != ReadWrite::kRefused) {
    if (connection_.WriteAndReadRegisters(options_.unit_id, pmc::kHrCompensationBase, static_cast<int>(out_.size()),
                                          out_.data(), pmc::kHrWindowCopyBase, static_cast<int>(window_.size()),
                                          window_.data())) {
      read_write_ = ReadWrite::kAnswered;
      return DecodeWindow(axes, machine);
    }
    const int ex = connection_.last_exception();
    if (ex != MODBUS_EXCEPTION_ILLEGAL_FUNCTION && ex != MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS) return false;
    read_write_ = ReadWrite::kRefused;  // a terminal without FC 23 or without the window's copy
  }
  return WriteCompensation(correction_um) && Read(axes, machine);
}

}  // namespace trueaxis::drivers
