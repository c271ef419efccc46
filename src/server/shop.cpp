#include "trueaxis/server/shop.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <queue>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/drivers/event_loop.hpp"
#include "trueaxis/drivers/mbap.hpp"
#include "trueaxis/drivers/open_file_limit.hpp"
#include "trueaxis/drivers/terminal_registers.hpp"
#include "trueaxis/drivers/thread_cpu.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"
#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/server/terminal_hardware.hpp"
#include "trueaxis/station/history_logger.hpp"
#include "trueaxis/station/installation.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace trueaxis::server {
namespace {

namespace pmc = drivers::pmc;
namespace adam = drivers::adam6015;
namespace mbap = drivers::mbap;
using drivers::EnsureOpenFileLimit;
using drivers::EventLoop;
using drivers::ThreadCpuSeconds;
using Clock = std::chrono::steady_clock;
constexpr double kBatchS = 0.002;  // the event loop's pass: ticks may start and answers be taken this much late

double UnixNowS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// What a cycle is doing: the request in flight belongs to this phase.
enum class Phase { kIdle, kConfig, kWindow, kReadWrite, kTemperatures, kWrite };
const char* PhaseName(Phase p) {
  switch (p) {
    case Phase::kIdle: return "idle";
    case Phase::kConfig: return "reading the ADAM-6015 type codes";
    case Phase::kWindow: return "reading the PMC window";
    case Phase::kReadWrite: return "writing the compensation and reading the PMC window (FC 23)";
    case Phase::kTemperatures: return "reading the ADAM-6015 AI values";
    case Phase::kWrite: return "writing the compensation";
  }
  return "?";
}
enum class Link { kDown, kConnecting, kOpen };
// Whether the terminal answers FC 23 (write the command block, read the window's copy) on this
// connection: until it refuses it (exception 0x01 or 0x02), a cycle is one transaction.
enum class ReadWrite { kUnknown, kAnswered, kRefused };

// Read → write latencies without storing them: 40 logarithmic buckets per decade from 10 µs
// (each 6 % wide) to 100 s; a percentile is the upper edge of its bucket.
class LatencyHistogram {
 public:
  static constexpr int kBuckets = 280;
  static double UpperEdgeMs(int k) { return 0.01 * std::pow(10.0, k / 40.0); }
  void Add(double ms) {
    const int k = ms <= 0.01 ? 0 : static_cast<int>(std::ceil(40.0 * std::log10(ms / 0.01) - 1e-9));
    ++counts_[static_cast<std::size_t>(std::clamp(k, 0, kBuckets - 1))];
    ++total_;
    max_ms_ = std::max(max_ms_, ms);
  }
  void Clear() { *this = LatencyHistogram(); }
  void Merge(const LatencyHistogram& o) {
    for (std::size_t k = 0; k < counts_.size(); ++k) counts_[k] += o.counts_[k];
    total_ += o.total_;
    max_ms_ = std::max(max_ms_, o.max_ms_);
  }
  std::uint64_t total() const { return total_; }
  double max_ms() const { return max_ms_; }
  double Quantile(double q) const {
    const auto want = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(total_)));
    std::uint64_t seen = 0;
    for (int k = 0; k < kBuckets; ++k)
      if ((seen += counts_[static_cast<std::size_t>(k)]) >= std::max<std::uint64_t>(want, 1)) return std::min(UpperEdgeMs(k), max_ms_);
    return max_ms_;
  }
  std::vector<std::pair<double, std::uint64_t>> NonEmpty() const {
    std::vector<std::pair<double, std::uint64_t>> out;
    for (int k = 0; k < kBuckets; ++k)
      if (counts_[static_cast<std::size_t>(k)]) out.emplace_back(UpperEdgeMs(k), counts_[static_cast<std::size_t>(k)]);
    return out;
  }

 private:
  std::array<std::uint64_t, kBuckets> counts_{};
  std::uint64_t total_ = 0;
  double max_ms_ = 0;
};

struct ModelEntry {
  station::PublishedModel model;
  ModelInfo info;
};

int RevisionOf(const station::PublishedModel& m) { return m.composite ? m.composite->revision : 0; }

// A registered change of the controls, applied by the machine's loop thread at the next cycle.
struct Controls {
  std::vector<std::uint8_t> axis_enabled;
  std::optional<CoolantState> coolant_override;
};

struct Timer {
  double due_s;
  std::uint32_t machine;
  bool tick;                 // else a request / connect deadline
  std::uint64_t generation;  // deadlines: valid while the machine's generation matches
  bool operator>(const Timer& o) const { return due_s > o.due_s; }
};

// One polling thread ([server] poll_threads): its epoll set, its timers and its share of the
// shop's counters. Machine i belongs to thread i mod K for good: no other loop thread touches
// anything of it, and the counters here are written by this thread only (read under stats_mu and
// summed by Shop::Stats).
struct Poller {
  EventLoop loop;
  int epoll_fd = loop.epoll_fd();
  std::priority_queue<Timer, std::vector<Timer>, std::greater<Timer>> timers;
  mutable std::mutex stats_mu;
  LatencyHistogram latency;
  ShopStats totals;  // cycles, complete_cycles, faults, overruns
};

}  // namespace

// One machine: its terminal link, its compensator state and its published status.
struct MachineSlot {
  explicit MachineSlot(const MachineConfig& c) : cfg(c) {}
  const MachineConfig& cfg;  // the shop's own (Shop::config_ outlives every slot): not a copy per machine
  std::size_t index = 0;
  sockaddr_in addr{};
  std::size_t module_count = 0;
  Poller* poller = nullptr;  // the loop thread that owns this machine

