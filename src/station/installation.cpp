#include "trueaxis/station/installation.hpp"

#include <chrono>
#include <filesystem>

#include "trueaxis/model/sha256.hpp"
#include "trueaxis/station/machine_connection.hpp"

namespace trueaxis::station {

namespace fs = std::filesystem;

Installation::Installation(InstallationConfig config, hw::CncLink& link, hw::TemperatureSource& raw_temperatures,
                           std::function<double()> clock_s, std::string machine_name)
    : config_(std::move(config)), link_(link), raw_(raw_temperatures), machine_name_(std::move(machine_name)) {
  // Always judged; [signal] enabled = false only turns the filter off (MakeTemperaturePipeline).
  pipeline_ = MakeTemperaturePipeline(config_, raw_, std::move(clock_s), &warnings_);
  // A config without thermal_channels reads composite models only (ReadModelFor): its compensator
  // holds no generic models' state.
  compensator_ = runtime::Compensator::ForHardware(config_.compensator, link_, temperatures(), config_.axes,
                                                   config_.thermal_channels.empty() ? runtime::ModelKinds::kCompositeOnly
                                                                                    : runtime::ModelKinds::kCompositeAndGeneric);
  cnc_ = compensator_->MakeCncSnapshot();
  temperatures_ = compensator_->MakeTemperatureSnapshot();
  if (!config_.model_file.empty()) LoadModel(config_.model_file);
}

const runtime::CycleStatus& Installation::Cycle(double now_s, bool read_temperatures) {
  if (read_temperatures || temperature_reads_ == 0)
    runtime::ReadTemperatures(temperatures(), now_s, ++temperature_reads_, temperatures_);
  runtime::ReadCnc(link_, now_s, ++cnc_reads_, cnc_);
  return compensator_->Cycle(temperatures_, cnc_, now_s);
}

PublishedModel Installation::ReadModel(const std::string& model_file) const {
  return ReadModelFor(*compensator_, config_, machine_name_, model_file);
}

const PublishedModel& Installation::LoadModel(const std::string& model_file) {
  std::error_code ec;
  const auto mtime = fs::last_write_time(model_file, ec);
  Publish(ReadModel(model_file), model_file);  // InputError: the running model stays
  if (model_file == config_.model_file) model_mtime_ = ec ? std::nullopt : std::optional(mtime);
  return model_;
}

void Installation::Publish(const PublishedModel& model, const std::string& label) {
  PublishTo(*compensator_, model, label);
  model_ = model;
}

std::optional<PublishedModel> Installation::ReloadIfChanged() {
  std::error_code ec;
  const auto mtime = fs::last_write_time(config_.model_file, ec);
  if (ec || (model_mtime_ && mtime == *model_mtime_)) return std::nullopt;
  model_mtime_ = mtime;  // a refused file is not tried again until it changes again
  const PublishedModel& next = LoadModel(config_.model_file);
  if (log_) {
    const double unix_s = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    const std::string note = "reloaded " + config_.model_file;
    log_->ModelPublished(next, model::Sha256OfFile(config_.model_file), note, note, unix_s);
  }
  return next;
}

CycleLog& Installation::OpenLog(const HistoryConfig& history, double unix0) {
  std::vector<std::string> axis_names;
  for (const auto& a : compensator_->axes()) axis_names.push_back(a.axis);
  log_ = std::make_unique<CycleLog>(history, std::move(axis_names), compensator_->channel_names(), config_.period_s, unix0);
  if (!config_.model_file.empty())
    log_->ModelPublished(model_, model::Sha256OfFile(config_.model_file), "loaded " + config_.model_file,
                         config_.model_file, unix0);
  return *log_;
}

}  // namespace trueaxis::station
