#include "trueaxis/sim_shop/virtual_shop.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <random>
#include <thread>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/drivers/event_loop.hpp"
#include "trueaxis/drivers/mbap.hpp"
#include "trueaxis/drivers/open_file_limit.hpp"
#include "trueaxis/drivers/terminal_registers.hpp"
#include "trueaxis/drivers/thread_cpu.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {
namespace {

namespace pmc = drivers::pmc;
namespace adam = drivers::adam6015;
namespace mbap = drivers::mbap;
using drivers::EventLoop;
using Clock = std::chrono::steady_clock;

struct Terminal;

// What an epoll event belongs to.
struct Endpoint {
  Terminal* terminal = nullptr;
  int fd = -1;
  bool listening = false;
  std::uint8_t in[2 * mbap::kMaxFrameBytes];
  std::size_t in_len = 0;
};

struct DelayedReply {
  double due_s;
  Endpoint* connection;
  std::uint64_t connection_serial;
  std::vector<std::uint8_t> bytes;
};

// One virtual machine behind its terminal's register image.
struct Terminal {
  std::size_t index = 0;
  std::string name;
  int port = 0;
  std::unique_ptr<sim::VirtualMachine> vm;
  std::vector<std::string> axes, channels;
  Endpoint listener;
  std::vector<std::unique_ptr<Endpoint>> connections;
  std::uint16_t ir[pmc::kInputRegisterCount] = {};
  std::uint16_t hr[pmc::kHoldingImageCount] = {};  // enable, command block, the window's copy
  std::vector<std::array<std::uint16_t, adam::kRegisterCount>> modules;
  std::vector<std::array<std::uint8_t, adam::kCoilCount>> coils;
  std::vector<hw::AxisState> axis_state;
  std::vector<hw::RawTemperature> raw;
  std::vector<double> command_um, applied_um;
  std::vector<bool> history_valid;  // per channel: the module's max/min hold a reading
  drivers::TravelCounter travel;
  bool temperatures_online = false;
  std::uint32_t heartbeat = 0;
  double last_client_write_s = 0;
  double last_tick_s = 0;
  double next_tick_s = 0;
  // The day: work (reciprocating) with coolant for part of it, then idle, on this machine's own schedule.
  double day_offset_s = 0;
  CoolantState work_coolant = CoolantState::kFlood;
  int day_phase = -1;
  TerminalFault fault = TerminalFault::kNone;
  double fault_delay_s = 0;
  std::array<std::uint64_t, 24> requests_by_function{};  // function codes 1…23 received
};

}  // namespace

bool VirtualShopOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string m) {
    if (why) *why = std::move(m);
    return false;
  };
  if (machine_files.empty()) return fail("no machine description given");
  if (machines < 1 || machines > 20000) return fail("machines must be in 1..20000");
  if (base_port < 1 || base_port + machines - 1 > 65535) return fail("base_port + machines - 1 must stay within 1..65535");
  if (!(time_scale > 0 && time_scale <= 1e5)) return fail("time_scale must be in (0, 100000]");
  if (!(tick_s >= 0.001 && tick_s <= 10)) return fail("tick_s must be in [0.001, 10] s");
  if (!(watchdog_s >= 0)) return fail("watchdog_s must be >= 0 (0 = hold)");
  if (!(watchdog_ramp_um_per_s > 0)) return fail("watchdog_ramp_um_per_s must be > 0");
  if (!(day_s > 0)) return fail("day_s must be > 0");
  return true;
}

struct VirtualShop::Impl {
  VirtualShopOptions opt;
  std::vector<std::unique_ptr<Terminal>> terminals;
  EventLoop loop;
  int epoll_fd = loop.epoll_fd();
  std::atomic<bool> faults_changed{false};
  Clock::time_point t0 = Clock::now();
  mutable std::mutex mu;  // stats, faults, applied values (the loop holds it while handling a machine)
  VirtualShopStats stats;
  std::deque<DelayedReply> delayed;  // loop thread only
  std::uint64_t serial = 0;

