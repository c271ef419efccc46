#include "trueaxis/drivers/modbus_machine_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "trueaxis/core/periodic_thread.hpp"
#include "trueaxis/drivers/mbap.hpp"
#include "trueaxis/drivers/register_codec.hpp"
#include "trueaxis/drivers/terminal_registers.hpp"

namespace trueaxis::drivers {
namespace {

using Clock = std::chrono::steady_clock;

bool ValidUnitId(int id) { return id >= 1 && id <= 247; }

// Holding-register writes seen in a request PDU: (first address, values).
// FC 06 and FC 16 only; anything else has no holding-register write.
struct RegisterWrite {
  int address = 0;
  int count = 0;
  const std::uint8_t* values = nullptr;  // big-endian 16-bit words (mbap::WordAt)
};
struct CoilWrite {
  int address = 0;
  int count = 0;
  const std::uint8_t* bits = nullptr;  // FC 15 packed bits; null for FC 05
  bool single_value = false;
  bool Value(int i) const { return bits ? ((bits[i / 8] >> (i % 8)) & 1) != 0 : single_value; }
};

int U16(const std::uint8_t* p) { return (p[0] << 8) | p[1]; }

}  // namespace

bool ModbusMachineServerOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  in_addr addr{};
  if (inet_pton(AF_INET, bind_address.c_str(), &addr) != 1)
    return fail(fmt::format("bind_address '{}' is not an IPv4 address", bind_address));
  if (port < 1 || port > 65535) return fail(fmt::format("port {} is outside 1..65535", port));
  if (!ValidUnitId(pmc_unit_id)) return fail(fmt::format("pmc_unit_id {} is outside 1..247", pmc_unit_id));
  if (!ValidUnitId(first_rtd_unit_id)) return fail(fmt::format("first_rtd_unit_id {} is outside 1..247", first_rtd_unit_id));
  if (!FindRtdRange(rtd_range_code)) return fail(fmt::format("rtd_range_code 0x{:02X} is not an ADAM-6015 RTD type code", rtd_range_code));
  if (!(machine_period_s > 0 && machine_period_s <= 10)) return fail("machine_period_s must be in (0, 10] s");
  if (!(max_abs_compensation_um > 0 && max_abs_compensation_um <= 1e6)) return fail("max_abs_compensation_um must be in (0, 1e6] µm");
  if (max_clients < 1 || max_clients > 512) return fail("max_clients must be in 1..512");
  if (!(idle_timeout_s >= 0)) return fail("idle_timeout_s must be >= 0 (0 = never)");
  if (!(watchdog_s >= 0)) return fail("watchdog_s must be >= 0 (0 = off: hold the last compensation)");
  if (!(watchdog_ramp_um_per_s > 0)) return fail("watchdog_ramp_um_per_s must be > 0");
  return true;
}

std::string ModbusMachineServerStats::BriefReport() const {
  return fmt::format("{} requests ({} exceptions), {} clients now, {} connections ({} refused, {} dropped idle, {} "
                     "evicted for a new client), {} machine exchanges, {} compensation writes",
                     requests, exceptions, clients, connections, refused_connections, idle_disconnects,
                     evicted_connections, exchanges, compensation_writes);
}

struct ModbusMachineServer::Impl {
  hw::CncLink* cnc = nullptr;
  hw::TemperatureSource* temps = nullptr;
  ModbusMachineServerOptions opt;
  AdvanceFn advance;
  std::mutex* machine_mutex = nullptr;  // held around each exchange when the owner drives the machine too

  // --- fixed at construction ---
  std::size_t axis_count = 0;
  std::size_t channel_count = 0;
  std::size_t module_count = 0;

  // --- register image, guarded by mu ---
  mutable std::mutex mu;
  modbus_mapping_t* pmc_map = nullptr;
  std::vector<modbus_mapping_t*> rtd_maps;
  std::vector<const adam6015::RtdRange*> channel_range;  // per channel
  std::vector<bool> history_valid;                       // per channel: max/min hold a reading
  bool compensation_dirty = false;  // a client wrote new compensation registers (wakes the machine loop)
  Clock::time_point last_client_write{};  // of any PMC holding register (watchdog)
  bool temperatures_online = false;
  std::uint32_t heartbeat = 0;
  ModbusMachineServerStats stats;

