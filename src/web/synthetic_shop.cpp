#include "trueaxis/web/synthetic_shop.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/store/time_text.hpp"

namespace trueaxis::web {

namespace {
double NowUnixS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
const char* const kKinds[] = {"vmc850", "hmc800", "lathe_tc620", "gantry2000", "vmc400"};
runtime::MachineModelView ModelOf(const std::string& id, const std::string& revision) {
  return {revision, fmt::format("{:064x}", std::hash<std::string>{}(id + revision)), ""};
}
}  // namespace

const std::vector<std::string> SyntheticShop::kAxes = {"X", "Y", "Z"};
const std::vector<std::string> SyntheticShop::kChannels = {"spindle", "x_nut", "bed", "ambient"};

SyntheticShop::SyntheticShop(std::size_t machine_count, std::size_t live_capacity) : start_unix_s_(NowUnixS()) {
  machines_.reserve(machine_count);
  for (std::size_t i = 0; i < machine_count; ++i) {
    Machine_ m;
    m.live = LiveRing(live_capacity);
    m.summary.id = fmt::format("m{:04d}", i + 1);
    m.summary.name = fmt::format("{}-{:04d}", kKinds[i % std::size(kKinds)], i + 1);
    m.summary.connected = i % 250 != 7;  // a few machines are off the network
    m.summary.coolant = i % 3 == 0 ? "flood" : "off";
    for (const auto& a : kAxes) m.summary.axes.push_back({.name = a, .enabled = true, .state = "full"});
    for (const auto& c : kChannels) m.summary.channels.push_back({.name = c});
    m.revision_stack = {"1", std::to_string(2 + i % 2)};
    m.summary.model = ModelOf(m.summary.id, m.revision_stack.back());
    m.phase = 2 * std::numbers::pi * static_cast<double>((i * 7919) % 1000) / 1000.0;
    m.gain = 0.8 + 0.4 * static_cast<double>((i * 104729) % 100) / 100.0;
    machines_.push_back(std::move(m));
  }
}

SyntheticShop::~SyntheticShop() { Stop(); }

std::string SyntheticShop::Describe() const { return fmt::format("synthetic shop: {} machines", machines_.size()); }

void SyntheticShop::Evaluate(const Machine_& m, double t, std::vector<double>& temp_c, std::vector<double>& corr_um) const {
  const double since = std::max(0.0, t - start_unix_s_ + 1800);
  const double warm = 6.0 * (1 - std::exp(-since / 3600.0));
  const double day = 1.5 * std::sin(2 * std::numbers::pi * t / 86400.0 + m.phase);
  const double wobble = 0.5 * std::sin(2 * std::numbers::pi * t / 20.0 + m.phase);  // visible second by second
  temp_c = {22 + 1.6 * warm + day + wobble, 22 + warm + day + 0.6 * wobble, 21.5 + 0.4 * warm + 0.5 * day,
            21 + day};
  corr_um = {-m.gain * 2.0 * (temp_c[1] - 21.0), -m.gain * 1.2 * (temp_c[2] - 21.0), -m.gain * 3.0 * (temp_c[0] - 21.0)};
  for (std::size_t a = 0; a < corr_um.size(); ++a)
    if (!m.summary.axes[a].enabled) corr_um[a] = 0;
}

void SyntheticShop::Tick(double unix_s) {
  std::vector<std::pair<std::string, std::vector<std::string>>> alarm_updates;
  {
    std::unique_lock lock(mutex_);
    std::vector<double> temps, corr;
    for (std::size_t i = 0; i < machines_.size(); ++i) {
      Machine_& m = machines_[i];
      std::vector<std::string> alarms;
      if (!m.summary.connected) {
        alarms.push_back("link_read");
      } else {
        Evaluate(m, unix_s, temps, corr);
        for (std::size_t c = 0; c < temps.size(); ++c) m.summary.channels[c] = {kChannels[c], temps[c], "ok"};
        for (std::size_t a = 0; a < corr.size(); ++a) {
          m.summary.axes[a].correction_um = corr[a];
          m.summary.axes[a].position_mm = 250 + 200 * std::sin(unix_s / 7.0 + static_cast<double>(a) + m.phase);
        }
        m.summary.updated_unix_s = unix_s;
        m.live.Push(LiveSample{0, unix_s, temps, corr});
        if (i % 50 == 3) {
          alarms.push_back("sensor_held");
          m.summary.channels[1].health = "held";
        }
        if (i % 120 == 11 && std::sin(unix_s / 30.0) > 0) alarms.push_back("model_extrapolated");
      }
      m.summary.coolant = !m.summary.coolant_override.empty() ? m.summary.coolant_override : (i % 3 == 0 ? "flood" : "off");
      if (m.summary.alarms != alarms) {
        m.summary.alarms = alarms;
        alarm_updates.emplace_back(m.summary.id, alarms);
      }
    }
  }
  for (const auto& [id, names] : alarm_updates) alarms_.Update(id, names, unix_s);
}

void SyntheticShop::Start(double period_s) {
  Stop();
  Tick(NowUnixS());  // values before Start() returns
  ticker_.Start(period_s, [this](double) { Tick(NowUnixS()); });
}

void SyntheticShop::Stop() { ticker_.Stop(); }

std::size_t SyntheticShop::Index(const std::string& id) const {
  // ids are m0001 … in order: parse rather than search (1,000 machines, every poll).
  if (id.size() >= 2 && id[0] == 'm') {
    std::size_t n = 0;
    bool digits = true;
    for (std::size_t k = 1; k < id.size(); ++k) {
      if (!std::isdigit(static_cast<unsigned char>(id[k]))) digits = false;
      else n = n * 10 + static_cast<std::size_t>(id[k] - '0');
    }
    if (digits && n >= 1 && n <= machines_.size() && machines_[n - 1].summary.id == id) return n - 1;
  }
  throw BackendError(404, "no machine '" + id + "'");
}

std::vector<MachineSummary> SyntheticShop::ListMachines() const {
  std::shared_lock lock(mutex_);
  std::vector<MachineSummary> out;
  out.reserve(machines_.size());
  for (const auto& m : machines_) out.push_back(m.summary);
  return out;
}

MachineDetail SyntheticShop::Machine(const std::string& id) const {
  const std::size_t i = Index(id);
  std::shared_lock lock(mutex_);
  const Machine_& m = machines_[i];
  MachineDetail d{m.summary, {}};
  d.model.label = "synthetic model";
  for (int r = 1; r <= 3; ++r) d.model.available.push_back({std::to_string(r), "", "synthetic revision", 0});
  for (std::size_t a = 0; a < kAxes.size(); ++a)
    d.model.figures.push_back({kAxes[a], "E (bidirectional systematic positioning error)", 18.0 * m.gain + 4.0 * a,
                               3.5 + 0.5 * a, "synthetic"});
  return d;
}

LiveSeries SyntheticShop::Live(const std::string& id, std::uint64_t after, std::size_t max_samples) const {
  const std::size_t i = Index(id);
  LiveSeries s{kChannels, kAxes, 0, {}};
  std::shared_lock lock(mutex_);
  s.last_sequence = machines_[i].live.last_sequence();
  machines_[i].live.CopyAfter(after, max_samples, s.samples);
  return s;
}

HistorySeries SyntheticShop::History(const std::string& id, double from, double to, std::size_t max_points) const {
  const std::size_t i = Index(id);
  HistorySeries h{from, to, {}, {}, false};
  const double stored = std::floor(to - from) + 1;  // one stored point a second
  const std::size_t n = static_cast<std::size_t>(std::min<double>(std::max<std::size_t>(max_points, 2), stored));
  h.decimated = static_cast<double>(n) < stored;
  for (const auto& c : kChannels) h.temperatures.push_back({c, "C", {}});
  for (const auto& a : kAxes) h.corrections.push_back({a, "um", {}});
  std::shared_lock lock(mutex_);
  std::vector<double> temps, corr;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = n == 1 ? from : from + (to - from) * static_cast<double>(k) / static_cast<double>(n - 1);
    Evaluate(machines_[i], t, temps, corr);
    for (std::size_t c = 0; c < temps.size(); ++c) h.temperatures[c].points.push_back({t, temps[c]});
    for (std::size_t a = 0; a < corr.size(); ++a) h.corrections[a].points.push_back({t, corr[a]});
  }
  return h;
}