  // ---- its loop thread only ----
  Link link = Link::kDown;
  int fd = -1;
  Phase phase = Phase::kIdle;
  ReadWrite read_write = ReadWrite::kUnknown;
  bool write_pending = false;       // the last step's command waits for this cycle's FC 23
  bool cycle_written = false;       // this cycle's FC 23 wrote the command (a complete cycle once stepped)
  std::uint32_t published_alarms = ~0u;  // alarm_names of the status were made for these bits
  std::size_t module = 0;           // ADAM module of the request in flight
  mbap::Request request;
  std::uint16_t next_transaction = 1;
  std::uint64_t deadline_generation = 0;
  std::uint8_t in[mbap::kMaxFrameBytes * 2];
  std::size_t in_len = 0;
  std::uint16_t registers[mbap::kMaxReadRegisters];
  double next_tick_s = 0;
  double cycle_start_s = 0;
  double reconnect_at_s = 0;
  double backoff_s = 0;
  bool ranges_known = false;
  std::vector<const adam::RtdRange*> ranges;  // per channel
  bool cnc_ok = false, temps_ok = false;
  bool temps_read = false;          // this cycle reads the ADAM-6015 modules (every temperature_period_s)
  double temps_read_s = -1e9;       // when they were last read
  drivers::HeartbeatWatch heartbeat;  // a frozen heartbeat: the terminal's machine side has stopped
  std::vector<double> applied_um;   // what the CNC applies, as the window reports (µm)
  // The machine's asynchronous hardware (decoded registers) and its installation: the temperature
  // pipeline, the compensator (pick-up without a jump), the model — the same assembly as `run`'s.
  std::unique_ptr<TerminalCnc> cnc;
  std::unique_ptr<TerminalTemperatures> temps;
  std::unique_ptr<station::Installation> installation;
  Controls controls;
  std::unique_ptr<station::HistoryLogger> logger;
  double next_record_s = 0;
  std::uint32_t logged_alarms = 0;
  std::uint64_t cycles = 0, complete_cycles = 0, faults = 0, connects = 0, overruns = 0;
  double last_good_read_unix_s = 0;
  double last_latency_ms = 0;
  std::string last_fault;

  // ---- shared, under mu ----
  mutable std::mutex mu;
  MachineStatus status;
  Controls wanted;                  // written by the API, copied by the loop each cycle
  ModelInfo model_info;             // the model in force (the loop ramps to a new one)
  std::vector<ModelEntry> models;   // every model this machine has had, in order
  std::size_t current_model = 0;
  std::vector<ModelChange> changes;
};

struct Shop::Impl {
  ShopConfig& config;
  store::HistoryWriter* history = nullptr;
  std::vector<std::unique_ptr<MachineSlot>> machines;  // fixed once constructed: loop threads index it
  std::vector<std::unique_ptr<Poller>> pollers;         // machine i → pollers[i % size]
  Clock::time_point t0 = Clock::now();
  double unix_offset_s = UnixNowS();  // unix time = loop time + offset
  std::mutex audit_mu;

  explicit Impl(ShopConfig& c) : config(c) {}

  double Now() const { return std::chrono::duration<double>(Clock::now() - t0).count(); }

  // Before the change takes effect: a change whose audit line cannot be written is refused.
  void Audit(const ModelChange& c) {
    if (config.audit_log.empty()) return;
    nlohmann::json j = {{"time_unix_s", c.time_unix_s}, {"machine", c.machine}, {"action", c.action},
                        {"user", c.user},               {"from", c.from},       {"old_file", c.old_model.file},
                        {"old_sha256", c.old_model.sha256}, {"old_revision", c.old_model.revision},
                        {"new_file", c.new_model.file}, {"new_sha256", c.new_model.sha256},
                        {"new_revision", c.new_model.revision}};
    std::lock_guard<std::mutex> lock(audit_mu);
    FILE* f = std::fopen(config.audit_log.c_str(), "a");
    const int open_errno = errno;
    bool ok = f != nullptr;
    if (f) {
      const std::string line = j.dump() + "\n";
      ok = std::fwrite(line.data(), 1, line.size(), f) == line.size() && std::fflush(f) == 0;
      ok = fsync(fileno(f)) == 0 && ok;  // a model change is never lost, even across kill -9
      ok = std::fclose(f) == 0 && ok;
    }
    if (!ok) {
      const std::string why = fmt::format("{}: cannot append the audit line ({}): the {} of '{}' is refused", config.audit_log,
                                          std::strerror(f ? errno : open_errno), c.action, c.machine);
      fmt::print(stderr, "trueaxis server: {}\n", why);
      throw InputError(config.source, config.audit_log_line, "audit_log", why);
    }
  }

  void RecordChange(MachineSlot& m, const ModelChange& c) {
    if (history)
      history->PushModelChange(c.time_unix_s, c.new_model.sha256, std::to_string(c.new_model.revision),
                               fmt::format("{} {} by {} from {}: rev {} ({}) -> rev {} ({})", m.cfg.name, c.action,
                                           c.user, c.from, c.old_model.revision, c.old_model.sha256.substr(0, 12),
                                           c.new_model.revision, c.new_model.sha256.substr(0, 12)));
  }

  // ------------------------------------------------------------ status
  void Publish(MachineSlot& m) {
    const runtime::StepOutputs& o = m.installation->compensator().LastOutputs();
    std::lock_guard<std::mutex> lock(m.mu);
    MachineStatus& s = m.status;
    s.connected = m.link == Link::kOpen;
    s.last_good_read_unix_s = m.last_good_read_unix_s;
    s.alarms = o.status.alarms;
    if (m.published_alarms != o.status.alarms) {  // the names only when the bits change: no allocation per cycle
      s.alarm_names = runtime::AlarmNames(o.status.alarms);
      m.published_alarms = o.status.alarms;
    }
    s.unacknowledged |= o.status.alarms;
    if (s.last_fault != m.last_fault) s.last_fault = m.last_fault;
    s.cycles = m.cycles;
    s.complete_cycles = m.complete_cycles;
    s.faults = m.faults;
    s.connects = m.connects;
    s.overruns = m.overruns;
    s.last_latency_ms = m.last_latency_ms;
    s.coolant = CoolantStateName(o.status.coolant);
    if (m.controls.coolant_override) s.coolant_override = CoolantStateName(*m.controls.coolant_override);
    else s.coolant_override.reset();
    s.model = m.model_info;
    const bool fresh = s.connected && m.cnc_ok;
    for (std::size_t a = 0; a < s.axes.size(); ++a) {
      AxisView& v = s.axes[a];
      v.position_mm = fresh ? Reading(m.cnc->axes[a].position_mm) : std::nullopt;
      v.applied_um = fresh ? Reading(m.cnc->axes[a].applied_um) : std::nullopt;
      v.target_um = o.axes[a].desired_um;
      v.output_um = o.axes[a].output_um;
      v.enabled = m.controls.axis_enabled[a] != 0;
      v.state = runtime::AxisCompensationState(fresh, o.axes[a].enabled, o.axes[a].thermal_used, o.axes[a].fallback_model);
    }
    for (std::size_t c = 0; c < s.channels.size(); ++c) {
      ChannelView& v = s.channels[c];
      const auto& judged = m.installation->temperature_snapshot().channels[c];  // filtered, calibrated, judged
      v.temp_c = (s.connected && m.temps_ok && judged.usable()) ? Reading(judged.value_c) : std::nullopt;
      v.health = station::ChannelHealthName(o.channels[c].health);
    }
  }