  // --- machine thread only ---
  std::vector<hw::AxisState> axes;
  std::vector<hw::RawTemperature> raw;
  std::vector<double> pending_um;
  std::vector<double> applied_um;
  bool retry_write = false;  // the CNC refused the last vector: try again next period (no busy loop)
  TravelCounter travel;  // per axis: the path travelled
  Clock::time_point last_read_ok{};
  bool ever_read_ok = false;
  Clock::time_point last_exchange{};

  // --- network thread only ---
  modbus_t* ctx = nullptr;
  int listen_fd = -1;
  int wake_pipe[2] = {-1, -1};
  struct Client;
  std::vector<std::unique_ptr<Client>> clients;

  std::atomic<bool> stop{false};
  std::thread net_thread;
  // Every machine_period_s, and at once when a client writes compensation registers (Wake).
  core::PeriodicThread machine_loop;

  ~Impl() {
    if (pmc_map) modbus_mapping_free(pmc_map);
    for (auto* m : rtd_maps) modbus_mapping_free(m);
    if (ctx) modbus_free(ctx);
    for (int fd : wake_pipe)
      if (fd >= 0) close(fd);
  }

  modbus_mapping_t* UnitMap(int unit, int* module) {
    if (pmc_map && unit == opt.pmc_unit_id) {
      *module = -1;
      return pmc_map;
    }
    const int k = unit - opt.first_rtd_unit_id;
    if (k >= 0 && k < static_cast<int>(rtd_maps.size())) {
      *module = k;
      return rtd_maps[k];
    }
    return nullptr;
  }

  std::size_t ModuleChannels(std::size_t k) const {
    return RtdModuleChannels(channel_count, k);
  }

  // ------------------------------------------------------------------ network
  // Returns 0 when the request may be applied, else the MODBUS exception code.
  // Validates writes before libmodbus applies them, so a refused write leaves
  // the register image untouched.
  int ValidatePmc(const std::uint8_t* request, int request_len, const std::uint8_t* pdu, int pdu_len) {
    RegisterWrite w;
    const int fc = pdu[0];
    if (fc == MODBUS_FC_WRITE_SINGLE_REGISTER) {
      if (pdu_len < 5) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
      w = {U16(pdu + 1), 1, pdu + 3};
    } else if (fc == MODBUS_FC_WRITE_MULTIPLE_REGISTERS) {
      if (pdu_len < 6) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
      w = {U16(pdu + 1), U16(pdu + 3), pdu + 6};
      if (w.count < 1 || w.count > MODBUS_MAX_WRITE_REGISTERS || pdu[5] != 2 * w.count || pdu_len < 6 + 2 * w.count)
        return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
    } else if (fc == MODBUS_FC_WRITE_AND_READ_REGISTERS) {
      // the write part as FC 16; the read part must be one libmodbus answers too (else it would
      // refuse the request after this check had counted it as a client write)
      mbap::ParsedRequest q;
      if (!mbap::ParseRequest({request, static_cast<std::size_t>(request_len)}, &q)) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
      if (q.head.address + q.head.count > PmcHoldingImageLength(axis_count)) return MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS;
      w = {q.write_address, q.write_count, q.values};
    } else if (fc == MODBUS_FC_MASK_WRITE_REGISTER) {
      return MODBUS_EXCEPTION_ILLEGAL_FUNCTION;  // not part of the window
    } else {
      return 0;  // reads, and writes to tables the window does not have (libmodbus answers those)
    }
    std::uint16_t candidate[pmc::kHoldingRegisterCount];
    return CheckPmcWrite(pmc_map->tab_registers, axis_count, w.address, w.count, [v = w.values](int i) { return mbap::WordAt(v, i); },
                         opt.max_abs_compensation_um, candidate);
  }