  std::unique_ptr<Terminal> MakeTerminal(int i, const sim::MachineDescription& description) const {
    auto t = std::make_unique<Terminal>();
    t->index = static_cast<std::size_t>(i);
    t->name = fmt::format("vm-{:04d}", i);
    t->port = opt.base_port + i;
    t->vm = std::make_unique<sim::VirtualMachine>(description,
                                                  opt.seed + static_cast<std::uint64_t>(i));
    for (std::size_t a = 0; a < t->vm->AxisCount(); ++a) t->axes.push_back(t->vm->AxisName(a));
    for (std::size_t c = 0; c < t->vm->ChannelCount(); ++c) t->channels.push_back(t->vm->ChannelName(c));
    if (t->axes.size() > pmc::kMaxAxes) throw InputError("virtual shop", "a machine has more axes than the PMC window holds");
    t->axis_state.resize(t->axes.size());
    t->raw.resize(t->channels.size());
    t->command_um.assign(t->axes.size(), 0.0);
    t->applied_um.assign(t->axes.size(), 0.0);
    t->history_valid.assign(t->channels.size(), false);
    t->travel = drivers::TravelCounter(t->axes.size());
    drivers::InitPmcImage(t->ir, t->hr, t->axes.size(), true);
    const std::size_t modules = drivers::RtdModulesFor(t->channels.size());
    t->modules.resize(modules);
    t->coils.resize(modules);
    for (std::size_t k = 0; k < modules; ++k) {
      drivers::InitRtdModule(t->modules[k].data(), ModuleChannels(*t, k), adam::kDefaultRangeCode);
      t->coils[k].fill(0);
    }
    std::mt19937_64 rng(opt.seed * 7919 + static_cast<std::uint64_t>(i));
    t->day_offset_s = std::uniform_real_distribution<double>(0, opt.day_s)(rng);
    t->work_coolant = static_cast<CoolantState>(1 + i % 3);
    return t;
  }

  double Now() const { return std::chrono::duration<double>(Clock::now() - t0).count(); }

  std::size_t ModuleChannels(const Terminal& t, std::size_t k) const {
    return drivers::RtdModuleChannels(t.channels.size(), k);
  }

