// trueaxis thermal fit|predict|evaluate — data-driven thermal error models
// (docs/thermal-models.md, docs/thermal-series.md).
#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <optional>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/progress.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"
#include "trueaxis/thermal/model_fitting.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace trueaxis::cli {
namespace {
using namespace trueaxis::thermal;

// How the columns of a recording are read (ThermalReadOptions), for every subcommand.
struct ColumnOptions {
  std::string temperature_unit;  // C, F, K; empty: °C, checked for plausibility
  std::string error_unit;        // um, mm; empty: µm, checked
  std::vector<std::string> error_columns;
  std::string time_column;
  std::string time_unit;  // s, min, h; empty: from the column's name
  double sample_interval_s = 0;
  bool no_header = false;
};

void AddColumnOptions(CLI::App* cmd, ColumnOptions* o) {
  cmd->add_option("--temperature-unit", o->temperature_unit,
                  "unit of the temperature columns: C, F (converted) or K (converted); without it °C, and a recording "
                  "whose coolest sensor reads like °F or kelvin is refused");
  cmd->add_option("--error-unit", o->error_unit,
                  "unit of the error columns: um or mm (converted); without it µm, and a column that reads like mm "
                  "(all within ±0.2, RMS below 0.05) is refused");
  cmd->add_option("--error-column", o->error_columns,
                  "read this column as an error channel whatever its name (e.g. \"delta L\": channel delta_L); "
                  "repeat or separate by commas for several")
      ->delimiter(',');
  cmd->add_option("--time-column", o->time_column,
                  "read this column as the time (unit from --time-unit, or its name's _s/_min/_h; else s)");
  cmd->add_option("--time-unit", o->time_unit, "unit of the time column: s, min or h (time_min and time_h are known)");
  cmd->add_option("--sample-interval-s", o->sample_interval_s,
                  "a file without a time column was sampled every S seconds (rows are then this far apart)");
  cmd->add_flag("--no-header", o->no_header,
                "the first row is data: columns are named col1..colN, and those not named by --time-column or "
                "--error-column are temperatures");
}

ThermalReadOptions MakeReadOptions(const ColumnOptions& o) {
  ThermalReadOptions r;
  if (!o.temperature_unit.empty() && !ParseTemperatureUnit(o.temperature_unit, &r.temperature_unit))
    throw InputError("command line", 0, "--temperature-unit", fmt::format("'{}' is not C, F or K", o.temperature_unit));
  if (!o.error_unit.empty() && !ParseErrorUnit(o.error_unit, &r.error_unit))
    throw InputError("command line", 0, "--error-unit", fmt::format("'{}' is not um or mm", o.error_unit));
  for (const auto& c : o.error_columns)
    if (!Trim(c).empty()) r.error_columns.emplace_back(Trim(c));
  r.time_column = o.time_column;
  if (!o.time_unit.empty()) {
    const auto unit = ParseTimeUnitS(o.time_unit);
    if (!unit) throw InputError("command line", 0, "--time-unit", fmt::format("'{}' is not s, min or h", o.time_unit));
    r.time_unit_s = *unit;
  }
  if (o.sample_interval_s != 0 && !(o.sample_interval_s > 0))
    throw InputError("command line", 0, "--sample-interval-s", "must be > 0 s");
  r.sample_interval_s = o.sample_interval_s;
  r.no_header = o.no_header;
  return r;
}

// Each file read and cleaned on its own (its own clock and gaps), then joined as experiments;
// `select` (optional) narrows a file's channels and sensors before it is cleaned.
ThermalSeries ReadCleanAndJoin(const std::vector<std::string>& paths, const ColumnOptions& columns,
                               const SeriesCleaningOptions& co, SeriesCleaningReport* report,
                               const std::function<ThermalSeries(ThermalSeries)>& select = {}) {
  const ThermalReadOptions ro = MakeReadOptions(columns);
  std::vector<ThermalSeries> parts;
  for (const auto& path : paths)
    for (ThermalSeries s : ReadThermalSeriesFile(path, &report->warnings, ro)) {
      if (select) s = select(std::move(s));
      SeriesCleaningReport part_report;
      parts.push_back(CleanSeries(s, co, &part_report));
      for (const auto& w : part_report.warnings) report->warnings.push_back(w);
      report->interpolated_values += part_report.interpolated_values;
      for (const auto& d : part_report.dropped_temperatures) report->dropped_temperatures.push_back(d);
    }
  return ConcatenateExperiments(parts, &report->warnings);
}

struct CommonOptions {
  ColumnOptions columns;
  std::vector<std::string> series;  // several: one experiment each
  std::string channels;  // comma list; empty = all
  std::string sensors_list;  // comma list; empty = every sensor of the series
  std::string lags_s = "auto";  // lagged inputs: auto (DefaultLagGridS), none, or a list of τ in s
  // cleaning
  int max_gap_samples = 4;
  bool strict = false;
  bool allow_time_gaps = false;
  // models
  std::string select = "lasso";
  std::string sensors = "auto";  // a count, or "auto": chosen per channel by blocked CV (up to 32)
  double lambda = 1e-3;
  int temperature_inputs = 1;
  int hidden = 7;
  int epochs = 500;
  int particles = 200;
  int pso_iterations = 100;
  int pso_max_samples = 400;
  std::uint64_t seed = 1;
  double window_s = 900;
  double threshold_c_per_h = 0.3;
};

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!Trim(item).empty()) out.emplace_back(Trim(item));
  return out;
}