  int ValidateRtd(int module, const std::uint8_t* pdu, int pdu_len) {
    const int fc = pdu[0];
    const std::size_t n = ModuleChannels(module);
    if (!temperatures_online) return MODBUS_EXCEPTION_GATEWAY_TARGET;  // module "not answering"
    if (fc == MODBUS_FC_WRITE_SINGLE_REGISTER || fc == MODBUS_FC_WRITE_MULTIPLE_REGISTERS) {
      RegisterWrite w;
      if (fc == MODBUS_FC_WRITE_SINGLE_REGISTER) {
        if (pdu_len < 5) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
        w = {U16(pdu + 1), 1, pdu + 3};
      } else {
        if (pdu_len < 6) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
        w = {U16(pdu + 1), U16(pdu + 3), pdu + 6};
        if (w.count < 1 || w.count > MODBUS_MAX_WRITE_REGISTERS || pdu[5] != 2 * w.count || pdu_len < 6 + 2 * w.count)
          return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
      }
      return CheckRtdTypeCodeWrite(n, w.address, w.count, [v = w.values](int i) { return mbap::WordAt(v, i); });
    }
    if (fc == MODBUS_FC_WRITE_SINGLE_COIL || fc == MODBUS_FC_WRITE_MULTIPLE_COILS) {
      CoilWrite w;
      if (fc == MODBUS_FC_WRITE_SINGLE_COIL) {
        if (pdu_len < 5) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
        w.address = U16(pdu + 1);
        w.count = 1;
      } else {
        if (pdu_len < 6) return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
        w.address = U16(pdu + 1);
        w.count = U16(pdu + 3);
        if (w.count < 1 || w.count > MODBUS_MAX_WRITE_BITS || pdu_len < 6 + (w.count + 7) / 8)
          return MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE;
      }
      return CheckRtdCoilWrite(n, w.address, w.count);
    }
    if (fc == MODBUS_FC_MASK_WRITE_REGISTER || fc == MODBUS_FC_WRITE_AND_READ_REGISTERS)
      return MODBUS_EXCEPTION_ILLEGAL_FUNCTION;
    return 0;
  }

  // After libmodbus applied an accepted write: act on it (mu held).
  void AfterWrite(int module, const std::uint8_t* pdu) {
    const int fc = pdu[0];
    if (module < 0) {
      if (fc == MODBUS_FC_WRITE_SINGLE_REGISTER || fc == MODBUS_FC_WRITE_MULTIPLE_REGISTERS ||
          fc == MODBUS_FC_WRITE_AND_READ_REGISTERS) {
        compensation_dirty = true;
        last_client_write = Clock::now();
        machine_loop.Wake();
      }
      return;
    }
    modbus_mapping_t* m = rtd_maps[module];
    const std::size_t n = ModuleChannels(module);
    if (fc == MODBUS_FC_WRITE_SINGLE_REGISTER || fc == MODBUS_FC_WRITE_MULTIPLE_REGISTERS) {
      for (std::size_t c = 0; c < n; ++c) {
        const std::size_t ch = module * adam6015::kChannelCount + c;
        const auto* r = FindRtdRange(m->tab_registers[adam6015::kTypeCodeAddress + c]);
        if (r != channel_range[ch]) {
          channel_range[ch] = r;
          history_valid[ch] = false;  // old extremes are in another scale
        }
      }
      MirrorInputRegisters(m);
    } else if (fc == MODBUS_FC_WRITE_SINGLE_COIL || fc == MODBUS_FC_WRITE_MULTIPLE_COILS) {
      ResetRtdHistory(n, m->tab_registers, m->tab_bits);
      MirrorInputRegisters(m);
    }
  }

  static void MirrorInputRegisters(modbus_mapping_t* m) {
    std::copy(m->tab_registers, m->tab_registers + m->nb_registers, m->tab_input_registers);
  }