  // ------------------------------------------------------------ the compensator
  // The machine's cycle, once its reads are complete (or its link is down): the installation reads
  // what was decoded, filters the temperatures (only when new ones came), and steps.
  void RunStep(MachineSlot& m, double now) {
    m.cnc->ok = m.cnc_ok;
    m.temps->ok = m.temps_ok;
    if (m.temps_read && m.temps_ok) m.temps_read_s = now;
    if (m.cnc_ok) m.last_good_read_unix_s = now + unix_offset_s;
    {
      std::lock_guard<std::mutex> lock(m.mu);
      m.controls = m.wanted;
    }
    runtime::Compensator& comp = m.installation->compensator();
    for (std::size_t a = 0; a < m.controls.axis_enabled.size(); ++a) comp.SetAxisEnabled(a, m.controls.axis_enabled[a] != 0);
    m.cnc->coolant_override = m.controls.coolant_override;
    m.installation->Cycle(now, m.temps_read || !m.temps_ok);
  }

  void AfterStep(MachineSlot& m, double now) {
    Publish(m);
    if (!m.logger) return;
    const runtime::CycleStatus& status = m.installation->compensator().LastStatus();
    const std::uint32_t alarms = status.alarms;
    if (now < m.next_record_s && alarms == m.logged_alarms) return;
    m.next_record_s = std::max(m.next_record_s + config.record_interval_s, now);
    m.logged_alarms = alarms;
    runtime::CycleRecord rec;
    runtime::FillRecord(status, rec);
    if (!m.cnc_ok)
      for (std::size_t a = 0; a < rec.axis_count; ++a) rec.axes[a].cnc_position_mm = std::nan("");  // UNAVAILABLE
    m.logger->Log(rec);
  }

  // ------------------------------------------------------------ link
  void PushDeadline(MachineSlot& m, double due) {
    m.poller->timers.push({due, static_cast<std::uint32_t>(m.index), false, ++m.deadline_generation});
  }

  void CloseLink(MachineSlot& m) {
    if (m.fd >= 0) {
      epoll_ctl(m.poller->epoll_fd, EPOLL_CTL_DEL, m.fd, nullptr);
      close(m.fd);
    }
    m.fd = -1;
    m.link = Link::kDown;
    m.phase = Phase::kIdle;
    m.in_len = 0;
    m.write_pending = false;  // never written: the compensator's shaper still holds what the CNC has
    ++m.deadline_generation;
  }

  void Fault(MachineSlot& m, double now, const std::string& why) {
    const bool was_open = m.link == Link::kOpen;
    CloseLink(m);
    m.cnc_ok = m.temps_ok = false;
    m.temps_read_s = -1e9;
    m.ranges_known = false;
    m.backoff_s = m.backoff_s <= 0 ? m.cfg.min_backoff_s : std::min(2 * m.backoff_s, m.cfg.max_backoff_s);
    m.reconnect_at_s = now + m.backoff_s;
    ++m.faults;
    m.last_fault = why;
    {
      std::lock_guard<std::mutex> lock(m.poller->stats_mu);
      ++m.poller->totals.faults;
    }
    if (history && (was_open || m.faults == 1 || m.backoff_s >= m.cfg.max_backoff_s))
      history->PushAlarm(now + unix_offset_s, "warning", m.cfg.name,
                         fmt::format("terminal {}:{}: {} (retry in {:.2f} s)", m.cfg.host, m.cfg.port, why, m.backoff_s));
    std::lock_guard<std::mutex> lock(m.mu);
    m.status.connected = false;
    m.status.last_fault = why;
    m.status.faults = m.faults;
    for (auto& a : m.status.axes) a.position_mm = a.applied_um = std::nullopt;
    for (auto& c : m.status.channels) c.temp_c = std::nullopt;
  }

