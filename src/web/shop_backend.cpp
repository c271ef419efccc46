#include "trueaxis/web/shop_backend.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"
#include "trueaxis/server/http_api.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/web/history_files.hpp"
#include "trueaxis/web/model_figures.hpp"

namespace trueaxis::web {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double NowUnixS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double ValueOrNaN(const server::Reading& r) { return r ? *r : kNaN; }  // UNAVAILABLE is never a number

// The model files a machine has run, oldest first (its start model, then every file loaded since).
std::vector<ModelRevision> FilesRun(const server::MachineStatus& m, const std::vector<server::ModelChange>& changes) {
  std::vector<ModelRevision> out;
  auto add = [&](const server::ModelInfo& info, double unix_s) {
    for (auto& r : out)
      if (r.revision == info.file) {
        r.sha256 = info.sha256;
        r.label = fmt::format("revision {} of {}", info.revision, info.file);
        return;
      }
    out.push_back({info.file, info.sha256, fmt::format("revision {} of {}", info.revision, info.file), unix_s});
  };
  if (!changes.empty()) add(changes.front().old_model, 0);
  for (const auto& c : changes) add(c.new_model, c.time_unix_s);
  if (changes.empty() && !m.model.file.empty()) add(m.model, 0);
  return out;
}
}  // namespace

ShopBackend::ShopBackend(server::Shop& shop, store::HistoryWriter* history, ShopBackendOptions options)
    : shop_(shop), history_(history), options_(std::move(options)) {
  if (!(options_.sample_period_s > 0)) throw InputError("web", 0, "sample_period_s", "must be > 0");
  const auto& machines = shop_.config().machines;
  for (std::size_t i = 0; i < machines.size(); ++i) index_[machines[i].name] = i;
  live_.assign(machines.size(), LiveRing(options_.live_capacity));
}

ShopBackend::~ShopBackend() { Stop(); }

void ShopBackend::Sample(double unix_s) {
  const std::vector<server::MachineStatus> shop = shop_.Snapshot();
  for (const auto& m : shop) {
    const auto it = index_.find(m.name);
    if (it == index_.end()) continue;
    LiveSample s{0, unix_s, {}, {}};
    for (const auto& c : m.channels) s.temp_c.push_back(ValueOrNaN(c.temp_c));
    for (const auto& a : m.axes) s.correction_um.push_back(a.output_um);
    {
      std::lock_guard lock(mutex_);
      live_[it->second].Push(std::move(s));
    }
    alarms_.Update(m.name, runtime::SplitAlarmNames(m.alarm_names), unix_s,
                   m.last_fault.empty() ? std::map<std::string, std::string>{}
                                        : std::map<std::string, std::string>{{"link_read", m.last_fault}});
  }
}

void ShopBackend::Start() {
  worker_.Start(options_.sample_period_s, [this](double) { Sample(NowUnixS()); });
}

void ShopBackend::Stop() { worker_.Stop(); }

std::string ShopBackend::Describe() const { return fmt::format("shop: {} machines", index_.size()); }

server::MachineStatus ShopBackend::StatusOrThrow(const std::string& id) const {
  auto m = shop_.Machine(id);
  if (!m) throw BackendError(404, "no machine '" + id + "' in this shop");
  return std::move(*m);
}

const server::MachineConfig& ShopBackend::ConfigOrThrow(const std::string& id) const {
  const auto it = index_.find(id);
  if (it == index_.end()) throw BackendError(404, "no machine '" + id + "' in this shop");
  return shop_.config().machines[it->second];
}

std::vector<MachineSummary> ShopBackend::ListMachines() const {
  std::vector<MachineSummary> out;
  for (const auto& m : shop_.Snapshot()) out.push_back(server::MachineViewOf(m));
  return out;
}

ShopBackend::Figures ShopBackend::FiguresOf(const server::ModelInfo& model) const {
  {
    std::lock_guard lock(mutex_);
    if (const auto it = figures_.find(model.sha256); it != figures_.end()) return it->second;
  }
  Figures f;
  try {
    // Only the file that was loaded: one rewritten since would show another model's figures.
    if (model::Sha256OfFile(model.file) != model.sha256)
      f.missing = model.file + " has changed since it was loaded";
    else
      f.figures = FiguresFromFitSummary(model::ReadModelFile(model.file));
  } catch (const std::exception& e) {
    f.missing = e.what();  // the model still runs; the page says why its figures are not shown
  }
  std::lock_guard lock(mutex_);
  figures_[model.sha256] = f;
  return f;
}