void AddCommon(CLI::App* cmd, CommonOptions* o) {
  cmd->add_option("--series", o->series,
                  "thermal series CSV (docs/thermal-series.md; fl_thermal.csv reads as is); several files (or "
                  "--series given again) are separate experiments of the same machine")
      ->required()
      ->expected(1, -1);
  AddColumnOptions(cmd, &o->columns);
  cmd->add_option("--channels", o->channels, "error channels to model, comma separated (default: all)");
  cmd->add_option("--sensors-list", o->sensors_list,
                  "use exactly these inputs, comma separated (no selection; e.g. t1,t4,t9 or t4@lag1800s)");
  cmd->add_option("--lags-s", o->lags_s,
                  "offer each sensor also lagged by these time constants (first-order lag, s): auto "
                  "(600,1800,5400,16200 up to a third of the longest experiment), none, or a list such as 900,2700; "
                  "with --sensors auto the lags are kept only where the cross-validation finds they help")
      ->capture_default_str();
  cmd->add_option("--max-gap-samples", o->max_gap_samples, "interior gaps up to this many rows are interpolated")
      ->capture_default_str();
  cmd->add_flag("--strict", o->strict, "refuse a series with a dead/gappy temperature channel instead of dropping it");
  cmd->add_flag("--allow-time-gaps", o->allow_time_gaps, "warn instead of refusing jumps in time_s");
  cmd->add_option("--select", o->select, "sensor selection: lasso, correlation-clusters or all")->capture_default_str();
  cmd->add_option("--sensors", o->sensors,
                  "sensors per channel for mlr/ridge/hysteresis: a count, or auto (chosen per channel by time-ordered "
                  "cross-validation on the training rows among the constant, 1, 2, 3, 4, 6, … and all sensors, "
                  "without and with lags, all also with ridge λ 0.01 and 0.1; input sets as good within the noise "
                  "averaged; the constant where no input beats it)")
      ->capture_default_str();
  cmd->add_option("--lambda", o->lambda, "ridge penalty on standardised temperatures")->capture_default_str();
  cmd->add_option("--temperature-inputs", o->temperature_inputs,
                  "pso-bp: selected temperatures fed to the network (1 in the workshop paper, plus the position)")
      ->capture_default_str();
  cmd->add_option("--hidden", o->hidden, "pso-bp: hidden units")->capture_default_str();
  cmd->add_option("--epochs", o->epochs, "pso-bp: back-propagation epochs")->capture_default_str();
  cmd->add_option("--particles", o->particles, "pso-bp: swarm size")->capture_default_str();
  cmd->add_option("--pso-iterations", o->pso_iterations, "pso-bp: swarm iterations (not given by the workshop paper)")
      ->capture_default_str();
  cmd->add_option("--pso-max-samples", o->pso_max_samples, "pso-bp: rows used for the swarm's fitness")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "pso-bp: random seed (same seed, same network)")->capture_default_str();
  cmd->add_option("--window-s", o->window_s, "hysteresis: trailing window of the temperature trend")->capture_default_str();
  cmd->add_option("--threshold-c-per-h", o->threshold_c_per_h, "hysteresis: |trend| above this is heating/cooling")
      ->capture_default_str();
}