  void HandleRequest(const std::uint8_t* req, int len) {
    const int hl = modbus_get_header_length(ctx);
    if (len <= hl) return;
    const int unit = req[hl - 1];
    const std::uint8_t* pdu = req + hl;
    const int pdu_len = len - hl;
    std::lock_guard<std::mutex> lock(mu);
    ++stats.requests;
    const int fc = pdu[0];
    const bool supported = (fc >= 1 && fc <= 6) || fc == 15 || fc == 16 || fc == 23;
    const int min_pdu = (fc >= 1 && fc <= 6) ? 5 : (fc == 15 || fc == 16) ? 6 : fc == 23 ? 10 : 1;
    // Refuse here what libmodbus would refuse itself: its own refusal of an
    // unknown function sleeps for the response timeout and flushes the
    // socket, on the network thread. A short PDU it would read past.
    if (!supported || pdu_len < min_pdu) {
      ++stats.exceptions;
      modbus_reply_exception(ctx, req, supported ? MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE : MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
      return;
    }
    int module = -1;
    modbus_mapping_t* map = UnitMap(unit, &module);
    int ex = map ? (module < 0 ? ValidatePmc(req, len, pdu, pdu_len) : ValidateRtd(module, pdu, pdu_len))
                 : MODBUS_EXCEPTION_GATEWAY_TARGET;  // no such device behind this terminal
    if (ex != 0) {
      ++stats.exceptions;
      modbus_reply_exception(ctx, req, ex);
      return;
    }
    if (modbus_reply(ctx, req, len, map) < 0) return;
    AfterWrite(module, pdu);
  }

  // One connection and the bytes of its frame in progress. Frames are
  // assembled here from non-blocking reads, so a client that stops in the
  // middle of a frame costs nothing to the others (libmodbus' own
  // modbus_receive() would block the thread for the byte timeout).
  struct Client {
    int fd = -1;
    std::uint8_t buf[MODBUS_TCP_MAX_ADU_LENGTH];
    std::size_t len = 0;
    Clock::time_point last_activity{};
  };

  void CloseClient(std::size_t i) {
    close(clients[i]->fd);
    clients.erase(clients.begin() + static_cast<std::ptrdiff_t>(i));
    std::lock_guard<std::mutex> lock(mu);
    stats.clients = static_cast<int>(clients.size());
  }

  // Reads what is there and answers every complete frame. False: drop the client.
  bool ServeClient(Client& c) {
    const ssize_t n = recv(c.fd, c.buf + c.len, sizeof c.buf - c.len, 0);
    if (n == 0) return false;  // closed by the peer
    if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
    c.len += static_cast<std::size_t>(n);
    c.last_activity = Clock::now();
    constexpr std::size_t kMbap = 7;  // transaction id, protocol id, length, unit id
    while (c.len >= kMbap) {
      const int protocol = U16(c.buf + 2);
      const int length = U16(c.buf + 4);  // unit id + PDU
      const std::size_t frame = 6 + static_cast<std::size_t>(length);
      if (protocol != 0 || length < 2 || frame > sizeof c.buf) return false;  // not MODBUS TCP
      if (c.len < frame) break;  // rest of the frame still on its way
      // Function codes 0x80…0xFF are the exception responses themselves: a request carrying one is
      // not MODBUS (an "exception reply" to it would echo the same code and look like a normal
      // answer). Drop the connection, counted as a refused frame.
      if (c.buf[kMbap] >= 0x80) {
        std::lock_guard<std::mutex> lock(mu);
        ++stats.requests;
        ++stats.exceptions;
        return false;
      }
      modbus_set_socket(ctx, c.fd);
      HandleRequest(c.buf, static_cast<int>(frame));
      std::memmove(c.buf, c.buf + frame, c.len - frame);
      c.len -= frame;
    }
    return true;
  }

  void NetworkLoop() {
    while (!stop.load()) {
      fd_set rd;
      FD_ZERO(&rd);
      FD_SET(listen_fd, &rd);
      FD_SET(wake_pipe[0], &rd);
      int maxfd = std::max(listen_fd, wake_pipe[0]);
      for (const auto& c : clients) {
        FD_SET(c->fd, &rd);
        maxfd = std::max(maxfd, c->fd);
      }
      timeval tick{0, 250000};  // wake now and then to drop idle connections
      const int n = select(maxfd + 1, &rd, nullptr, nullptr, &tick);
      if (n < 0) {
        if (errno == EINTR) continue;
        break;
      }
      if (n > 0 && FD_ISSET(wake_pipe[0], &rd)) break;  // Stop()
      if (n > 0 && FD_ISSET(listen_fd, &rd)) {
        const int fd = accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
        if (fd >= 0) {
          std::lock_guard<std::mutex> lock(mu);
          // A new client always gets in: when every slot is taken, the connection silent the
          // longest makes room (silent sockets held open must not lock the real clients out).
          if (static_cast<int>(clients.size()) >= opt.max_clients && fd < FD_SETSIZE) {
            std::size_t oldest = 0;
            for (std::size_t i = 1; i < clients.size(); ++i)
              if (clients[i]->last_activity < clients[oldest]->last_activity) oldest = i;
            close(clients[oldest]->fd);
            clients.erase(clients.begin() + static_cast<std::ptrdiff_t>(oldest));
            ++stats.evicted_connections;
          }
          if (fd >= FD_SETSIZE) {
            close(fd);
            ++stats.refused_connections;
          } else {
            int one = 1;
            setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            auto c = std::make_unique<Client>();
            c->fd = fd;
            c->last_activity = Clock::now();
            clients.push_back(std::move(c));
            ++stats.connections;
            stats.clients = static_cast<int>(clients.size());
          }
        }
      }
      const auto now = Clock::now();
      const auto idle_limit = std::chrono::duration<double>(opt.idle_timeout_s);
      for (std::size_t i = clients.size(); i-- > 0;) {
        if (n > 0 && FD_ISSET(clients[i]->fd, &rd) && !ServeClient(*clients[i])) {
          CloseClient(i);
        } else if (opt.idle_timeout_s > 0 && now - clients[i]->last_activity > idle_limit) {
          CloseClient(i);  // silent too long: free the slot (a dead peer never says goodbye)
          std::lock_guard<std::mutex> lock(mu);
          ++stats.idle_disconnects;
        }
      }
    }
    for (const auto& c : clients) close(c->fd);
    clients.clear();
    modbus_set_socket(ctx, -1);
  }

  // ------------------------------------------------------------------ machine
  void Exchange(double elapsed_s) {
    std::unique_lock<std::mutex> machine_lock;
    if (machine_mutex) machine_lock = std::unique_lock<std::mutex>(*machine_mutex);
    if (advance) advance(elapsed_s);
    hw::CncState state;
    const bool read_ok = cnc && cnc->Read(axes, state);
    const bool temps_ok = temps && temps->Read(raw);
    const auto now = Clock::now();
    if (read_ok) {
      travel.Update(axes);
      last_read_ok = now;
      ever_read_ok = true;
    }
    bool write_needed = false;
    {
      std::lock_guard<std::mutex> lock(mu);
      ++heartbeat;
      ++stats.exchanges;
      if (pmc_map) PublishPmc(read_ok, temps_ok, state, now);
      if (temps) PublishTemperatures(temps_ok);
      if (pmc_map && WatchdogStep(elapsed_s, now)) compensation_dirty = true;
      if (pmc_map) CopyWindowToHolding(pmc_map->tab_input_registers, pmc_map->tab_registers, axis_count);
      if (pmc_map && (compensation_dirty || retry_write)) {
        DecodeCommand(pmc_map->tab_registers + pmc::kHrCompensationBase, pending_um);
        compensation_dirty = false;
        write_needed = true;
      }
    }
    if (!write_needed) return;
    const bool ok = cnc->WriteCompensation(pending_um);
    std::lock_guard<std::mutex> lock(mu);
    if (ok) {
      applied_um = pending_um;
      ++stats.compensation_writes;
    }
    EncodeWriteResult(ok, applied_um, pmc_map->tab_input_registers);
    CopyWindowToHolding(pmc_map->tab_input_registers, pmc_map->tab_registers, axis_count);
    retry_write = !ok;  // next period, not at once: a CNC that refuses must not be hammered
  }

  // Watchdog (mu held): when no client has written for watchdog_s, the command ramps to 0, so a
  // compensator that dies or loses its link cannot leave a stale offset on the machine, and the
  // machine never sees a jump. True when it changed a value.
  bool WatchdogStep(double elapsed_s, Clock::time_point now) {
    const CommandWatchdog watchdog{opt.watchdog_s, opt.watchdog_ramp_um_per_s};
    const double since_write_s = std::chrono::duration<double>(now - last_client_write).count();
    if (!watchdog.Step(pmc_map->tab_input_registers, pmc_map->tab_registers, axis_count, since_write_s, elapsed_s))
      return false;
    ++stats.watchdog_steps;
    return true;
  }

  void PublishPmc(bool read_ok, bool temps_ok, const hw::CncState& state, Clock::time_point now) {
    PmcExchange e;
    e.heartbeat = heartbeat;
    e.machine_read_ok = read_ok;
    e.temperatures_read_ok = temps_ok;
    e.machine = state;
    e.axes = axes;
    e.travel_mm = travel.travel_mm();
    e.read_age_ms = ever_read_ok ? std::chrono::duration<double, std::milli>(now - last_read_ok).count() : 65535.0;
    EncodePmcState(e, pmc_map->tab_input_registers, pmc_map->tab_registers);
  }

  void PublishTemperatures(bool temps_ok) {
    temperatures_online = temps_ok;
    if (!temps_ok) return;  // the modules "stop answering" (gateway target exception)
    for (std::size_t ch = 0; ch < channel_count; ++ch) {
      const std::size_t k = ch / adam6015::kChannelCount;
      const std::size_t c = ch % adam6015::kChannelCount;
      modbus_mapping_t* m = rtd_maps[k];
      bool valid = history_valid[ch];
      EncodeRtdChannel(raw[ch], *channel_range[ch], c, m->tab_registers, m->tab_bits, &valid);
      history_valid[ch] = valid;
    }
    for (auto* m : rtd_maps) MirrorInputRegisters(m);
  }

  void MachineTick() {
    const auto now = Clock::now();
    Exchange(std::chrono::duration<double>(now - last_exchange).count());
    last_exchange = now;
  }
};

ModbusMachineServer::ModbusMachineServer(hw::CncLink* cnc, hw::TemperatureSource* temperatures,
                                         ModbusMachineServerOptions options)
    : impl_(std::make_unique<Impl>()), options_(std::move(options)) {
  impl_->cnc = cnc;
  impl_->temps = temperatures;
  impl_->opt = options_;
}

ModbusMachineServer::~ModbusMachineServer() { Stop(); }

void ModbusMachineServer::SetAdvance(AdvanceFn advance) { impl_->advance = std::move(advance); }
void ModbusMachineServer::ShareMachineWith(std::mutex* machine_mutex) { impl_->machine_mutex = machine_mutex; }

std::optional<std::string> UnitIdLayoutProblem(const ModbusMachineServerOptions& o, std::size_t channel_count,
                                               bool has_cnc) {
  const std::size_t modules = RtdModulesFor(channel_count);
  if (modules == 0) return std::nullopt;
  const int last_unit = o.first_rtd_unit_id + static_cast<int>(modules) - 1;
  if (last_unit > 247)
    return fmt::format("too many RTD modules for the unit id range: {} channels need {} modules, unit ids {}..{} go "
                       "beyond MODBUS's 247",
                       channel_count, modules, o.first_rtd_unit_id, last_unit);
  if (has_cnc && o.pmc_unit_id >= o.first_rtd_unit_id && o.pmc_unit_id <= last_unit)
    return fmt::format("pmc_unit_id {} collides with the RTD modules' unit ids {}..{}", o.pmc_unit_id, o.first_rtd_unit_id,
                       last_unit);
  return std::nullopt;
}

std::size_t ModbusMachineServer::RtdModuleCount() const {
  if (!impl_->temps) return 0;
  return RtdModulesFor(impl_->temps->ChannelCount());
}

bool ModbusMachineServer::Start(std::string* error) {
  auto fail = [&](std::string msg) {
    if (error) *error = std::move(msg);
    return false;
  };
  if (running_.load()) return fail("server already running");
  Impl& s = *impl_;
  std::string why;
  if (!options_.IsValid(&why)) return fail("invalid server options: " + why);
  if (!s.cnc && !s.temps) return fail("nothing to serve: neither a CncLink nor a TemperatureSource");
  s.axis_count = s.cnc ? s.cnc->AxisCount() : 0;
  if (s.axis_count > pmc::kMaxAxes) return fail(fmt::format("the PMC window holds at most {} axes, the CNC has {}", pmc::kMaxAxes, s.axis_count));
  s.channel_count = s.temps ? s.temps->ChannelCount() : 0;
  s.module_count = RtdModuleCount();
  if (auto why = UnitIdLayoutProblem(options_, s.channel_count, s.cnc != nullptr)) return fail(*why);

  // (Re)build the register image.
  if (s.pmc_map) modbus_mapping_free(s.pmc_map);
  s.pmc_map = nullptr;
  for (auto* m : s.rtd_maps) modbus_mapping_free(m);
  s.rtd_maps.clear();
  if (s.cnc) {
    s.pmc_map = modbus_mapping_new(0, 0, PmcHoldingImageLength(s.axis_count),
                                   pmc::InputWindowLength(s.axis_count));
    if (!s.pmc_map) return fail("cannot allocate the PMC register image");
    InitPmcImage(s.pmc_map->tab_input_registers, s.pmc_map->tab_registers, s.axis_count, options_.initial_enable);
  }
  const auto* range = FindRtdRange(options_.rtd_range_code);
  s.channel_range.assign(s.channel_count, range);
  s.history_valid.assign(s.channel_count, false);
  for (std::size_t k = 0; k < s.module_count; ++k) {
    auto* m = modbus_mapping_new(adam6015::kCoilCount, 0, adam6015::kRegisterCount, adam6015::kRegisterCount);
    if (!m) return fail("cannot allocate an ADAM-6015 register image");
    InitRtdModule(m->tab_registers, s.ModuleChannels(k), options_.rtd_range_code);
    Impl::MirrorInputRegisters(m);
    s.rtd_maps.push_back(m);
  }
  s.axes.assign(s.axis_count, {});
  s.raw.assign(s.channel_count, {});
  s.pending_um.assign(s.axis_count, 0.0);
  s.applied_um.assign(s.axis_count, 0.0);
  s.travel = TravelCounter(s.axis_count);
  s.compensation_dirty = false;  // nothing is forwarded before a client writes: no jump at start-up
  s.retry_write = false;
  s.last_client_write = Clock::now();
  s.temperatures_online = false;
  s.heartbeat = 0;
  s.ever_read_ok = false;
  s.stats = {};

  if (s.ctx) modbus_free(s.ctx);
  s.ctx = modbus_new_tcp(options_.bind_address.c_str(), options_.port);
  if (!s.ctx) return fail(fmt::format("modbus_new_tcp: {}", modbus_strerror(errno)));
  // libmodbus sleeps for the response timeout before answering some bad
  // requests (e.g. a quantity of 0) and then flushes the socket; on a server
  // that sleep would stall every client, so keep it at 1 µs.
  modbus_set_response_timeout(s.ctx, 0, 1);
  s.listen_fd = modbus_tcp_listen(s.ctx, 16);
  if (s.listen_fd < 0)
    return fail(fmt::format("cannot listen on {}:{}: {}", options_.bind_address, options_.port, modbus_strerror(errno)));
  fcntl(s.listen_fd, F_SETFD, FD_CLOEXEC);
  if (pipe2(s.wake_pipe, O_CLOEXEC) != 0) {
    close(s.listen_fd);
    s.listen_fd = -1;
    return fail("cannot create the wake pipe");
  }
  s.stop.store(false);
  // One exchange before answering anyone, so the first read sees real state.
  s.Exchange(0.0);
  s.last_exchange = Clock::now();
  s.net_thread = std::thread([&s] { s.NetworkLoop(); });
  s.machine_loop.Start(options_.machine_period_s, [&s](double) { s.MachineTick(); });
  running_.store(true);
  return true;
}

void ModbusMachineServer::Stop() {
  if (!running_.exchange(false)) return;
  Impl& s = *impl_;
  {
    std::lock_guard<std::mutex> lock(s.mu);
    s.stop.store(true);
  }
  s.machine_loop.Stop();
  const char b = 1;
  [[maybe_unused]] auto w = write(s.wake_pipe[1], &b, 1);
  if (s.net_thread.joinable()) s.net_thread.join();
  close(s.listen_fd);
  s.listen_fd = -1;
  for (int& fd : s.wake_pipe) {
    close(fd);
    fd = -1;
  }
  std::lock_guard<std::mutex> lock(s.mu);
  s.stats.clients = 0;
}

ModbusMachineServerStats ModbusMachineServer::Stats() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->stats;
}

}  // namespace trueaxis::drivers
