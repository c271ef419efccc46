#include "trueaxis/web/run_backend.hpp"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/station/history_logger.hpp"
#include "trueaxis/web/history_files.hpp"
#include "trueaxis/web/model_figures.hpp"

namespace trueaxis::web {

namespace {
double NowUnixS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
}  // namespace

RunBackend::RunBackend(runtime::Compensator& compensator, CoolantOverrideLink* coolant, store::HistoryWriter* writer,
                       RunBackendOptions options)
    : compensator_(compensator), coolant_(coolant), writer_(writer), options_(std::move(options)),
      live_(options_.live_capacity) {
  const std::string& id = options_.machine_id;
  if (id.empty() || id.size() > 64 ||
      id.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") != std::string::npos)
    throw InputError("--machine-id", 0, "machine_id", "'" + id + "': 1 to 64 of A-Z a-z 0-9 _ . -");
  for (const auto& a : compensator_.axes()) axes_.push_back(a.axis);
  channels_ = compensator_.channel_names();
  summary_.id = options_.machine_id;
  summary_.name = options_.machine_name.empty() ? options_.machine_id : options_.machine_name;
  for (const auto& a : axes_) summary_.axes.push_back({.name = a, .state = "link_lost"});
  for (const auto& c : channels_) summary_.channels.push_back({.name = c});
  iso_figures_ = IsoFiguresFromLaserPairs(options_.iso_dir);
}

void RunBackend::OnRecord(const runtime::CycleRecord& r) {
  const double t = options_.unix0 + r.time_s;
  const std::vector<std::string> alarms = runtime::SplitAlarmNames(runtime::RecordAlarmNames(r, axes_));  // "no_model_for_axis(Y)"
  {
    std::lock_guard lock(mutex_);
    summary_.connected = r.link_read_ok;
    summary_.alarms = alarms;
    summary_.coolant = std::string(CoolantStateName(r.coolant));
    summary_.updated_unix_s = t;
    LiveSample s{0, t, {}, {}};
    for (std::size_t i = 0; i < r.axis_count && i < summary_.axes.size(); ++i) {
      summary_.axes[i].enabled = r.axes[i].enabled;
      summary_.axes[i].position_mm = r.axes[i].cnc_position_mm;
      summary_.axes[i].correction_um = r.axes[i].output_um;
      summary_.axes[i].target_um = r.axes[i].desired_um;
      summary_.axes[i].state =
          runtime::AxisCompensationState(r.link_read_ok, r.axes[i].enabled, r.axes[i].thermal_used, r.axes[i].fallback_model);
      s.correction_um.push_back(r.axes[i].output_um);
    }
    for (std::size_t i = 0; i < r.channel_count && i < summary_.channels.size(); ++i) {
      summary_.channels[i].temp_c = r.temp_c[i];
      summary_.channels[i].health = station::ChannelHealthName(r.health[i]);
      s.temp_c.push_back(r.temp_c[i]);
    }
    live_.Push(std::move(s));
  }
  alarms_.Update(options_.machine_id, alarms, t);
}

void RunBackend::OnModelPublished(station::PublishedModel model, const std::string& sha256, const std::string& label,
                                  double unix_s) {
  Loaded l;
  // A thermal model's "revision" is its kind ("ridge"): the file's hash tells two of them apart.
  const bool numbered = !model.revision.empty() && model.revision.find_first_not_of("0123456789") == std::string::npos;
  l.info = {numbered ? model.revision : model.revision + "-" + sha256.substr(0, 8), sha256, label, unix_s};
  if (!iso_figures_.empty())
    l.figures = iso_figures_;
  else if (model.composite)
    l.figures = FiguresFromFitSummary(*model.composite);  // a thermal model has no fit summary over travel
  l.model = std::move(model);
  std::lock_guard lock(mutex_);
  loaded_.push_back(std::move(l));
  in_use_.push_back(loaded_.size() - 1);
  summary_.model = {loaded_.back().info.revision, loaded_.back().info.sha256, ""};
}

std::string RunBackend::Describe() const { return "1 machine: " + summary_.name; }

void RunBackend::CheckId(const std::string& id) const {
  if (id != options_.machine_id) throw BackendError(404, "no machine '" + id + "' (this run is '" + options_.machine_id + "')");
}

MachineSummary RunBackend::Summary() const {
  MachineSummary s;
  {
    std::lock_guard lock(mutex_);
    s = summary_;
  }
  if (coolant_)
    if (const auto forced = coolant_->Override()) s.coolant_override = std::string(CoolantStateName(*forced));
  return s;
}

std::vector<MachineSummary> RunBackend::ListMachines() const { return {Summary()}; }

MachineDetail RunBackend::Machine(const std::string& id) const {
  CheckId(id);
  MachineDetail d{Summary(), {}};
  std::lock_guard lock(mutex_);
  if (!in_use_.empty()) {
    const Loaded& cur = loaded_[in_use_.back()];
    d.model.label = cur.info.label;
    d.model.figures = cur.figures;
  }
  for (const auto& l : loaded_) d.model.available.push_back(l.info);
  return d;
}

LiveSeries RunBackend::Live(const std::string& id, std::uint64_t after, std::size_t max_samples) const {
  CheckId(id);
  LiveSeries s{channels_, axes_, 0, {}};
  std::lock_guard lock(mutex_);
  s.last_sequence = live_.last_sequence();
  live_.CopyAfter(after, max_samples, s.samples);
  return s;
}

std::string RunBackend::HistoryDbOrThrow() const {
  if (options_.history_db.empty())
    throw BackendError(409, "this run keeps no history database ([history] db in the run config)");
  if (writer_) writer_->Flush();  // the newest rows too
  return options_.history_db;
}

HistorySeries RunBackend::History(const std::string& id, double from, double to, std::size_t max_points) const {
  CheckId(id);
  return ReadHistorySeries({HistoryDbOrThrow(), {}, {}, ""}, from, to, max_points);
}

std::vector<AlarmEntry> RunBackend::Alarms(std::size_t limit) const { return alarms_.Newest(limit); }

void RunBackend::SetAxisEnabled(const Actor&, const std::string& id, const std::string& axis, bool enabled) {
  CheckId(id);
  for (std::size_t i = 0; i < axes_.size(); ++i)
    if (axes_[i] == axis) return compensator_.SetAxisEnabled(i, enabled);
  throw BackendError(404, "machine '" + id + "' has no axis '" + axis + "'");
}

void RunBackend::AcknowledgeAlarm(const Actor& who, const std::string& alarm_id) {
  alarms_.Acknowledge(alarm_id, who.user, NowUnixS());
}

void RunBackend::SetCoolantOverride(const Actor&, const std::string& id, const std::string& state) {
  CheckId(id);
  if (!coolant_) throw BackendError(409, "this machine has no coolant override");
  if (state.empty()) return coolant_->SetOverride(std::nullopt);
  const auto parsed = ParseCoolantState(state);
  if (!parsed) throw BackendError(400, "coolant state '" + state + "' is not one of off, flood, mist, air (or \"\" to clear)");
  coolant_->SetOverride(parsed);
}

void RunBackend::Publish(const Loaded& l, const std::string& note) {
  try {
    station::PublishTo(compensator_, l.model, l.info.label);
  } catch (const std::exception& e) {
    throw BackendError(409, std::string("the model does not fit this machine: ") + e.what());
  }
  summary_.model = {l.info.revision, l.info.sha256, ""};
  if (writer_) writer_->PushModelChange(NowUnixS(), l.info.sha256, l.info.revision, note);
}

void RunBackend::LoadModelRevision(const Actor& who, const std::string& id, const std::string& revision) {
  CheckId(id);
  std::lock_guard lock(mutex_);
  for (std::size_t i = loaded_.size(); i-- > 0;)
    if (loaded_[i].info.revision == revision) {
      Publish(loaded_[i], "web: " + who.user + " from " + who.remote + " loaded revision " + revision);
      in_use_.push_back(i);
      return;
    }
  throw BackendError(404, "revision '" + revision + "' was not loaded by this run");
}

std::string RunBackend::RollbackModel(const Actor& who, const std::string& id) {
  CheckId(id);
  std::lock_guard lock(mutex_);
  if (in_use_.size() < 2) throw BackendError(409, "no earlier model revision to roll back to");
  const std::size_t previous = in_use_[in_use_.size() - 2];
  Publish(loaded_[previous],
          "web: " + who.user + " from " + who.remote + " rolled back to revision " + loaded_[previous].info.revision);
  in_use_.pop_back();
  return loaded_[previous].info.revision;
}

ExportFile RunBackend::Export(const std::string& id, double from, double to, ExportFormat format) const {
  CheckId(id);
  return ExportHistory({HistoryDbOrThrow(), {}, {}, ""}, from, to, format, options_.machine_id);
}

}  // namespace trueaxis::web