  void Connect(MachineSlot& m, double now) {
    m.fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (m.fd < 0) return Fault(m, now, fmt::format("socket: {}", std::strerror(errno)));
    int one = 1;
    setsockopt(m.fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    epoll_event ev{};
    ev.events = EPOLLOUT | EPOLLIN;
    ev.data.u64 = m.index;
    if (epoll_ctl(m.poller->epoll_fd, EPOLL_CTL_ADD, m.fd, &ev) != 0) return Fault(m, now, fmt::format("epoll: {}", std::strerror(errno)));
    m.link = Link::kConnecting;
    if (connect(m.fd, reinterpret_cast<const sockaddr*>(&m.addr), sizeof m.addr) != 0 && errno != EINPROGRESS)
      return Fault(m, now, fmt::format("connect: {}", std::strerror(errno)));
    PushDeadline(m, now + m.cfg.connect_timeout_s);
  }

  void OnConnected(MachineSlot& m, double now) {
    int err = 0;
    socklen_t len = sizeof err;
    if (getsockopt(m.fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0 || err != 0)
      return Fault(m, now, fmt::format("connect: {}", std::strerror(err ? err : errno)));
    epoll_event ev{};
    ev.events = EPOLLIN | EPOLLRDHUP;
    ev.data.u64 = m.index;
    epoll_ctl(m.poller->epoll_fd, EPOLL_CTL_MOD, m.fd, &ev);
    m.link = Link::kOpen;
    ++m.deadline_generation;
    ++m.connects;
    m.ranges_known = false;
    m.read_write = ReadWrite::kUnknown;  // a new terminal (or a new firmware) may answer FC 23 again
    if (history && m.faults > 0)
      history->PushAlarm(now + unix_offset_s, "info", m.cfg.name, fmt::format("terminal {}:{}: connected", m.cfg.host, m.cfg.port));
  }

  void Send(MachineSlot& m, double now) {
    std::uint8_t frame[mbap::kMaxFrameBytes];
    std::size_t len = 0;
    mbap::Request& r = m.request;
    r.transaction = m.next_transaction++;
    const std::size_t axes = m.cfg.axes.size();
    std::uint16_t values[drivers::CommandBlockLength(pmc::kMaxAxes)];  // the command block of a write
    if ((m.phase == Phase::kWrite || m.phase == Phase::kReadWrite) &&
        !drivers::EncodeCommand({m.installation->command().correction_um.data(), axes}, values))
      return Fault(m, now, "a correction that cannot be sent (not a number or beyond ±214 m)");
    switch (m.phase) {
      case Phase::kConfig:
        r.unit = static_cast<std::uint8_t>(m.cfg.first_rtd_unit_id + m.module);
        r.function = mbap::kReadHoldingRegisters;
        r.address = adam::kTypeCodeAddress;
        r.count = adam::kChannelEnableAddress - adam::kTypeCodeAddress + 1;
        break;
      case Phase::kWindow:
        r.unit = static_cast<std::uint8_t>(m.cfg.pmc_unit_id);
        r.function = mbap::kReadInputRegisters;
        r.address = 0;
        r.count = static_cast<std::uint16_t>(pmc::InputWindowLength(axes));
        break;
      case Phase::kReadWrite:  // the last step's command, then the window's copy, in one transaction
        r.unit = static_cast<std::uint8_t>(m.cfg.pmc_unit_id);
        r.function = mbap::kReadWriteMultipleRegisters;
        r.address = pmc::kHrWindowCopyBase;
        r.count = static_cast<std::uint16_t>(pmc::InputWindowLength(axes));
        len = mbap::EncodeWriteAndRead(frame, r.transaction, r.unit, r.address, r.count, pmc::kHrCompensationBase,
                                       {values, static_cast<std::size_t>(drivers::CommandBlockLength(axes))});
        break;
      case Phase::kTemperatures:
        r.unit = static_cast<std::uint8_t>(m.cfg.first_rtd_unit_id + m.module);
        r.function = mbap::kReadHoldingRegisters;
        r.address = adam::kAiValueAddress;
        r.count = static_cast<std::uint16_t>(ModuleChannels(m, m.module));
        break;
      case Phase::kWrite:
        r.unit = static_cast<std::uint8_t>(m.cfg.pmc_unit_id);
        r.function = mbap::kWriteMultipleRegisters;
        r.address = pmc::kHrCompensationBase;
        r.count = static_cast<std::uint16_t>(drivers::CommandBlockLength(axes));
        len = mbap::EncodeWriteRegisters(frame, r.transaction, r.unit, r.address, {values, r.count});
        break;
      case Phase::kIdle:
        return;
    }
    if (len == 0) len = mbap::EncodeRead(frame, r.transaction, r.unit, r.function, r.address, r.count);
    const ssize_t n = send(m.fd, frame, len, MSG_NOSIGNAL);
    if (n != static_cast<ssize_t>(len))
      return Fault(m, now, fmt::format("send failed while {}: {}", PhaseName(m.phase), n < 0 ? std::strerror(errno) : "short write"));
    PushDeadline(m, now + m.cfg.response_timeout_s);
  }

  static std::size_t ModuleChannels(const MachineSlot& m, std::size_t k) {
    return drivers::RtdModuleChannels(m.cfg.channels.size(), k);
  }

  void BeginCycle(MachineSlot& m, double now) {
    m.cycle_start_s = now;
    m.cnc_ok = false;
    // Temperatures every temperature_period_s (half a period early rather than a period late).
    m.temps_read = m.module_count > 0 && now - m.temps_read_s >= m.cfg.temperature_period_s - 0.5 * m.cfg.period_s;
    m.temps_ok = m.temps_read ? true : m.temps->ok;
    m.cycle_written = false;
    m.module = 0;
    if (!m.ranges_known && m.module_count > 0) {
      m.phase = Phase::kConfig;
      return Send(m, now);
    }
    SendWindow(m, now);
  }

  // The window: with the pending command in one FC 23 where the terminal takes it, else FC 04.
  void SendWindow(MachineSlot& m, double now) {
    m.phase = (m.write_pending && m.read_write != ReadWrite::kRefused) ? Phase::kReadWrite : Phase::kWindow;
    Send(m, now);
  }

  // After the reads: the step, then the write (which also refreshes the terminal's watchdog): with
  // the next cycle's FC 23 where the terminal answers it (one transaction per cycle: the command
  // reaches the CNC one period after its step), else at once with FC 16.
  void StepAndWrite(MachineSlot& m, double now) {
    RunStep(m, now);
    if (m.installation->compensator().PickUpPending()) {  // no applied values read yet since the connect: writing could jump
      m.installation->CommitWrite(false);
      AfterStep(m, now);
      m.phase = Phase::kIdle;
      m.write_pending = false;
      return;
    }
    AfterStep(m, now);
    if (m.read_write == ReadWrite::kRefused) {
      m.phase = Phase::kWrite;
      return Send(m, now);
    }
    m.phase = Phase::kIdle;
    m.write_pending = true;
    if (m.cycle_written) CycleComplete(m, now);
  }

  // A cycle whose reads, step and write were answered.
  void CycleComplete(MachineSlot& m, double now) {
    ++m.complete_cycles;
    m.backoff_s = 0;
    m.last_latency_ms = (now - m.cycle_start_s) * 1000.0;
    std::lock_guard<std::mutex> lock(m.poller->stats_mu);
    ++m.poller->totals.complete_cycles;
    m.poller->latency.Add(m.last_latency_ms);
  }

  void OnFrame(MachineSlot& m, std::span<const std::uint8_t> frame, double now) {
    std::uint8_t exception = 0;
    const mbap::Reply reply = mbap::ParseReply(frame, m.request, m.registers, nullptr, &exception);
    ++m.deadline_generation;  // answered: its deadline no longer applies
    if (reply == mbap::Reply::kMismatch || reply == mbap::Reply::kMalformed) {
      const int unit = frame.size() > 6 ? frame[6] : -1;
      return Fault(m, now, fmt::format("{} while {} (asked unit {} fc {}, got unit {} fc {})", mbap::ReplyName(reply),
                                       PhaseName(m.phase), m.request.unit, m.request.function, unit,
                                       frame.size() > 7 ? frame[7] : -1));
    }
    const bool ok = reply == mbap::Reply::kOk;
    switch (m.phase) {
      case Phase::kConfig:
        if (ok) {
          if (m.registers[adam::kModuleNameAddress - adam::kTypeCodeAddress] != adam::kModuleName)
            return Fault(m, now, fmt::format("unit {} is not an ADAM-6015 (name register 0x{:04X})", m.request.unit,
                                             m.registers[adam::kModuleNameAddress - adam::kTypeCodeAddress]));
          for (std::size_t c = 0; c < ModuleChannels(m, m.module); ++c) {
            const auto* range = drivers::FindRtdRange(m.registers[c]);
            if (!range)
              return Fault(m, now, fmt::format("unit {} channel {}: unknown RTD type code 0x{:04X}", m.request.unit, c, m.registers[c]));
            m.ranges[m.module * adam::kChannelCount + c] = range;
          }
        } else {
          m.temps_ok = false;  // the module does not answer now; its ranges are read again next cycle
        }
        if (ok && ++m.module < m.module_count) return Send(m, now);
        m.ranges_known = ok;
        m.module = 0;
        return SendWindow(m, now);
      case Phase::kReadWrite:
        if (reply == mbap::Reply::kException &&
            (exception == mbap::kIllegalFunction || exception == mbap::kIllegalDataAddress)) {
          // No FC 23 (or no window copy) on this terminal: FC 04 + FC 16 until the next reconnect. Nothing
          // was written (a refused request writes nothing): the pending command is dropped, the step runs again.
          m.read_write = ReadWrite::kRefused;
          m.write_pending = false;
          fmt::print(stderr,
                     "trueaxis server: machine '{}': the terminal refuses FC 23 (exception {:#04x}): two transactions a "
                     "cycle (FC 04 + FC 16) until it reconnects\n",
                     m.cfg.name, exception);
          m.phase = Phase::kWindow;
          return Send(m, now);
        }
        m.read_write = ReadWrite::kAnswered;
        m.write_pending = false;
        m.installation->CommitWrite(ok);  // the previous step's command: written, or refused (alarm link_write)
        m.cycle_written = ok;
        if (!ok) {  // refused (e.g. 0x03, beyond the terminal's bound): nothing was read either; read the window alone
          m.phase = Phase::kWindow;
          return Send(m, now);
        }
        [[fallthrough]];
      case Phase::kWindow:
        if (ok && !DecodeWindow(m, now)) return;
        if (!ok) m.cnc_ok = false;
        if (m.temps_read && m.ranges_known) {
          m.phase = Phase::kTemperatures;
          m.module = 0;
          return Send(m, now);
        }
        if (m.temps_read) m.temps_ok = m.cfg.channels.empty();  // the modules' ranges are unknown: no reading
        return StepAndWrite(m, now);
      case Phase::kTemperatures:
        if (ok) {
          DecodeTemperatures(m);
        } else {
          m.temps_ok = false;
        }
        if (++m.module < m.module_count) return Send(m, now);
        return StepAndWrite(m, now);
      case Phase::kWrite:
        m.installation->CommitWrite(ok);
        m.phase = Phase::kIdle;
        if (ok) CycleComplete(m, now);
        return;
      case Phase::kIdle:
        return Fault(m, now, "unsolicited data from the terminal");
    }
  }

  // Register decoding (the terminal's maps, docs/protocols.md) into the machine's asynchronous
  // hardware: the AI values of the module just read, and the PMC window.
  void DecodeTemperatures(MachineSlot& m) {
    for (std::size_t c = 0; c < ModuleChannels(m, m.module); ++c) {
      const std::size_t ch = m.module * adam::kChannelCount + c;
      m.temps->channels[ch] = drivers::DecodeRtdChannel(m.registers[c], false, *m.ranges[ch]);
    }
  }

  // False after a fault (the window does not match the shop file).
  bool DecodeWindow(MachineSlot& m, double now) {
    const std::uint16_t* r = m.registers;
    const std::size_t axes = m.cfg.axes.size();
    if (!drivers::PmcLayoutMatches(r, axes)) {
      Fault(m, now, fmt::format("PMC window layout {} with {} axes; the shop file expects layout {} with {} axes",
                                r[pmc::kIrLayoutVersion], r[pmc::kIrAxisCount], pmc::kLayoutVersion, axes));
      return false;
    }
    const drivers::PmcWindow w = drivers::DecodePmcWindow(r, std::span(m.cnc->axes).first(axes), m.cnc->machine, m.applied_um);
    for (std::size_t a = 0; a < axes; ++a) m.cnc->axes[a].applied_um = m.applied_um[a];  // the pick-up without a jump
    const bool fresh = m.heartbeat.Fresh(w.heartbeat, now, std::max(0.5, 5 * m.cfg.period_s));
    // a coolant code no state has is not read as "off": the cycle treats the CNC as not read
    m.cnc_ok = w.machine_read_ok() && w.coolant_known && fresh;
    return true;
  }

  void OnReadable(MachineSlot& m, double now) {
    for (;;) {
      const ssize_t n = recv(m.fd, m.in + m.in_len, sizeof m.in - m.in_len, 0);
      if (n == 0) return Fault(m, now, fmt::format("connection closed by the terminal while {}", PhaseName(m.phase)));
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK) break;
        if (errno == EINTR) continue;
        return Fault(m, now, fmt::format("recv: {}", std::strerror(errno)));
      }
      const bool drained = static_cast<std::size_t>(n) < sizeof m.in - m.in_len;  // no second recv to hear EAGAIN
      m.in_len += static_cast<std::size_t>(n);
      if (drained || m.in_len == sizeof m.in) break;  // the event is level-triggered: more data wakes the loop again
    }
    while (m.link == Link::kOpen && m.in_len > 0) {
      const int frame = mbap::FrameLength({m.in, m.in_len});
      if (frame < 0) return Fault(m, now, fmt::format("garbage from the terminal while {} (not MODBUS TCP)", PhaseName(m.phase)));
      if (frame == 0) return;
      if (m.phase == Phase::kIdle) return Fault(m, now, "unsolicited data from the terminal");
      std::uint8_t copy[mbap::kMaxFrameBytes];
      std::memcpy(copy, m.in, static_cast<std::size_t>(frame));
      std::memmove(m.in, m.in + frame, m.in_len - static_cast<std::size_t>(frame));
      m.in_len -= static_cast<std::size_t>(frame);
      OnFrame(m, {copy, static_cast<std::size_t>(frame)}, now);
    }
  }

