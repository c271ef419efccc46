#include "trueaxis/runtime/compensator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace trueaxis::runtime {

Compensator::Compensator(CompensatorOptions options, std::vector<AxisInterface> axes, std::vector<std::string> channel_names,
                         ModelKinds kinds)
    : options_(std::move(options)),
      axes_(std::move(axes)),
      channel_names_(std::move(channel_names)),
      kinds_(kinds),
      out_(axes_.size(), channel_names_.size()),
      inline_temperatures_(channel_names_.size()),
      inline_cnc_(axes_.size()) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("compensator options: " + why);
  for (const auto& a : axes_)
    if (!a.IsValid(&why)) throw std::invalid_argument("axis interface: " + why);
  const std::size_t n = axes_.size();
  axis_enabled_ = std::make_unique<std::atomic<bool>[]>(n);
  for (std::size_t i = 0; i < n; ++i) axis_enabled_[i].store(axes_[i].enabled);
  axis_enabled_now_.assign(n, 1);
  extra_error_um_ = std::make_unique<std::atomic<double>[]>(n);
  extra_valid_until_s_ = std::make_unique<std::atomic<double>[]>(n);
  for (std::size_t i = 0; i < n; ++i) extra_error_um_[i].store(std::numeric_limits<double>::quiet_NaN());
  extra_error_now_um_.assign(n, std::numeric_limits<double>::quiet_NaN());
  state_ = StepState(n, channel_names_.size(), options_, kinds_ == ModelKinds::kCompositeAndGeneric);
  pickup_applied_um_.assign(n, std::numeric_limits<double>::quiet_NaN());
  shaping_ = ShaperLimitsFor(options_, axes_);
}

std::unique_ptr<Compensator> Compensator::ForHardware(const CompensatorOptions& options, const hw::CncLink& link,
                                                      const signal::JudgedTemperatureSource& source,
                                                      const std::vector<AxisInterface>& interfaces, ModelKinds kinds) {
  std::vector<AxisInterface> axes;
  for (std::size_t i = 0; i < link.AxisCount(); ++i) {
    AxisInterface a;
    a.axis = link.AxisName(i);
    for (const auto& given : interfaces)
      if (given.axis == a.axis) a = given;
    axes.push_back(a);
  }
  std::vector<std::string> channels;
  for (std::size_t i = 0; i < source.ChannelCount(); ++i) channels.push_back(source.ChannelName(i));
  return std::make_unique<Compensator>(options, std::move(axes), std::move(channels), kinds);
}

void Compensator::PublishModel(std::shared_ptr<const model::CompositeModel> model, const std::string& label) {
  auto bound = BindModel(std::move(model), label, axes_, channel_names_, options_.channel_map);
  bound->id = next_model_id_.fetch_add(1);
  exchange_.Publish(std::move(bound));
}

void Compensator::PublishAxisModels(std::vector<std::shared_ptr<const model::AxisErrorModel>> models,
                                    const std::string& label) {
  if (kinds_ == ModelKinds::kCompositeOnly)
    throw std::logic_error("compensator for composite models only: '" + label + "' is a model behind the generic interface");
  auto bound = BindAxisModels(std::move(models), label, axes_, channel_names_, options_.channel_map);
  bound->id = next_model_id_.fetch_add(1);
  exchange_.Publish(std::move(bound));
}

void Compensator::PickUp(const CncSnapshot& cnc) {
  if (!cnc.read_ok) {
    if (cnc.sequence != 0) {  // a lost link: pick the CNC up again once it answers
      pickup_pending_ = true;
      std::fill(pickup_applied_um_.begin(), pickup_applied_um_.end(), std::numeric_limits<double>::quiet_NaN());
    }
    return;
  }
  if (!pickup_pending_ || state_.outstanding != 0 || cnc.sequence == pickup_sequence_) return;
  pickup_sequence_ = cnc.sequence;
  bool reported = true, agreed = true;
  for (std::size_t a = 0; a < axes_.size(); ++a) {
    const double applied = cnc.axes[a].applied_um;
    reported = reported && std::isfinite(applied);
    agreed = agreed && applied == pickup_applied_um_[a];
    pickup_applied_um_[a] = applied;
  }
  if (!reported) {  // the CNC does not say: the shaper's own state
    pickup_pending_ = false;
    return;
  }
  if (!agreed) return;  // two reads must agree: a terminal may show an accepted write a scan late
  for (std::size_t a = 0; a < axes_.size(); ++a)
    state_.shaper[a] = PickUpAt(pickup_applied_um_[a] / axes_[a].CncScale(), axes_[a].PhysicalQuantumUm());
  pickup_pending_ = false;
}

const CycleStatus& Compensator::Cycle(const TemperatureSnapshot& temperatures, const CncSnapshot& cnc, double now_s) {
  current_ = exchange_.Acquire();
  PickUp(cnc);
  bool extra_expired = false;
  for (std::size_t i = 0; i < axes_.size(); ++i) {
    axis_enabled_now_[i] = axis_enabled_[i].load(std::memory_order_relaxed);
    const double e = extra_error_um_[i].load(std::memory_order_relaxed);
    const bool expired = !std::isnan(e) && now_s > extra_valid_until_s_[i].load(std::memory_order_relaxed);
    extra_expired = extra_expired || expired;
    extra_error_now_um_[i] = expired ? std::numeric_limits<double>::quiet_NaN() : e;
  }
  StepInputs in;
  in.now_s = now_s;
  in.temperatures = &temperatures;
  in.cnc = &cnc;
  in.enabled = enabled_.load(std::memory_order_relaxed);
  in.axis_enabled = axis_enabled_now_;
  in.extra_error_um = extra_error_now_um_;
  Step(Model(), state_, in, out_);
  if (extra_expired) out_.status.alarms |= kAlarmStaleInput;  // a term past its validity is dropped, not used
  if (vision_stop_.load(std::memory_order_relaxed)) out_.status.alarms |= kAlarmVisionStop;
  return out_.status;
}

const CycleStatus& Compensator::CommitWrite(bool write_ok) {
  runtime::CommitWrite(Model(), state_, write_ok, out_);
  return out_.status;
}

const CycleStatus& Compensator::AwaitWrite() {
  runtime::AwaitWrite(Model(), state_, out_);
  return out_.status;
}

const CycleStatus& Compensator::RunCycle(hw::CncLink& link, signal::JudgedTemperatureSource& source, double now_s) {
  ++inline_sequence_;
  ReadTemperatures(source, now_s, inline_sequence_, inline_temperatures_);
  ReadCnc(link, now_s, inline_sequence_, inline_cnc_);
  Cycle(inline_temperatures_, inline_cnc_, now_s);
  return CommitWrite(WriteCnc(link, out_.command));
}

}  // namespace trueaxis::runtime