std::vector<AlarmEntry> SyntheticShop::Alarms(std::size_t limit) const { return alarms_.Newest(limit); }

void SyntheticShop::SetAxisEnabled(const Actor&, const std::string& id, const std::string& axis, bool enabled) {
  const std::size_t i = Index(id);
  std::unique_lock lock(mutex_);
  for (auto& a : machines_[i].summary.axes)
    if (a.name == axis) {
      a.enabled = enabled;
      return;
    }
  throw BackendError(404, "machine '" + id + "' has no axis '" + axis + "'");
}

void SyntheticShop::AcknowledgeAlarm(const Actor& who, const std::string& alarm_id) {
  alarms_.Acknowledge(alarm_id, who.user, NowUnixS());
}

void SyntheticShop::SetCoolantOverride(const Actor&, const std::string& id, const std::string& state) {
  if (!state.empty() && !ParseCoolantState(state))
    throw BackendError(400, "coolant state '" + state + "' is not one of off, flood, mist, air (or \"\" to clear)");
  const std::size_t i = Index(id);
  std::unique_lock lock(mutex_);
  machines_[i].summary.coolant_override = state;
  if (!state.empty()) machines_[i].summary.coolant = state;
}

void SyntheticShop::LoadModelRevision(const Actor&, const std::string& id, const std::string& revision) {
  if (revision != "1" && revision != "2" && revision != "3")
    throw BackendError(404, "machine '" + id + "' has no model revision '" + revision + "' (1, 2, 3)");
  const std::size_t i = Index(id);
  std::unique_lock lock(mutex_);
  machines_[i].revision_stack.push_back(revision);
  machines_[i].summary.model = ModelOf(id, revision);
}