  // ------------------------------------------------------------ timers
  void Tick(MachineSlot& m, double now) {
    const double period = m.cfg.period_s;
    m.next_tick_s += period;
    if (m.next_tick_s <= now) m.next_tick_s += std::ceil((now - m.next_tick_s) / period) * period;  // fell behind: skip
    Poller& p = *m.poller;
    p.timers.push({m.next_tick_s, static_cast<std::uint32_t>(m.index), true, 0});
    ++m.cycles;
    {
      std::lock_guard<std::mutex> lock(p.stats_mu);
      ++p.totals.cycles;
    }
    if (m.link == Link::kOpen) {
      if (m.phase != Phase::kIdle) {  // the terminal is still answering the last cycle: never queue a second
        ++m.overruns;
        std::lock_guard<std::mutex> lock(p.stats_mu);
        ++p.totals.overruns;
        return;
      }
      return BeginCycle(m, now);
    }
    // No link: the compensator sees the loss (its status and history say so); values are UNAVAILABLE.
    m.cnc_ok = m.temps_ok = false;
    RunStep(m, now);
    m.installation->CommitWrite(false);
    AfterStep(m, now);
    if (m.link == Link::kDown && now >= m.reconnect_at_s) Connect(m, now);
  }

  void Deadline(MachineSlot& m, double now) {
    if (m.link == Link::kConnecting)
      return Fault(m, now, fmt::format("connect timed out after {:.0f} ms", m.cfg.connect_timeout_s * 1000));
    if (m.link == Link::kOpen && m.phase != Phase::kIdle)
      return Fault(m, now, fmt::format("no answer within {:.0f} ms while {}", m.cfg.response_timeout_s * 1000, PhaseName(m.phase)));
  }