  bool Listen(Terminal& t, std::string* error) {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(t.port));
    inet_pton(AF_INET, opt.bind_address.c_str(), &a.sin_addr);
    if (bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || listen(fd, 64) != 0) {
      if (error) *error = fmt::format("cannot listen on {}:{}: {}", opt.bind_address, t.port, std::strerror(errno));
      close(fd);
      return false;
    }
    t.listener.fd = fd;
    t.listener.listening = true;
    t.listener.terminal = &t;
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.ptr = &t.listener;
    epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &ev);
    return true;
  }

  void CloseListener(Terminal& t) {
    if (t.listener.fd < 0) return;
    epoll_ctl(epoll_fd, EPOLL_CTL_DEL, t.listener.fd, nullptr);
    close(t.listener.fd);
    t.listener.fd = -1;
  }

  void CloseConnection(Terminal& t, Endpoint* c) {
    epoll_ctl(epoll_fd, EPOLL_CTL_DEL, c->fd, nullptr);
    close(c->fd);
    std::erase_if(delayed, [c](const DelayedReply& d) { return d.connection == c; });
    std::erase_if(t.connections, [c](const std::unique_ptr<Endpoint>& e) { return e.get() == c; });
  }

  // ---------------------------------------------------------------- machine side
  void ApplyDay(Terminal& t) {
    const double u = std::fmod(t.vm->TimeS() + t.day_offset_s, opt.day_s) / opt.day_s;
    const int phase = u < 0.35 ? 0 : u < 0.7 ? 1 : 2;  // work, work with coolant, idle
    if (phase == t.day_phase) return;
    t.day_phase = phase;
    t.vm->SetCoolant(phase == 1 ? t.work_coolant : CoolantState::kOff);
    for (std::size_t a = 0; a < t.axes.size(); ++a) {
      if (phase == 2) {
        t.vm->CommandStop(a);
      } else {
        const double travel = t.vm->description().axes[a].travel_mm;
        t.vm->CommandReciprocate(a, 0.1 * travel, 0.9 * travel, 2000 + 200.0 * static_cast<double>(t.index % 11), 0.7);
      }
    }
  }

  void Forward(Terminal& t) {
    drivers::DecodeCommand(t.hr + pmc::kHrCompensationBase, t.command_um);
    const bool ok = t.vm->WriteCompensation(t.command_um);
    if (ok) t.applied_um = t.command_um;
    drivers::EncodeWriteResult(ok, t.applied_um, t.ir);
    drivers::CopyWindowToHolding(t.ir, t.hr, t.axes.size());
  }

  void TickMachine(Terminal& t, double now) {
    const double elapsed = now - t.last_tick_s;
    t.last_tick_s = now;
    ApplyDay(t);
    if (elapsed > 0) t.vm->Advance(elapsed * opt.time_scale);
    hw::CncState state;
    const bool read_ok = t.vm->Read(t.axis_state, state);
    const bool temps_ok = t.vm->Read(std::span<hw::RawTemperature>(t.raw));
    if (read_ok) t.travel.Update(t.axis_state);
    ++t.heartbeat;
    drivers::PmcExchange e;
    e.heartbeat = t.heartbeat;
    e.machine_read_ok = read_ok;
    e.temperatures_read_ok = temps_ok;
    e.machine = state;
    e.axes = t.axis_state;
    e.travel_mm = t.travel.travel_mm();
    e.read_age_ms = 0;  // the virtual machine is read in the same tick
    drivers::EncodePmcState(e, t.ir, t.hr);
    t.temperatures_online = temps_ok;
    if (temps_ok) {
      for (std::size_t ch = 0; ch < t.channels.size(); ++ch) {
        const std::size_t k = ch / adam::kChannelCount, c = ch % adam::kChannelCount;
        auto& m = t.modules[k];
        bool valid = t.history_valid[ch];
        drivers::EncodeRtdChannel(t.raw[ch], *drivers::FindRtdRange(m[adam::kTypeCodeAddress + c]), c, m.data(),
                                  t.coils[k].data(), &valid);
        t.history_valid[ch] = valid;
      }
    }
    // The terminal's watchdog: no client write for watchdog_s → the command ramps to 0, forwarding each step.
    const drivers::CommandWatchdog watchdog{opt.watchdog_s, opt.watchdog_ramp_um_per_s};
    const bool ramped = watchdog.Step(t.ir, t.hr, t.axes.size(), now - t.last_client_write_s, elapsed);
    drivers::CopyWindowToHolding(t.ir, t.hr, t.axes.size());
    if (ramped) {
      ++stats.watchdog_steps;
      Forward(t);
    }
    ++stats.ticks;
  }

  // ---------------------------------------------------------------- network side
  // The answer to one request (0 bytes: none).
  std::size_t Answer(Terminal& t, const mbap::ParsedRequest& q, bool parsed, std::uint8_t* out, double now) {
    const mbap::Request& h = q.head;
    ++stats.requests;
    if (h.function < t.requests_by_function.size()) ++t.requests_by_function[h.function];
    auto refuse = [&](std::uint8_t code) {
      ++stats.exceptions;
      return mbap::EncodeException(out, h, code);
    };
    const bool known = h.function == mbap::kReadCoils || h.function == mbap::kReadHoldingRegisters ||
                       h.function == mbap::kReadInputRegisters || h.function == mbap::kWriteSingleRegister ||
                       h.function == mbap::kWriteMultipleRegisters || h.function == mbap::kReadWriteMultipleRegisters;
    if (!known || (h.function == mbap::kReadWriteMultipleRegisters && t.fault == TerminalFault::kNoReadWrite))
      return refuse(mbap::kIllegalFunction);
    if (!parsed) return refuse(mbap::kIllegalDataValue);
    const int end = h.address + h.count;
    if (h.unit == opt.pmc_unit_id) {
      const int hr_writable = drivers::PmcHoldingLength(t.axes.size());
      const int hr_count = drivers::PmcHoldingImageLength(t.axes.size());
      switch (h.function) {
        case mbap::kReadInputRegisters:
          if (end > pmc::InputWindowLength(t.axes.size())) return refuse(mbap::kIllegalDataAddress);
          return mbap::EncodeRegistersReply(out, h, t.ir + h.address);
        case mbap::kReadHoldingRegisters:
          if (end > hr_count) return refuse(mbap::kIllegalDataAddress);
          return mbap::EncodeRegistersReply(out, h, t.hr + h.address);
        case mbap::kWriteSingleRegister:
        case mbap::kWriteMultipleRegisters:
        case mbap::kReadWriteMultipleRegisters: {
          // FC 23: the write part first, then the read part (the window's copy after the CNC took the command)
          const bool read_write = h.function == mbap::kReadWriteMultipleRegisters;
          if (read_write && end > hr_count) return refuse(mbap::kIllegalDataAddress);
          std::uint16_t candidate[pmc::kHoldingRegisterCount];
          const int ex = drivers::CheckPmcWrite(t.hr, t.axes.size(), read_write ? q.write_address : h.address,
                                                read_write ? q.write_count : h.count,
                                                [v = q.values](int i) { return mbap::WordAt(v, i); },
                                                opt.max_compensation_um, candidate);
          if (ex != 0) return refuse(static_cast<std::uint8_t>(ex));
          std::copy(candidate, candidate + hr_writable, t.hr);
          t.last_client_write_s = now;
          ++stats.compensation_writes;
          Forward(t);
          return read_write ? mbap::EncodeRegistersReply(out, h, t.hr + h.address) : mbap::EncodeWriteReply(out, q);
        }
        default:
          return refuse(mbap::kIllegalFunction);
      }
    }
    const int k = h.unit - opt.first_rtd_unit_id;
    if (k < 0 || k >= static_cast<int>(t.modules.size())) return refuse(mbap::kGatewayTargetFailed);
    if (!t.temperatures_online) return refuse(mbap::kGatewayTargetFailed);
    auto& m = t.modules[static_cast<std::size_t>(k)];
    switch (h.function) {
      case mbap::kReadHoldingRegisters:
      case mbap::kReadInputRegisters:
        if (end > adam::kRegisterCount) return refuse(mbap::kIllegalDataAddress);
        return mbap::EncodeRegistersReply(out, h, m.data() + h.address);
      case mbap::kReadCoils:
        if (end > adam::kCoilCount) return refuse(mbap::kIllegalDataAddress);
        return mbap::EncodeBitsReply(out, h, t.coils[static_cast<std::size_t>(k)].data() + h.address);
      case mbap::kWriteSingleRegister:
      case mbap::kWriteMultipleRegisters: {
        const int ex = drivers::CheckRtdTypeCodeWrite(ModuleChannels(t, static_cast<std::size_t>(k)), h.address, h.count,
                                                      [v = q.values](int i) { return mbap::WordAt(v, i); });
        if (ex != 0) return refuse(static_cast<std::uint8_t>(ex));
        for (int i = 0; i < h.count; ++i) {
          const auto a = static_cast<std::size_t>(h.address + i);
          const std::uint16_t code = mbap::WordAt(q.values, i);
          if (m[a] != code) t.history_valid[static_cast<std::size_t>(k) * adam::kChannelCount + a - adam::kTypeCodeAddress] = false;
          m[a] = code;  // a new scale: max/min restart with the next reading
        }
        return mbap::EncodeWriteReply(out, q);
      }
      default:
        return refuse(mbap::kIllegalFunction);
    }
  }

  // False: close the connection.
  bool Serve(Terminal& t, Endpoint& c, double now) {
    for (;;) {
      const ssize_t n = recv(c.fd, c.in + c.in_len, sizeof c.in - c.in_len, 0);
      if (n == 0) return false;
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK) break;
        if (errno == EINTR) continue;
        return false;
      }
      const bool drained = static_cast<std::size_t>(n) < sizeof c.in - c.in_len;  // no second recv to hear EAGAIN
      c.in_len += static_cast<std::size_t>(n);
      if (drained || c.in_len == sizeof c.in) break;  // level-triggered: more data wakes the loop again
    }
    while (c.in_len > 0) {
      const int frame = mbap::FrameLength({c.in, c.in_len});
      if (frame < 0) return false;
      if (frame == 0) break;
      std::uint8_t reply[mbap::kMaxFrameBytes];
      std::size_t len = 0;
      std::lock_guard<std::mutex> lock(mu);
      const TerminalFault fault = t.fault;
      if (fault == TerminalFault::kDropMidRequest) return false;
      if (c.in[mbap::kHeaderBytes] >= 0x80) return false;  // an exception code as a request: not MODBUS
      if (fault != TerminalFault::kSilent) {
        mbap::ParsedRequest q;
        const bool parsed = mbap::ParseRequest({c.in, static_cast<std::size_t>(frame)}, &q);
        len = Answer(t, q, parsed, reply, now);
        if (fault == TerminalFault::kWrongUnit && len > 6) reply[6] = static_cast<std::uint8_t>(reply[6] + 7);
        if (fault == TerminalFault::kGarbage) {
          static constexpr char kJunk[] = "HTTP/1.1 400 Bad Request\r\n\r\n";
          len = sizeof kJunk - 1;
          std::memcpy(reply, kJunk, len);
        }
      }
      std::memmove(c.in, c.in + frame, c.in_len - static_cast<std::size_t>(frame));
      c.in_len -= static_cast<std::size_t>(frame);
      if (len == 0) continue;
      if (fault == TerminalFault::kSlow) {
        delayed.push_back({now + t.fault_delay_s, &c, 0, std::vector<std::uint8_t>(reply, reply + len)});
        continue;
      }
      if (send(c.fd, reply, len, MSG_NOSIGNAL) != static_cast<ssize_t>(len)) return false;
    }
    return true;
  }

  void Accept(Terminal& t) {
    for (;;) {
      const int fd = accept4(t.listener.fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) return;
      int one = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      if (t.connections.size() >= 16) CloseConnection(t, t.connections.front().get());  // the oldest makes room
      auto c = std::make_unique<Endpoint>();
      c->fd = fd;
      c->terminal = &t;
      epoll_event ev{};
      ev.events = EPOLLIN | EPOLLRDHUP;
      ev.data.ptr = c.get();
      epoll_ctl(epoll_fd, EPOLL_CTL_ADD, fd, &ev);
      t.connections.push_back(std::move(c));
      std::lock_guard<std::mutex> lock(mu);
      ++stats.connections;
    }
  }

  void Loop() {
    std::vector<epoll_event> events(1024);
    std::size_t next = 0;  // ticks come round robin: the start staggered them and they share one period
    while (!loop.stopping()) {
      double now = Now();
      for (std::size_t k = 0; k < std::min<std::size_t>(terminals.size(), 64); ++k) {  // then serve the network
        Terminal& t = *terminals[next];
        if (t.next_tick_s > now) break;
        t.next_tick_s += opt.tick_s;
        if (t.next_tick_s < now) t.next_tick_s = now + opt.tick_s;
        std::lock_guard<std::mutex> lock(mu);
        TickMachine(t, now);
        next = (next + 1) % terminals.size();
      }
      while (!delayed.empty() && delayed.front().due_s <= now) {
        DelayedReply d = std::move(delayed.front());
        delayed.pop_front();
        [[maybe_unused]] auto n = send(d.connection->fd, d.bytes.data(), d.bytes.size(), MSG_NOSIGNAL);
      }
      // Answers at once (no batching here: a terminal that made its client wait would favour a client
      // that keeps many requests in flight over one that asks each terminal in turn).
      const int n = epoll_wait(epoll_fd, events.data(), static_cast<int>(events.size()), 2);
      now = Now();
      for (int i = 0; i < n; ++i) {
        if (events[i].data.u64 == EventLoop::kWakeToken) continue;
        auto* e = static_cast<Endpoint*>(events[i].data.ptr);
        Terminal& t = *e->terminal;
        if (e->listening) {
          Accept(t);
        } else if (!Serve(t, *e, now)) {
          CloseConnection(t, e);
        }
      }
      // Faults the loop must act on: a terminal "down" closes its port and connections.
      if (!faults_changed.exchange(false)) continue;
      std::lock_guard<std::mutex> lock(mu);
      for (auto& tp : terminals) {
        Terminal& t = *tp;
        if (t.fault == TerminalFault::kDown && t.listener.fd >= 0) {
          CloseListener(t);
          while (!t.connections.empty()) CloseConnection(t, t.connections.front().get());
        } else if (t.fault != TerminalFault::kDown && t.listener.fd < 0) {
          Listen(t, nullptr);
        }
      }
    }
  }
};