// The raw sensors behind a list of inputs (a lagged input "t4@lag1800s" needs t4).
std::vector<std::string> BaseSensors(const std::vector<std::string>& inputs) {
  std::vector<std::string> out;
  for (const auto& name : inputs) {
    std::string base = name;
    ParseLaggedName(name, &base, nullptr);
    if (std::find(out.begin(), out.end(), base) == out.end()) out.push_back(base);
  }
  return out;
}

// --sensors as a count: the number given, or for "auto" the upper bound of the CV's search.
int SensorCount(const CommonOptions& o) {
  if (o.sensors == "auto") return 32;
  const auto v = ParseInt(o.sensors);
  if (!v || *v < 1 || *v > 1000)
    throw InputError("command line", 0, "--sensors", fmt::format("'{}' is not a count >= 1 or 'auto'", o.sensors));
  return static_cast<int>(*v);
}

ThermalFitOptions MakeFitOptions(const CommonOptions& o, ModelKind kind) {
  ThermalFitOptions f;
  f.kind = kind;
  if (!ParseSelectionMethod(o.select, &f.linear.selection.method))
    throw InputError("command line", 0, "--select", "'" + o.select + "' is not correlation-clusters, lasso or all");
  if (!o.sensors_list.empty()) {  // the user chose the sensors: no selection among them
    if (o.sensors != "auto")
      throw InputError("command line", 0, "--sensors-list", "names the sensors itself: leave out --sensors");
    f.linear.selection.method = SelectionMethod::kAll;
  }
  f.sensors_listed = !o.sensors_list.empty();
  f.linear.choose_count_by_cv = o.sensors == "auto" && f.linear.selection.method != SelectionMethod::kAll;
  f.linear.selection.max_sensors = SensorCount(o);

  f.ridge_lambda = o.lambda;
  f.network.selection = f.linear.selection;
  f.network.temperature_inputs = o.temperature_inputs;
  f.network.hidden_units = o.hidden;
  f.network.epochs = o.epochs;
  f.network.particles = o.particles;
  f.network.pso_iterations = o.pso_iterations;
  f.network.pso_max_samples = o.pso_max_samples;
  f.network.seed = o.seed;
  f.hysteresis.classifier.window_s = o.window_s;
  f.hysteresis.classifier.threshold_c_per_h = o.threshold_c_per_h;
  std::string why;
  if (!f.IsValid(&why)) throw InputError("command line", 0, "", why);
  return f;
}

ThermalSeries LoadSeries(const CommonOptions& o, SeriesCleaningReport* report) {
  SeriesCleaningOptions co;
  co.max_interpolated_gap_samples = o.max_gap_samples;
  co.drop_bad_temperature_channels = !o.strict;
  co.allow_time_gaps = o.allow_time_gaps;
  std::string why;
  if (!co.IsValid(&why)) throw InputError("command line", 0, "--max-gap-samples", why);
  ThermalSeries cleaned = ReadCleanAndJoin(o.series, o.columns, co, report, [&](ThermalSeries s) {
    if (!o.channels.empty()) s = SelectErrorChannels(s, SplitList(o.channels));
    if (!o.sensors_list.empty()) s = SelectTemperatureSensors(s, BaseSensors(SplitList(o.sensors_list)));
    return s;
  });
  if (o.lags_s != "none") {
    std::vector<double> grid = DefaultLagGridS();
    if (o.lags_s != "auto") {
      grid.clear();
      for (const auto& t : SplitList(o.lags_s)) {
        const auto v = ParseDouble(t);
        if (!v || !(*v > 0)) throw InputError("command line", 0, "--lags-s", fmt::format("'{}' is not a time constant in s", t));
        grid.push_back(*v);
      }
    }
    std::vector<double> skipped;
    if (cleaned.has_time) cleaned = AddLaggedTemperatures(cleaned, grid, &skipped);
    else if (o.lags_s != "auto") throw InputError(cleaned.source, 0, "--lags-s", "lagged inputs need time_s");
    // Said either way: with auto the short recording decides which lags are offered.
    if (!skipped.empty())
      report->warnings.push_back(fmt::format("--lags-s {}: {} s not offered: longer than a third of the longest "
                                             "experiment ({:.2f} h)", o.lags_s, fmt::join(skipped, ", "),
                                             LongestExperimentS(cleaned) / 3600));
  }
  if (!o.sensors_list.empty()) cleaned = SelectTemperatureSensors(cleaned, SplitList(o.sensors_list));
  for (const auto& w : report->warnings) fmt::print(stderr, "warning: {}\n", w);
  // More sensors asked for than the recording has: say so rather than silently use them all.
  const int available = static_cast<int>(cleaned.temperature_names.size());
  const int asked = SensorCount(o);
  if (o.sensors != "auto" && asked > available)
    fmt::print(stderr, "warning: --sensors {}: {} has only {} usable temperature channel(s); at most those are used\n",
               asked, cleaned.source, available);
  // A fit needs more rows than coefficients to mean anything.
  if (cleaned.Rows() < 10 + 2 * std::min(asked, available))
    fmt::print(stderr, "warning: {} has only {} rows for up to {} sensors: the fit is barely determined\n", cleaned.source,
               cleaned.Rows(), std::min(asked, available));
  return cleaned;
}