  // One polling thread's loop: its own timers and epoll set, its own machines only.
  void Loop(Poller& p) {
    auto& timers = p.timers;
    std::vector<epoll_event> events(1024);
    double iteration_s = -1;
    while (!p.loop.stopping()) {
      // At most one pass per kBatchS: the answers that arrive meanwhile are taken together, so a
      // thousand terminals cost a few hundred wake-ups a second instead of one per answer.
      if (const double since = Now() - iteration_s; since < kBatchS)
        std::this_thread::sleep_for(std::chrono::duration<double>(kBatchS - since));
      double now = iteration_s = Now();
      while (!timers.empty() && timers.top().due_s <= now) {
        const Timer t = timers.top();
        timers.pop();
        MachineSlot& m = *machines[t.machine];
        if (t.tick) Tick(m, now);
        else if (t.generation == m.deadline_generation) Deadline(m, now);
      }
      int wait_ms = 100;
      if (!timers.empty()) wait_ms = std::clamp(static_cast<int>(std::ceil((timers.top().due_s - Now()) * 1000.0)), 0, 100);
      const int n = epoll_wait(p.epoll_fd, events.data(), static_cast<int>(events.size()), wait_ms);
      now = Now();
      for (int i = 0; i < n; ++i) {
        if (events[i].data.u64 == EventLoop::kWakeToken) continue;
        MachineSlot& m = *machines[events[i].data.u64];
        if (m.fd < 0) continue;
        if (m.link == Link::kConnecting) {
          if (events[i].events & (EPOLLOUT | EPOLLERR | EPOLLHUP)) OnConnected(m, now);
          continue;
        }
        if (events[i].events & (EPOLLIN | EPOLLERR | EPOLLHUP | EPOLLRDHUP)) OnReadable(m, now);
      }
    }
  }
};