VirtualShop::VirtualShop(VirtualShopOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.opt = std::move(options);
  std::string why;
  if (!s.opt.IsValid(&why)) throw InputError("virtual shop", why);
  std::vector<sim::MachineDescription> descriptions;
  for (const auto& f : s.opt.machine_files) descriptions.push_back(sim::ReadMachineFile(f));
  s.terminals.resize(static_cast<std::size_t>(s.opt.machines));
  // A virtual machine takes ~20 ms to build (its thermal network soaked overnight): build them on every core.
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mu;
  auto build = [&] {
    for (int i = next++; i < s.opt.machines; i = next++) {
      try {
        s.terminals[static_cast<std::size_t>(i)] = s.MakeTerminal(i, descriptions[static_cast<std::size_t>(i) % descriptions.size()]);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mu);
        failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> workers;
  for (unsigned k = 1; k < std::max(1u, std::thread::hardware_concurrency()); ++k) workers.emplace_back(build);
  build();
  for (auto& w : workers) w.join();
  if (failure) std::rethrow_exception(failure);
}

VirtualShop::~VirtualShop() { Stop(); }

bool VirtualShop::Start(std::string* error) {
  Impl& s = *impl_;
  if (!drivers::EnsureOpenFileLimit(2 * s.terminals.size() + 64, error)) return false;  // a listener + a connection each
  const double now = s.Now();
  for (auto& t : s.terminals) {
    if (!s.Listen(*t, error)) {
      for (auto& u : s.terminals) s.CloseListener(*u);
      return false;
    }
    t->last_tick_s = now;
    t->last_client_write_s = now;
    t->next_tick_s = now + s.opt.tick_s * static_cast<double>(t->index) / static_cast<double>(s.terminals.size());
    s.TickMachine(*t, now);  // registers hold real state before the first request
  }
  s.loop.Start([&s] { s.Loop(); });
  return true;
}

void VirtualShop::Stop() {
  Impl& s = *impl_;
  if (!s.loop.Stop()) return;
  for (auto& t : s.terminals) {
    s.CloseListener(*t);
    while (!t->connections.empty()) s.CloseConnection(*t, t->connections.front().get());
  }
}

std::vector<VirtualMachineInfo> VirtualShop::Machines() const {
  std::vector<VirtualMachineInfo> out;
  for (const auto& t : impl_->terminals) out.push_back({t->name, t->vm->description().name, t->port, t->axes, t->channels});
  return out;
}

VirtualShopStats VirtualShop::Stats() const {
  VirtualShopStats s;
  {
    std::lock_guard<std::mutex> lock(impl_->mu);
    s = impl_->stats;
  }
  s.loop_cpu_s = drivers::ThreadCpuSeconds(impl_->loop.thread());
  return s;
}

void VirtualShop::SetFault(std::size_t machine, TerminalFault fault, double delay_s) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Terminal& t = *impl_->terminals.at(machine);
  t.fault = fault;
  t.fault_delay_s = delay_s;
  impl_->faults_changed.store(true);
}

std::vector<double> VirtualShop::AppliedUm(std::size_t machine) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return impl_->terminals.at(machine)->applied_um;
}

