#include "trueaxis/station/cycle_log.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "trueaxis/store/open_history_sink.hpp"

namespace trueaxis::station {

namespace fs = std::filesystem;

namespace {

std::uint64_t RecordEvery(const HistoryConfig& h, double period_s) {
  return static_cast<std::uint64_t>(std::max(1.0, std::round(h.record_interval_s / period_s)));
}

}  // namespace

CycleLog::CycleLog(const HistoryConfig& h, std::vector<std::string> axis_names, std::vector<std::string> channel_names,
                   double period_s, double unix0)
    : recorder_(8192, RecordEvery(h, period_s)), unix0_(unix0) {
  if (!h.db.empty()) {
    if (!store::IsPostgresUrl(h.db) && fs::path(h.db).has_parent_path()) fs::create_directories(fs::path(h.db).parent_path());
    writer_ = std::make_unique<store::HistoryWriter>(store::OpenHistorySink(h.db));
    history_ = std::make_unique<HistoryLogger>(*writer_, axis_names, channel_names, unix0);
  }
  if (!h.csv.empty()) {
    csv_ = std::make_unique<CsvCycleLog>(h.csv, std::move(axis_names), channel_names);
    if (csv_->repaired())
      notes_.push_back(h.csv + ": its last row was cut short (the previous run was killed); removed, appending");
  }
}

CycleLog::~CycleLog() {
  watchers_.clear();  // they may be gone already; what is left goes to the history and the CSV log
  Close();
}

void CycleLog::Watch(CycleLogWatcher w) {
  if (in_force_ && w.on_model) w.on_model(in_force_->model, in_force_->sha256, in_force_->label, in_force_->unix_s);
  watchers_.push_back(std::move(w));
}

void CycleLog::Log(const runtime::CycleRecord& r) {
  if (history_) history_->Log(r);
  if (csv_) csv_->Write(r);
  for (const auto& w : watchers_)
    if (w.on_record) w.on_record(r);
}

std::size_t CycleLog::Drain(const std::function<void(const runtime::CycleRecord&)>& each) {
  std::size_t n = 0;
  while (recorder_.Pop(record_)) {
    Log(record_);
    if (each) each(record_);
    ++n;
  }
  return n;
}

void CycleLog::ModelPublished(const PublishedModel& model, const std::string& sha256, const std::string& note,
                              const std::string& label, double unix_s) {
  in_force_ = InForce{model, sha256, label, unix_s};
  if (history_) history_->LogModelChange(unix_s - unix0_, sha256, model.revision, note);
  for (const auto& w : watchers_)
    if (w.on_model) w.on_model(model, sha256, label, unix_s);
}

void CycleLog::Flush() {
  if (csv_) csv_->Flush();
}

void CycleLog::Close() {
  Drain();
  Flush();
  if (writer_) writer_->Close();
}

}  // namespace trueaxis::station