Shop::Shop(ShopConfig config, store::HistoryWriter* history) : config_(std::move(config)), impl_(std::make_unique<Impl>(config_)) {
  impl_->history = history;
  if (!config_.audit_log.empty()) {
    // Every model change is appended here; a folder or an unwritable path would lose them.
    FILE* f = std::fopen(config_.audit_log.c_str(), "a");
    if (!f)
      throw InputError(config_.source, config_.audit_log_line, "audit_log",
                       fmt::format("{}: cannot open for append ({})", config_.audit_log, std::strerror(errno)));
    std::fclose(f);
  }
  if (config_.poll_threads < 1 || config_.poll_threads > kMaxPollThreads)
    throw InputError(config_.source, config_.poll_threads_line, "server.poll_threads",
                     fmt::format("{} is out of range: 1 to {} polling threads", config_.poll_threads, kMaxPollThreads));
  // No more threads than machines: a thread without a machine would only wake up.
  const std::size_t threads = std::max<std::size_t>(1, std::min<std::size_t>(static_cast<std::size_t>(config_.poll_threads),
                                                                             config_.machines.size()));
  for (std::size_t k = 0; k < threads; ++k) impl_->pollers.push_back(std::make_unique<Poller>());
  const double unix0 = impl_->unix_offset_s;
  for (std::size_t i = 0; i < config_.machines.size(); ++i) {
    const MachineConfig& c = config_.machines[i];
    auto m = std::make_unique<MachineSlot>(c);
    m->index = i;
    m->poller = impl_->pollers[i % threads].get();
    m->addr.sin_family = AF_INET;
    m->addr.sin_port = htons(static_cast<std::uint16_t>(c.port));
    inet_pton(AF_INET, c.host.c_str(), &m->addr.sin_addr);
    m->module_count = (c.channels.size() + adam::kChannelCount - 1) / adam::kChannelCount;
    m->ranges.assign(c.channels.size(), nullptr);
    const std::size_t axes = c.axes.size();
    m->applied_um.assign(axes, 0.0);
    m->cnc = std::make_unique<TerminalCnc>(c.axes);
    m->temps = std::make_unique<TerminalTemperatures>(c.channels);
    m->wanted.axis_enabled.assign(axes, 1);
    for (std::size_t a = 0; a < axes; ++a) m->wanted.axis_enabled[a] = c.axis_interfaces[a].enabled ? 1 : 0;
    m->controls = m->wanted;
    // The installation, with the first model: a model that does not fit this machine is an input error naming it.
    try {
      Impl* impl = impl_.get();
      m->installation = std::make_unique<station::Installation>(c.installation, *m->cnc, *m->temps,
                                                                [impl] { return impl->Now(); }, "");
      const station::PublishedModel& model = m->installation->model();
      ModelEntry e{model, {c.model_file, model::Sha256OfFile(c.model_file), RevisionOf(model), 0}};
      m->model_info = e.info;
      m->models.push_back(e);
    } catch (const InputError& e) {
      throw InputError(config_.source, c.line, fmt::format("machine[{}].model", i),
                       fmt::format("machine '{}': {}", c.name, e.what()));
    }
    for (const auto& w : m->installation->warnings()) fmt::print(stderr, "trueaxis server: machine '{}': {}\n", c.name, w);
    MachineStatus& s = m->status;
    s.name = c.name;
    s.endpoint = fmt::format("{}:{}", c.host, c.port);
    s.model = m->model_info;
    for (std::size_t a = 0; a < axes; ++a) s.axes.push_back({c.axes[a], std::nullopt, std::nullopt, 0, 0, m->wanted.axis_enabled[a] != 0});
    for (const auto& ch : c.channels) s.channels.push_back({ch, std::nullopt, "lost"});
    if (history) {
      std::vector<std::string> axis_names, channel_names;
      for (const auto& a : c.axes) axis_names.push_back(c.name + "/" + a);
      for (const auto& ch : c.channels) channel_names.push_back(c.name + "/" + ch);
      m->logger = std::make_unique<station::HistoryLogger>(*history, axis_names, channel_names, unix0, c.name);
      history->PushModelChange(UnixNowS(), m->model_info.sha256, m->installation->model().revision,
                               fmt::format("{} start: {}", c.name, c.model_file));
    }
    impl_->machines.push_back(std::move(m));
  }
}

Shop::~Shop() { Stop(); }

void Shop::Start() {
  Impl& s = *impl_;
  if (s.pollers.front()->loop.thread().joinable()) return;
  std::string why;
  if (!EnsureOpenFileLimit(s.machines.size() + 256, &why)) throw std::runtime_error("trueaxis server: " + why);
  // Staggered start: machine i's first cycle is i/N of a period in, so the shop's requests spread over the period.
  const double now = s.Now();
  const std::size_t n = s.machines.size();
  for (std::size_t i = 0; i < n; ++i) {
    MachineSlot& m = *s.machines[i];
    m.next_tick_s = now + m.cfg.period_s * static_cast<double>(i) / static_cast<double>(n);
    m.poller->timers.push({m.next_tick_s, static_cast<std::uint32_t>(i), true, 0});
    m.reconnect_at_s = m.next_tick_s;
  }
  for (auto& p : s.pollers) p->loop.Start([&s, q = p.get()] { s.Loop(*q); });
}

void Shop::Stop() {
  Impl& s = *impl_;
  bool was_running = false;
  for (auto& p : s.pollers) was_running = p->loop.Stop() || was_running;
  if (!was_running) return;
  for (auto& m : s.machines) s.CloseLink(*m);
}

namespace {
MachineSlot& Find(const std::vector<std::unique_ptr<MachineSlot>>& machines, const std::string& name) {
  for (const auto& m : machines)
    if (m->cfg.name == name) return *m;
  throw InputError("request", 0, "machine", fmt::format("no machine named '{}' in this shop", name));
}
}  // namespace

std::vector<MachineStatus> Shop::Snapshot() const {
  std::vector<MachineStatus> out;
  out.reserve(impl_->machines.size());
  for (const auto& m : impl_->machines) {
    std::lock_guard<std::mutex> lock(m->mu);
    out.push_back(m->status);
  }
  return out;
}

std::optional<MachineStatus> Shop::Machine(const std::string& name) const {
  for (const auto& m : impl_->machines)
    if (m->cfg.name == name) {
      std::lock_guard<std::mutex> lock(m->mu);
      return m->status;
    }
  return std::nullopt;
}

std::size_t Shop::MachineCount() const { return impl_->machines.size(); }

MachineStatus Shop::MachineAt(std::size_t i) const {
  const MachineSlot& m = *impl_->machines.at(i);
  std::lock_guard<std::mutex> lock(m.mu);
  return m.status;
}

std::vector<std::string> Shop::MachineNames() const {
  std::vector<std::string> out;
  for (const auto& m : impl_->machines) out.push_back(m->cfg.name);
  return out;
}