std::string SyntheticShop::RollbackModel(const Actor&, const std::string& id) {
  const std::size_t i = Index(id);
  std::unique_lock lock(mutex_);
  auto& stack = machines_[i].revision_stack;
  if (stack.size() < 2) throw BackendError(409, "machine '" + id + "': no earlier model revision to roll back to");
  stack.pop_back();
  machines_[i].summary.model = ModelOf(id, stack.back());
  return stack.back();
}

ExportFile SyntheticShop::Export(const std::string& id, double from, double to, ExportFormat format) const {
  if (format == ExportFormat::kXlsx)
    throw BackendError(409, "the synthetic shop exports CSV only (xlsx comes from a history database: trueaxis run)");
  if (to - from > 86400) throw BackendError(409, "export at most one day of the synthetic shop at a time");
  const HistorySeries h = History(id, from, to, static_cast<std::size_t>(to - from) + 1);
  const auto& traces = format == ExportFormat::kCsvTemperature ? h.temperatures : h.corrections;
  std::string csv = "time_s,time_utc";
  for (const auto& t : traces) csv += "," + t.name + (format == ExportFormat::kCsvTemperature ? "_c" : "_correction_um");
  csv += "\n";
  for (std::size_t k = 0; !traces.empty() && k < traces[0].points.size(); ++k) {
    csv += fmt::format("{:.3f},{}", traces[0].points[k].unix_s, store::FormatUtc(traces[0].points[k].unix_s));
    for (const auto& t : traces) csv += fmt::format(",{:.3f}", t.points[k].value);
    csv += "\n";
  }
  return {fmt::format("{}_{}.csv", id, format == ExportFormat::kCsvTemperature ? "temperature" : "compensation"),
          "text/csv; charset=utf-8", std::move(csv)};
}

}  // namespace trueaxis::web