bool VirtualShop::WatchdogRamping(std::size_t machine) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return (impl_->terminals.at(machine)->ir[pmc::kIrStatus] & pmc::kStatusWatchdogRamping) != 0;
}

std::uint64_t VirtualShop::Requests(std::size_t machine, int function) const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  const auto& counts = impl_->terminals.at(machine)->requests_by_function;
  return function >= 0 && static_cast<std::size_t>(function) < counts.size() ? counts[static_cast<std::size_t>(function)] : 0;
}

VirtualMachine& VirtualShop::Machine(std::size_t machine) { return *impl_->terminals.at(machine)->vm; }
std::mutex& VirtualShop::MachineMutex() { return impl_->mu; }

std::string ShopFileFor(const std::vector<VirtualMachineInfo>& machines, const std::string& bind_address,
                        const std::string& model_file, const std::string& history, double period_s, int http_port) {
  auto list = [](const std::vector<std::string>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += fmt::format("{}\"{}\"", i ? ", " : "", v[i]);
    return s + "]";
  };
  std::string out = fmt::format("# Shop file for `trueaxis server` (docs/server.md), written by `trueaxis sim shop`.\n"
                                "history = \"{}\"\n", history);
  if (http_port > 0) out += fmt::format("\n[http]\nport = {}\n", http_port);
  for (const auto& m : machines)
    out += fmt::format("\n[[machine]]\nname = \"{}\"   # {}\nhost = \"{}\"\nport = {}\naxes = {}\nrtd_channels = {}\n"
                       "model = \"{}\"\nperiod_s = {}\n",
                       m.name, m.description, bind_address, m.port, list(m.axes), list(m.channels), model_file, period_s);
  return out;
}

}  // namespace trueaxis::sim
