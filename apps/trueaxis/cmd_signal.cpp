// trueaxis signal: the temperature signal chain on the command line (docs/signal.md).
//   trueaxis signal filter  --in readings.csv [--channels a,b] [--calibration cal.json] [--groups "a,b,c;d,e"]
//                           [--hampel-window 9] [--median-window 5] [--tau-s 5] [--max-rate 0.5]
//                           [--stuck-window-s 300] [--min-c -10] [--max-c 80] [--out filtered.csv]
//                           [--db history.db [--start-time 2026-11-22T08:00:00Z]]
//   trueaxis signal convert --adc COUNT [--bits 12 --adc-min-v 0 --adc-max-v 5 --span-min-c 0 --span-max-c 50 ...]
//   trueaxis signal convert --ds18b20 0x0550 [--resolution-bits 12]
#include <algorithm>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/signal/conversions.hpp"
#include "trueaxis/signal/offline_filter.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/store/time_text.hpp"

namespace {

using namespace trueaxis::signal;
using trueaxis::InputError;

std::vector<std::string> SplitList(std::string_view text, char sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    auto pos = text.find(sep, start);
    auto item = trueaxis::Trim(text.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start));
    if (!item.empty()) out.emplace_back(item);
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

struct FilterCmd {
  std::string in, out, channels, calibration, groups, db, start_time;
  MonitorOptions options;
};

void RunFilter(FilterCmd& o) {
  for (const auto& g : SplitList(o.groups, ';')) o.options.neighbour_groups.push_back(SplitList(g, ','));
  std::string why;
  if (!o.options.IsValid(&why)) throw InputError("command line", 0, "options", why);
  trueaxis::RefuseOutputOverInput(o.out, {o.in, o.calibration, o.db}, "--out");
  trueaxis::RefuseOutputOverInput(o.db, {o.in, o.calibration}, "--db");
  const ReadingsTable table = ReadReadingsCsv(o.in, SplitList(o.channels, ','));
  for (const auto& g : o.options.neighbour_groups)
    for (const auto& name : g)
      if (std::find(table.channels.begin(), table.channels.end(), name) == table.channels.end())
        throw InputError("command line", 0, "--groups", fmt::format("'{}' is not a channel of {}", name, o.in));
  CalibrationSet cal;
  if (!o.calibration.empty()) cal = ReadCalibrationFile(o.calibration);
  // Parse --start-time before any work, so a bad one stores nothing.
  double offset_s = 0;
  if (!o.db.empty() && !o.start_time.empty()) {
    auto t = trueaxis::store::ParseTimeText(o.start_time);
    if (!t) throw InputError("command line", 0, "--start-time", fmt::format("'{}' is not a time", o.start_time));
    if (auto bad = trueaxis::ImplausibleTimeS(*t)) throw InputError("command line", 0, "--start-time", *bad);
    offset_s = *t - table.time_s.front();
  }
  const OfflineFilterResult result = RunMonitorOffline(table, o.options, o.calibration.empty() ? nullptr : &cal);
  for (const auto& name : result.calibration_without_channel)
    fmt::print(stderr, "warning: {}: sensor '{}' is no channel of {}: its calibration is not applied\n", o.calibration,
               name, o.in);
  fmt::print("{} rows, {} channels from {}\n{}", table.time_s.size(), table.channels.size(), o.in, result.FullReport());
  if (!o.out.empty()) {
    trueaxis::WriteTextFile(o.out, FormatOfflineFilterCsv(table, result));
    fmt::print("filtered values and statuses written to {}\n", o.out);
  }
  if (!o.db.empty()) {
    trueaxis::store::HistoryWriterOptions wo;
    wo.queue_capacity = 1 << 16;
    trueaxis::store::HistoryWriter writer(o.db, wo);
    for (std::size_t row = 0; row < table.time_s.size(); ++row) {
      for (std::size_t c = 0; c < table.channels.size(); ++c) {
        // Offline there is no deadline: wait for room instead of dropping.
        while (!writer.PushTemperature(table.time_s[row] + offset_s, table.channels[c], table.values_c[c][row],
                                       result.filtered_c[c][row], ChannelStatusName(result.status[c][row])))
          std::this_thread::yield();
      }
    }
    writer.Close();
    const auto stats = writer.Stats();
    if (stats.failed > 0) throw std::runtime_error(o.db + ": " + std::to_string(stats.failed) + " readings not stored: " + stats.last_error);
    fmt::print("{} readings stored in {}\n", stats.written, o.db);
  }
}

struct ConvertCmd {
  int adc = -1;
  std::string ds18b20;
  AnalogChannelOptions analog;
  Ds18b20Options digital;
};

void RunConvert(const ConvertCmd& o) {
  std::string why;
  if ((o.adc >= 0) == !o.ds18b20.empty())
    throw InputError("command line", 0, "--adc/--ds18b20", "give exactly one of --adc COUNT or --ds18b20 RAW");
  if (o.adc >= 0) {
    if (!o.analog.IsValid(&why)) throw InputError("command line", 0, "analog options", why);
    const auto r = ConvertAdcCount(o.adc, o.analog);
    fmt::print("count {} -> {:.4f} V -> {:.4f} °C ({}); resolution {:.4f} °C per count\n", o.adc,
               AdcCountToVolts(o.adc, o.analog), r.temp_c, ConversionConditionName(r.condition), AnalogResolutionC(o.analog));
    return;
  }
  if (!o.digital.IsValid(&why)) throw InputError("command line", 0, "--resolution-bits", why);
  unsigned long value = 0;
  try {
    std::size_t used = 0;
    value = std::stoul(o.ds18b20, &used, 0);  // accepts 0x0550, 1360
    if (used != o.ds18b20.size() || value > 0xFFFF) throw std::out_of_range("");
  } catch (const std::exception&) {
    throw InputError("command line", 0, "--ds18b20", fmt::format("'{}' is not a 16-bit word (e.g. 0x0191)", o.ds18b20));
  }
  const auto r = ConvertDs18b20(static_cast<std::uint16_t>(value), o.digital);
  fmt::print("0x{:04X} -> {:.4f} °C ({})\n", value, r.temp_c, ConversionConditionName(r.condition));
}

void Setup(CLI::App& app) {
  auto* signal = app.add_subcommand("signal", "Temperature signal chain: offline filtering/fault check, hardware conversions");
  signal->require_subcommand(1);

  auto f = std::make_shared<FilterCmd>();
  auto* filter = signal->add_subcommand("filter", "Run recorded raw readings through the temperature monitor");
  filter->add_option("--in", f->in, "CSV with time_s and one column per channel (°C)")->required();
  filter->add_option("--channels", f->channels, "comma-separated columns to process (default: all but time_s)");
  filter->add_option("--calibration", f->calibration, "cal.json from trueaxis calibrate");
  filter->add_option("--groups", f->groups, "neighbour groups: \"a,b,c;d,e\"");
  filter->add_option("--hampel-window", f->options.filter.hampel_window, "spike test window (odd samples)");
  filter->add_option("--median-window", f->options.filter.median_window, "median window (odd samples)");
  filter->add_option("--tau-s", f->options.filter.lowpass_time_constant_s, "low-pass time constant (s)");
  filter->add_option("--max-rate", f->options.faults.max_rate_c_per_s, "implausible rate of change (°C/s)");
  filter->add_option("--stuck-window-s", f->options.faults.stuck_window_s, "stuck detection window (s)");
  filter->add_option("--stuck-band-c", f->options.faults.stuck_band_c, "own span at or below this counts as no change (°C)");
  filter->add_option("--min-c", f->options.faults.min_plausible_c, "below: under_range");
  filter->add_option("--max-c", f->options.faults.max_plausible_c, "above: over_range");
  filter->add_option("--out", f->out, "write time_s,<ch>_c,<ch>_status,... here");
  filter->add_option("--db", f->db, "also store raw, filtered and status of every reading in this history database");
  filter->add_option("--start-time", f->start_time,
                     "with --db: the absolute time of the first row (ISO 8601 UTC or seconds); default: time_s as is");
  filter->callback([f] { RunFilter(*f); });

  auto c = std::make_shared<ConvertCmd>();
  auto* convert = signal->add_subcommand("convert", "Convert one ADC count or DS18B20 word to °C (commissioning aid)");
  convert->add_option("--adc", c->adc, "ADC count");
  convert->add_option("--bits", c->analog.adc_bits, "ADC resolution (bits)");
  convert->add_option("--adc-min-v", c->analog.adc_min_v, "voltage at count 0");
  convert->add_option("--adc-max-v", c->analog.adc_max_v, "voltage at full scale");
  convert->add_option("--span-min-c", c->analog.span_min_c, "transmitter: °C at span-min-v");
  convert->add_option("--span-max-c", c->analog.span_max_c, "transmitter: °C at span-max-v");
  convert->add_option("--span-min-v", c->analog.span_min_v, "transmitter output at span-min-c");
  convert->add_option("--span-max-v", c->analog.span_max_v, "transmitter output at span-max-c");
  convert->add_option("--ds18b20", c->ds18b20, "DS18B20 scratchpad word, e.g. 0x0191");
  convert->add_option("--resolution-bits", c->digital.resolution_bits, "DS18B20 resolution 9..12");
  convert->callback([c] { RunConvert(*c); });
}

trueaxis::cli::CommandRegistrar reg("signal", Setup);

}  // namespace