// One line per channel of a linear model that is its training mean because no input beat the
// mean on the time-ordered cross-validation: said, never shipped silently. A constant is the error
// of the state the training rows were in and is applied in every state: where a recording (or an
// experiment) starts far from it — a start from cold before a warm-up — that start is named, with
// what the constant would add on a machine in that state.
constexpr double kColdStartRmsFactor = 3;  // a start this many RMS off the constant is named

std::string ConstantFallbackNotes(const ThermalErrorModel& model, const ThermalSeries& train) {
  std::string out;
  const auto* linear = dynamic_cast<const LinearThermalModel*>(&model);
  if (!linear) return out;
  for (std::size_t k = 0; k < linear->channel_models().size(); ++k) {
    const LinearChannel& c = linear->channel_models()[k];
    if (!c.IsConstant()) continue;
    out += fmt::format("note: {}: no input beat the training mean on time-ordered cross-validation (held-out "
                       "RMS per candidate: sensor_count_cv_rms_um): the model is the constant {:.3f} µm\n",
                       c.name, c.intercept_um);
    const auto col = static_cast<Eigen::Index>(std::find(train.error_names.begin(), train.error_names.end(), c.name) -
                                               train.error_names.begin());
    if (col >= train.errors_um.cols() || train.Rows() == 0) continue;
    const Eigen::VectorXd e = train.errors_um.col(col).array() - c.intercept_um;
    const double rms = std::sqrt(e.squaredNorm() / static_cast<double>(e.size()));
    Eigen::Index start = 0;  // the first row of the experiment whose start lies farthest from the constant
    for (Eigen::Index r = 1; r < train.Rows(); ++r)
      if (train.ExperimentOf(r) != train.ExperimentOf(r - 1) && std::abs(e(r)) > std::abs(e(start))) start = r;
    const auto id = static_cast<std::size_t>(train.ExperimentOf(start));
    const std::string where = train.ExperimentCount() > 1 && id < train.experiment_names.size()
                                  ? "experiment " + train.experiment_names[id]
                                  : std::string("recording");
    if (std::abs(e(start)) > kColdStartRmsFactor * rms)
      out += fmt::format("warning: {}: the constant is the mean error of the state the training rows were in and is "
                         "compensated in every state: the {} started at {:.3f} µm, {:.3f} µm from it ({:.0f} × its RMS "
                         "about the mean) — on a machine in that starting state (a start from cold before a warm-up) "
                         "the compensation adds about that much error. Compensate with it once the machine is in its "
                         "working state, or record a sensor that follows the warm-up so that an input can be chosen "
                         "(docs/thermal-models.md)\n",
                         c.name, where,
                         train.errors_um(start, col), std::abs(e(start)), std::abs(e(start)) / std::max(rms, 1e-12));
  }
  return out;
}

ModelKind ParseKind(const std::string& text, const std::string& field) {
  ModelKind k;
  if (!ParseModelKind(text, &k))
    throw InputError("command line", 0, field, "'" + text + "' is not a model: mlr, ridge, pso-bp, hysteresis or auto");
  return k;
}