ShopStats Shop::Stats() const {
  ShopStats s;
  LatencyHistogram h;  // the polling threads' histograms merged
  for (const auto& p : impl_->pollers) {
    std::lock_guard<std::mutex> lock(p->stats_mu);
    s.cycles += p->totals.cycles;
    s.complete_cycles += p->totals.complete_cycles;
    s.faults += p->totals.faults;
    s.overruns += p->totals.overruns;
    h.Merge(p->latency);
  }
  s.latency_samples = h.total();
  if (h.total() > 0) {
    s.latency_p50_ms = h.Quantile(0.5);
    s.latency_p99_ms = h.Quantile(0.99);
    s.latency_max_ms = h.max_ms();
  }
  s.latency_histogram = h.NonEmpty();
  if (impl_->history) s.history_dropped = impl_->history->Stats().dropped;
  for (auto& p : impl_->pollers) s.loop_cpu_s += ThreadCpuSeconds(p->loop.thread());
  s.poll_threads = static_cast<int>(impl_->pollers.size());
  return s;
}

void Shop::ResetLatency() {
  for (auto& p : impl_->pollers) {
    std::lock_guard<std::mutex> lock(p->stats_mu);
    p->latency.Clear();
  }
}

ModelChange Shop::LoadModel(const std::string& machine, const std::string& model_file, const std::string& user,
                            const std::string& from) {
  MachineSlot& m = Find(impl_->machines, machine);
  // The path comes from a client: a device or FIFO would never end, and a file that is not JSON must
  // not have its first bytes quoted back (a parse error shows what it read).
  std::error_code ec;
  if (!std::filesystem::is_regular_file(model_file, ec))
    throw InputError(model_file, 0, "file",
                     std::filesystem::exists(model_file, ec) ? "not a regular file (a model is a JSON file)" : "no such file");
  station::PublishedModel model;
  try {
    model = m.installation->ReadModel(model_file);  // InputError: the running model stays
  } catch (const InputError& e) {
    if (e.field().empty() && e.message().rfind("not valid JSON", 0) == 0)
      throw InputError(model_file, 0, "file", "not a model file (not valid JSON)");
    throw;
  }
  const std::string sha = model::Sha256OfFile(model_file);
  std::lock_guard<std::mutex> lock(m.mu);
  ModelChange c{machine, user, from, UnixNowS(), m.models[m.current_model].info, {}, "load"};
  c.new_model = {model_file, sha, RevisionOf(model), m.models.size()};
  impl_->Audit(c);  // InputError: the running model stays
  m.installation->Publish(model, model_file);
  m.models.push_back({model, c.new_model});
  m.current_model = m.models.size() - 1;
  m.model_info = c.new_model;
  m.changes.push_back(c);
  impl_->RecordChange(m, c);
  return c;
}

ModelChange Shop::Rollback(const std::string& machine, const std::string& user, const std::string& from) {
  MachineSlot& m = Find(impl_->machines, machine);
  std::lock_guard<std::mutex> lock(m.mu);
  if (m.current_model == 0)
    throw InputError("request", 0, "rollback", fmt::format("machine '{}' runs its first model: nothing to roll back to", machine));
  const ModelEntry& back = m.models[m.current_model - 1];
  ModelChange c{machine, user, from, UnixNowS(), m.models[m.current_model].info, back.info, "rollback"};
  impl_->Audit(c);  // InputError: the running model stays
  m.installation->Publish(back.model, back.info.file);
  m.model_info = back.info;
  --m.current_model;
  m.changes.push_back(c);
  impl_->RecordChange(m, c);
  return c;
}

std::vector<ModelChange> Shop::ModelChanges(const std::string& machine) const {
  MachineSlot& m = Find(impl_->machines, machine);
  std::lock_guard<std::mutex> lock(m.mu);
  return m.changes;
}

void Shop::SetAxisEnabled(const std::string& machine, const std::string& axis, bool enabled, const std::string& user) {
  MachineSlot& m = Find(impl_->machines, machine);
  const auto it = std::find(m.cfg.axes.begin(), m.cfg.axes.end(), axis);
  if (it == m.cfg.axes.end())
    throw InputError("request", 0, "axis", fmt::format("machine '{}' has no axis '{}'", machine, axis));
  {
    std::lock_guard<std::mutex> lock(m.mu);
    const auto a = static_cast<std::size_t>(it - m.cfg.axes.begin());
    m.wanted.axis_enabled[a] = enabled ? 1 : 0;
    m.status.axes[a].enabled = enabled;  // shown at once; the loop applies it next cycle (ramping)
  }
  if (impl_->history)
    impl_->history->PushAlarm(UnixNowS(), "info", machine, fmt::format("axis {} {} by {}", axis, enabled ? "enabled" : "disabled", user));
}

void Shop::AcknowledgeAlarms(const std::string& machine, const std::string& user) {
  MachineSlot& m = Find(impl_->machines, machine);
  std::string names;
  {
    std::lock_guard<std::mutex> lock(m.mu);
    names = runtime::AlarmNames(m.status.unacknowledged);
    m.status.unacknowledged = m.status.alarms;  // what still holds stays raised
  }
  if (impl_->history)
    impl_->history->PushAlarm(UnixNowS(), "info", machine, fmt::format("alarms acknowledged by {}: {}", user, names.empty() ? "none" : names));
}

void Shop::SetCoolantOverride(const std::string& machine, std::optional<CoolantState> coolant, const std::string& user) {
  MachineSlot& m = Find(impl_->machines, machine);
  {
    std::lock_guard<std::mutex> lock(m.mu);
    m.wanted.coolant_override = coolant;
    m.status.coolant_override = coolant ? std::optional<std::string>(std::string(CoolantStateName(*coolant))) : std::nullopt;
  }
  if (impl_->history)
    impl_->history->PushAlarm(UnixNowS(), "info", machine,
                              fmt::format("coolant override {} by {}", coolant ? std::string(CoolantStateName(*coolant)) : "off (follow the CNC)", user));
}

}  // namespace trueaxis::server