MachineDetail ShopBackend::Machine(const std::string& id) const {
  const server::MachineStatus m = StatusOrThrow(id);
  MachineDetail d{server::MachineViewOf(m), {}};
  if (!m.model.file.empty()) {
    d.model.label = fmt::format("revision {} of {}", m.model.revision, m.model.file);
    const Figures f = FiguresOf(m.model);
    d.model.figures = f.figures;
    if (!f.missing.empty()) d.model.label += " (before/after figures not shown: " + f.missing + ")";
  }
  d.model.available = FilesRun(m, shop_.ModelChanges(id));
  return d;
}

LiveSeries ShopBackend::Live(const std::string& id, std::uint64_t after, std::size_t max_samples) const {
  const server::MachineConfig& c = ConfigOrThrow(id);
  LiveSeries s{c.channels, c.axes, 0, {}};
  std::lock_guard lock(mutex_);
  const LiveRing& ring = live_[index_.at(id)];
  s.last_sequence = ring.last_sequence();
  ring.CopyAfter(after, max_samples, s.samples);
  return s;
}

std::string ShopBackend::HistoryDbOrThrow() const {
  if (options_.history_db.empty())
    throw BackendError(409, "this shop keeps no SQLite history (history in the shop file)");
  if (history_) history_->Flush();  // the newest rows too
  return options_.history_db;
}

namespace {
HistorySelection MachineRows(const std::string& db, const server::MachineConfig& c) {
  HistorySelection s{db, {}, {}, c.name + "/"};
  for (const auto& ch : c.channels) s.channels.push_back(s.strip_prefix + ch);
  for (const auto& a : c.axes) s.axes.push_back(s.strip_prefix + a);
  return s;
}
}  // namespace

HistorySeries ShopBackend::History(const std::string& id, double from, double to, std::size_t max_points) const {
  const server::MachineConfig& c = ConfigOrThrow(id);
  return ReadHistorySeries(MachineRows(HistoryDbOrThrow(), c), from, to, max_points);
}

ExportFile ShopBackend::Export(const std::string& id, double from, double to, ExportFormat format) const {
  const server::MachineConfig& c = ConfigOrThrow(id);
  return ExportHistory(MachineRows(HistoryDbOrThrow(), c), from, to, format, id);
}

std::vector<AlarmEntry> ShopBackend::Alarms(std::size_t limit) const { return alarms_.Newest(limit); }

void ShopBackend::SetAxisEnabled(const Actor& who, const std::string& id, const std::string& axis, bool enabled) {
  const server::MachineConfig& c = ConfigOrThrow(id);
  if (std::find(c.axes.begin(), c.axes.end(), axis) == c.axes.end())
    throw BackendError(404, "machine '" + id + "' has no axis '" + axis + "'");
  shop_.SetAxisEnabled(id, axis, enabled, who.user);
}

void ShopBackend::AcknowledgeAlarm(const Actor& who, const std::string& alarm_id) {
  std::string machine;
  for (const auto& e : alarms_.Newest(std::numeric_limits<std::size_t>::max()))
    if (e.id == alarm_id) machine = e.machine_id;
  alarms_.Acknowledge(alarm_id, who.user, NowUnixS());  // 404 / 409 from the book
  if (!machine.empty()) shop_.AcknowledgeAlarms(machine, who.user);
}

void ShopBackend::SetCoolantOverride(const Actor& who, const std::string& id, const std::string& state) {
  ConfigOrThrow(id);
  if (state.empty()) return shop_.SetCoolantOverride(id, std::nullopt, who.user);
  const auto parsed = ParseCoolantState(state);
  if (!parsed) throw BackendError(400, "coolant state '" + state + "' is not one of off, flood, mist, air (or \"\" to clear)");
  shop_.SetCoolantOverride(id, parsed, who.user);
}

void ShopBackend::LoadModelRevision(const Actor& who, const std::string& id, const std::string& revision) {
  const server::MachineStatus m = StatusOrThrow(id);
  bool known = false;
  for (const auto& r : FilesRun(m, shop_.ModelChanges(id))) known |= r.revision == revision;
  if (!known)
    throw BackendError(404, "machine '" + id + "' has not run the model '" + revision +
                                "' (new files are loaded with `trueaxis server model load`)");
  try {
    shop_.LoadModel(id, revision, who.user, who.remote);
  } catch (const std::exception& e) {
    throw BackendError(409, std::string("the model was not loaded: ") + e.what());
  }
}

std::string ShopBackend::RollbackModel(const Actor& who, const std::string& id) {
  ConfigOrThrow(id);
  try {
    return shop_.Rollback(id, who.user, who.remote).new_model.file;
  } catch (const std::exception& e) {
    throw BackendError(409, e.what());
  }
}

}  // namespace trueaxis::web