void Setup(CLI::App& app) {
  auto* thermal = app.add_subcommand("thermal", "Data-driven thermal error models: fit, predict, evaluate");
  thermal->require_subcommand(1);

  // fit
  {
    auto* cmd = thermal->add_subcommand("fit", "Fit a thermal error model to a series and write it as JSON");
    auto o = std::make_shared<CommonOptions>();
    auto kind = std::make_shared<std::string>("ridge");
    auto out = std::make_shared<std::string>();
    auto blocks = std::make_shared<std::string>("all");
    AddCommon(cmd, o.get());
    cmd->add_option("--model", *kind, "mlr, ridge, pso-bp, hysteresis, or auto (the best of mlr/ridge/hysteresis by time-ordered CV)")->capture_default_str();
    cmd->add_option("--train-blocks", *blocks, "speed blocks to fit on (e.g. 0-8); default all rows")
        ->capture_default_str();
    cmd->add_option("-o,--out", *out, "model JSON to write")->required();
    cmd->callback([o, kind, out, blocks] {
      RefuseOutputOverInput(*out, o->series, "--out");
      SeriesCleaningReport rep;
      ThermalSeries s = LoadSeries(*o, &rep);
      ThermalFitOptions fo = MakeFitOptions(*o, ParseKind(*kind, "--model"));
      auto sb = SpeedBlocks(s);
      ThermalSeries train = SelectRows(s, RowsOfBlocks(sb, ParseBlockList(*blocks, static_cast<int>(sb.size()), "--train-blocks")));
      std::string report;
      auto model = FitThermalModel(train, fo, &report);
      WriteThermalModelFile(*model, *out);
      Eigen::MatrixXd pred = PredictSeries(*model, train);
      std::vector<Eigen::Index> all(static_cast<std::size_t>(train.Rows()));
      for (Eigen::Index r = 0; r < train.Rows(); ++r) all[static_cast<std::size_t>(r)] = r;
      auto metrics = ResidualMetrics(train, pred, all);
      fmt::print("{} model on {} rows, written to {}\n{}{}{}", *kind, train.Rows(), *out, model->Describe(), report,
                 ConstantFallbackNotes(*model, train));
      for (const auto& m : metrics)
        fmt::print("{}: fit RMSE {:.3f} um, max |residual| {:.3f} um\n", m.channel, m.rmse_um, m.max_abs_um);
    });
  }

  // predict
  {
    auto* cmd = thermal->add_subcommand("predict", "Predict the thermal error of every row of a series");
    auto model_path = std::make_shared<std::string>();
    auto series = std::make_shared<std::string>();
    auto out = std::make_shared<std::string>();
    auto gap = std::make_shared<int>(4);
    auto columns = std::make_shared<ColumnOptions>();
    cmd->add_option("--model", *model_path, "model JSON from 'thermal fit'")->required();
    cmd->add_option("--series", *series, "thermal series CSV or .xlsx workbook (one experiment per sheet)")->required();
    AddColumnOptions(cmd, columns.get());
    cmd->add_option("-o,--out", *out, "CSV to write (default: stdout)");
    cmd->add_option("--max-gap-samples", *gap, "interior gaps up to this many rows are interpolated")->capture_default_str();
    cmd->callback([model_path, series, out, gap, columns] {
      RefuseOutputOverInput(*out, {*model_path, *series}, "--out");
      auto model = ReadThermalModelFile(*model_path);
      SeriesCleaningOptions co;
      co.max_interpolated_gap_samples = *gap;
      co.min_temperature_std_c = 0;       // prediction does not standardise
      co.check_error_channels = false;    // and needs no measured error
      SeriesCleaningReport rep;
      ThermalSeries cleaned = ReadCleanAndJoin({*series}, *columns, co, &rep);
      // A lagged input starts at the file's first reading as if the machine had been at rest: on a
      // file cut out of a longer recording its first rows lack the history the model was fitted with.
      if (const LagStartUp lag = LagStartUpRows(cleaned, model->InputSensors()); lag.rows > 0)
        rep.warnings.push_back(fmt::format(
            "the model's lagged inputs (τ up to {:g} s) start at the first reading{}: the first {} row(s) ({:g} s = "
            "{:g} × τ{}) lack the lag history and are predicted as if the machine had been at rest before; if it was "
            "not, include the hours before in the file",
            lag.longest_tau_s, lag.starts > 1 ? fmt::format(" of each of {} runs", lag.starts) : std::string(),
            lag.rows, lag.settle_s, kLagSettleTaus, lag.starts > 1 ? " after each start" : ""));
      for (const auto& w : rep.warnings) fmt::print(stderr, "warning: {}\n", w);
      Eigen::MatrixXd pred = PredictSeries(*model, cleaned);
      // A prediction no machine's thermal error reaches (a damaged coefficient, a model of other
      // units) is refused, not written as a compensation value.
      for (Eigen::Index r = 0; r < pred.rows(); ++r)
        for (Eigen::Index c = 0; c < pred.cols(); ++c)
          if (auto why = ImplausibleDeviationUm(pred(r, c)))
            throw InputError(*model_path, 0, "channels",
                             fmt::format("the model predicts {:g} µm for channel {} at line {} of {}: {}; the model file "
                                         "is damaged or of other units",
                                         pred(r, c), model->Channels()[static_cast<std::size_t>(c)],
                                         cleaned.LineOf(r), *series, *why));
      std::vector<ThermalInterval> iv = model->ClassifyRows(WithLaggedInputs(cleaned, model->InputSensors()));
      std::string text = cleaned.has_time ? "time_s" : "row";
      if (cleaned.has_position) text += ",position_mm";
      if (model->UsesInterval()) text += ",interval";
      // Where the series also holds the measured error of a channel, it is written beside the
      // prediction with the residual (measured − predicted: what compensation would leave).
      std::vector<std::optional<std::size_t>> measured;
      for (const auto& c : model->Channels()) {
        measured.push_back(cleaned.ErrorIndex(c));
        text += ",e_" + c + "_predicted_um";
        if (measured.back()) text += ",e_" + c + "_measured_um,e_" + c + "_residual_um";
      }
      text += '\n';
      std::vector<double> sum_sq(measured.size(), 0.0);
      std::vector<int> count(measured.size(), 0);
      for (Eigen::Index r = 0; r < cleaned.Rows(); ++r) {
        text += FormatShortest(cleaned.time_s[static_cast<std::size_t>(r)]);
        if (cleaned.has_position) text += "," + FormatShortest(cleaned.position_mm[static_cast<std::size_t>(r)]);
        if (model->UsesInterval()) text += std::string(",") + ThermalIntervalName(iv[static_cast<std::size_t>(r)]);
        for (Eigen::Index c = 0; c < pred.cols(); ++c) {
          text += "," + FormatShortest(pred(r, c));
          if (const auto m = measured[static_cast<std::size_t>(c)]) {
            const double v = cleaned.errors_um(r, static_cast<Eigen::Index>(*m));
            if (std::isfinite(v)) {
              text += "," + FormatShortest(v) + "," + FormatShortest(v - pred(r, c));
              sum_sq[static_cast<std::size_t>(c)] += (v - pred(r, c)) * (v - pred(r, c));
              ++count[static_cast<std::size_t>(c)];
            } else {
              text += ",,";  // not measured in this row
            }
          }
        }
        text += '\n';
      }
      for (std::size_t c = 0; c < measured.size(); ++c)
        if (count[c] > 0)
          fmt::print(stderr, "{}: residual RMSE {:.3f} um over {} measured rows\n", model->Channels()[c],
                     std::sqrt(sum_sq[c] / count[c]), count[c]);
      if (out->empty()) std::cout << text;
      else WriteTextFile(*out, text);
    });
  }

  // evaluate
  {
    auto* cmd = thermal->add_subcommand(
        "evaluate", "Train on part of a recording, validate on the rest (speed blocks, rows, hours, experiments); RMSE and max "
        "|error| per channel and model next to no compensation, a constant and all sensors");
    auto o = std::make_shared<CommonOptions>();
    auto models = std::make_shared<std::string>("mlr,ridge,pso-bp,hysteresis");
    auto train = std::make_shared<std::string>("auto");
    auto validate = std::make_shared<std::string>("auto");
    auto report = std::make_shared<std::string>();
    auto markdown = std::make_shared<std::string>();
    AddCommon(cmd, o.get());
    cmd->add_option("--models", *models, "comma list of mlr, ridge, pso-bp, hysteresis, auto")->capture_default_str();
    cmd->add_option("--train-blocks", *train,
                    "speed blocks to train on, e.g. 0-8 (auto: first 60 % of blocks; all)")
        ->capture_default_str();
    cmd->add_option("--validate-blocks", *validate, "speed blocks to validate on (auto: the others)")
        ->capture_default_str();
    auto last = std::make_shared<double>(0);
    cmd->add_option("--validate-last", *last,
                    "split in time instead: validate on this last fraction of the rows, e.g. 0.1 (default with "
                    "a single speed block: 0.3)");
    auto rows = std::make_shared<std::string>(), hours = std::make_shared<std::string>(),
         experiments = std::make_shared<std::string>();
    auto after = std::make_shared<bool>(false);
    cmd->add_option("--validate-rows", *rows,
                    "validate on these data rows (0-based ranges, e.g. 9000-11114), train on the rows before them");
    cmd->add_option("--validate-hours", *hours,
                    "validate on the rows whose time lies in these hours (e.g. 30-46), train on the rows before them");
    cmd->add_flag("--train-after-validation", *after,
                  "with --validate-rows/--validate-hours: also train on the rows after the validated ones (in a time "
                  "series that lets the model see the future it is judged on)");
    cmd->add_option("--validate-experiments", *experiments,
                    "with several --series files: validate on these experiments (0-based, e.g. 2 or 1,3), or 'each' "
                    "for leave-one-experiment-out (the default with several files)");
    cmd->add_option("--report", *report, "write an HTML report (plots of measured vs predicted, residuals, sensors)");
    cmd->add_option("--markdown", *markdown, "write the metrics table as Markdown");
    auto verbose = std::make_shared<bool>(false);
    cmd->add_flag("--verbose", *verbose, "also print each model's coefficients and fit notes");
    cmd->callback([o, models, train, validate, last, rows, hours, experiments, report, markdown, after, verbose] {
      RefuseOutputOverInput(*report, o->series, "--report");
      std::vector<std::string> read_or_written = o->series;
      read_or_written.push_back(*report);
      RefuseOutputOverInput(*markdown, read_or_written, "--markdown");
      SeriesCleaningReport rep;
      ThermalSeries s = LoadSeries(*o, &rep);
      EvaluationOptions eo;
      eo.train_blocks = *train;
      eo.validate_blocks = *validate;
      eo.validate_last_fraction = *last;
      eo.validate_rows = *rows;
      eo.validate_hours = *hours;
      eo.validate_experiments = *experiments;
      eo.train_after_validation = *after;
      if (*after && rows->empty() && hours->empty())
        throw InputError("command line", 0, "--train-after-validation", "applies to --validate-rows or --validate-hours");
      for (const auto& m : SplitList(*models)) eo.models.push_back(MakeFitOptions(*o, ParseKind(m, "--models")));
      if (eo.models.empty()) throw InputError("command line", 0, "--models", "no model given");
      auto progress = ProgressLine::OnStderr("thermal evaluate");
      eo.progress = [&](std::size_t done, std::size_t total, const std::string& what) { progress.Step(done, total, what); };
      ThermalEvaluation ev = EvaluateThermalModels(s, rep, eo);
      progress.Finish();
      // Every line wrapped under 120 characters (a model may read hundreds of lagged inputs).
      const auto inputs = s.temperature_names.size();
      const auto sensors = BaseSensors(s.temperature_names).size();
      fmt::print("{}", WrapLines(fmt::format("series: {} ({} rows, {} sensors{}, {} channels)", s.source, s.Rows(), sensors,
                                             inputs > sensors ? fmt::format(" ({} inputs with lags)", inputs) : std::string(),
                                             s.error_names.size())));
      fmt::print("{}", WrapLines(ev.SplitDescription()));
      for (const auto& m : ev.models) {
        const auto used = m.model->InputSensors();
        fmt::print("\n{}", WrapLines(fmt::format("[{}] fitted in {:.2f} s; {} input{}: {}", m.name, m.fit_seconds,
                                                 used.size(), used.size() == 1 ? "" : "s", fmt::join(used, ", "))));
        if (*verbose) fmt::print("{}", WrapLines(m.model->Describe() + m.fit_report));
        if (const auto notes = ConstantFallbackNotes(*m.model, SelectRows(ev.series, ev.train_rows)); !notes.empty()) fmt::print("{}", WrapLines(notes));
      }
      if (!*verbose) fmt::print("\n(--verbose: each model's coefficients and fit notes)\n");
      fmt::print("\n{}", WrapLines(ev.BriefReport()));
      if (!markdown->empty()) WriteTextFile(*markdown, ev.SplitDescription() + "\n" + ev.MarkdownTable());
      if (!report->empty()) {
        WriteThermalReport(ev, *report);
        fmt::print("report: {}\n", *report);
      }
    });
  }
}

CommandRegistrar reg("thermal", Setup);

}  // namespace
}  // namespace trueaxis::cli
