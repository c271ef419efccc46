#include "trueaxis/thermal/model_fitting.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/thermal/time_folds.hpp"

namespace trueaxis::thermal {

const char* ModelKindName(ModelKind k) {
  switch (k) {
    case ModelKind::kMlr: return "mlr";
    case ModelKind::kRidge: return "ridge";
    case ModelKind::kPsoBp: return "pso-bp";
    case ModelKind::kHysteresis: return "hysteresis";
    case ModelKind::kAuto: return "auto";
  }
  return "?";
}

bool ParseModelKind(const std::string& text, ModelKind* out) {
  for (auto k : {ModelKind::kMlr, ModelKind::kRidge, ModelKind::kPsoBp, ModelKind::kHysteresis, ModelKind::kAuto})
    if (text == ModelKindName(k)) {
      *out = k;
      return true;
    }
  return false;
}

bool ThermalFitOptions::IsValid(std::string* why) const {
  if (!(ridge_lambda >= 0) || !std::isfinite(ridge_lambda)) {
    if (why) *why = "ridge_lambda must be a finite number >= 0";
    return false;
  }
  switch (kind) {
    case ModelKind::kMlr:
    case ModelKind::kRidge: return linear.IsValid(why);
    case ModelKind::kPsoBp: return network.IsValid(why);
    case ModelKind::kHysteresis:
    case ModelKind::kAuto: return linear.IsValid(why) && hysteresis.classifier.IsValid(why);
  }
  return true;
}

namespace {

// Time-ordered CV RMSE (all channels pooled) of one model kind on `s` (time_folds.hpp).
double TimeOrderedCvRmse(const ThermalSeries& s, const TimeFolds& folds, const ThermalFitOptions& o) {
  double ss = 0;
  long count = 0;
  for (const TimeFold& f : folds.folds) {
    const auto model = FitThermalModel(SelectRows(s, f.train_rows), o, nullptr);
    const Eigen::MatrixXd p = PredictSeries(*model, s);
    for (Eigen::Index r : f.validate_rows)
      for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
        const double e = s.errors_um(r, c) - p(r, c);
        ss += e * e;
        ++count;
      }
  }
  return count ? std::sqrt(ss / static_cast<double>(count)) : std::numeric_limits<double>::infinity();
}

}  // namespace

std::unique_ptr<ThermalErrorModel> FitThermalModel(const ThermalSeries& s, const ThermalFitOptions& o,
                                                   std::string* fit_report) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("fit options", why);
  if (s.error_names.empty()) throw InputError(s.source, 0, "", "no error channel to fit");
  switch (o.kind) {
    case ModelKind::kAuto: {
      if (s.Rows() < 50) throw InputError(s.source, 0, "--model", "auto needs at least 50 rows to cross-validate");
      std::string cv;
      const TimeFolds folds = MakeTimeFolds(s);
      ThermalFitOptions best = o;
      double best_rmse = std::numeric_limits<double>::infinity();
      for (ModelKind k : {ModelKind::kMlr, ModelKind::kRidge, ModelKind::kHysteresis}) {
        ThermalFitOptions c = o;
        c.kind = k;
        if (k == ModelKind::kHysteresis && !s.has_time) continue;
        const double rmse = TimeOrderedCvRmse(s, folds, c);
        cv += fmt::format("{}{} {:.3f} µm", cv.empty() ? "" : ", ", ModelKindName(k), rmse);
        if (rmse < best_rmse) best_rmse = rmse, best = c;
      }
      std::string report;
      auto m = FitThermalModel(s, best, &report);
      if (fit_report)
        *fit_report = fmt::format("auto: {} chosen by {} CV RMSE ({})\n{}", ModelKindName(best.kind), folds.Name(), cv,
                                  report);
      return m;
    }
    case ModelKind::kMlr: {
      LinearFitOptions lo = o.linear;
      lo.ridge_lambda = 0;
      return std::make_unique<LinearThermalModel>(FitLinearModel(s, lo));
    }
    case ModelKind::kRidge: {
      LinearFitOptions lo = o.linear;
      lo.ridge_lambda = o.ridge_lambda;
      return std::make_unique<LinearThermalModel>(FitLinearModel(s, lo));
    }
    case ModelKind::kPsoBp: {
      PsoBpFitSummary summary;
      auto m = std::make_unique<PsoBpNetworkModel>(FitPsoBpNetwork(s, o.network, &summary));
      if (fit_report) *fit_report = summary.BriefReport();
      return m;
    }
    case ModelKind::kHysteresis: {
      HysteresisFitOptions ho = o.hysteresis;
      ho.sub_model = o.linear;
      ho.sub_model.ridge_lambda = o.ridge_lambda;
      std::vector<std::string> warnings;
      auto m = std::make_unique<HysteresisThermalModel>(FitHysteresisModel(s, ho, &warnings));
      if (fit_report) {
        std::vector<ThermalInterval> cls = m->ClassifyRows(s);
        int count[kThermalIntervalCount + 1] = {0, 0, 0, 0};
        for (auto c : cls) ++count[static_cast<int>(c)];
        *fit_report = fmt::format("training rows: {} heating, {} steady, {} cooling, {} start-up\n", count[0], count[1],
                                  count[2], count[3]);
        for (const auto& w : warnings) *fit_report += "warning: " + w + "\n";
      }
      return m;
    }
  }
  throw InputError("fit options", "unknown model kind");
}

std::string ThermalEvaluation::SplitDescription() const {
  auto list = [&](const std::vector<int>& ids) {
    std::string out;
    for (int b : ids) {
      const SpeedBlock& k = blocks[static_cast<std::size_t>(b)];
      out += fmt::format("{}{}({} rpm, {:.2f}-{:.2f} h)", out.empty() ? "" : ", ", b, k.spindle_rpm, k.start_s / 3600,
                         k.end_s / 3600);
    }
    return out;
  };
  if (!split.empty()) {
    std::string out = split + "\n";
    if (folds.size() > 1)
      for (const auto& f : folds)
        out += fmt::format("  fold {}: validate {} rows, train {} rows\n", f.name, f.validate_rows.size(), f.train_rows.size());
    return out;
  }
  if (time_split_fraction > 0 && !train_rows.empty() && !validate_rows.empty()) {
    auto hours = [&](Eigen::Index r) {
      return series.has_time ? fmt::format("{:.2f} h", series.time_s[static_cast<std::size_t>(r)] / 3600)
                             : fmt::format("row {}", r);
    };
    return fmt::format("split in time: train on the first {} rows ({} … {}), validate on the last {:.0f} %: {} rows "
                       "({} … {})\n", train_rows.size(), hours(train_rows.front()), hours(train_rows.back()),
                       100 * time_split_fraction, validate_rows.size(), hours(validate_rows.front()),
                       hours(validate_rows.back()));
  }
  std::string out = fmt::format("train: {} rows in blocks {}\nvalidate: {} rows in blocks {}\n", train_rows.size(),
                                list(train_blocks), validate_rows.size(), list(validate_blocks));
  if (in_sample) out += "NOTE: validation overlaps training: these are in-sample (fit) residuals\n";
  return out;
}

namespace {
// Validation RMSE as a percentage of a baseline's; "-" when the baseline is 0.
std::string PercentOf(double rmse, double baseline) {
  return baseline > 0 ? fmt::format("{:.0f} %", 100 * rmse / baseline) : std::string("-");
}
}  // namespace

std::string ThermalEvaluation::BriefReport() const {
  std::string out = fmt::format("{:<22} {:<8} {:>12} {:>12} {:>12} {:>12} {:>8} {:>8}\n", "model", "channel",
                                "train RMSE", "train max", "valid RMSE", "valid max", "% none", "% const");
  auto rows = [&](const std::string& name, const std::vector<ChannelMetrics>& tr, const std::vector<ChannelMetrics>& va) {
    for (std::size_t c = 0; c < tr.size(); ++c)
      out += fmt::format("{:<22} {:<8} {:>12.3f} {:>12.3f} {:>12.3f} {:>12.3f} {:>8} {:>8}\n", name, tr[c].channel,
                         tr[c].rmse_um, tr[c].max_abs_um, va[c].rmse_um, va[c].max_abs_um,
                         PercentOf(va[c].rmse_um, baseline_validate[c].rmse_um),
                         PercentOf(va[c].rmse_um, constant_validate[c].rmse_um));
  };
  rows("no compensation", baseline_train, baseline_validate);
  rows("constant (train mean)", constant_train, constant_validate);
  for (const auto& m : models) rows(m.name, m.train, m.validate);
  out += "(µm; residual = measured - predicted; no compensation = the measured error; constant = the training "
         "mean of the error; % = validation RMSE against those two baselines)\n";
  return out;
}

std::string ThermalEvaluation::MarkdownTable() const {
  std::string out = "| model | channel | train RMSE (µm) | train max \\|e\\| (µm) | validation RMSE (µm) | validation max \\|e\\| (µm) | % of none | % of constant |\n";
  out += "|---|---|---:|---:|---:|---:|---:|---:|\n";
  auto rows = [&](const std::string& name, const std::vector<ChannelMetrics>& tr, const std::vector<ChannelMetrics>& va) {
    for (std::size_t c = 0; c < tr.size(); ++c)
      out += fmt::format("| {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {} | {} |\n", name, tr[c].channel,
                         tr[c].rmse_um, tr[c].max_abs_um, va[c].rmse_um, va[c].max_abs_um,
                         PercentOf(va[c].rmse_um, baseline_validate[c].rmse_um),
                         PercentOf(va[c].rmse_um, constant_validate[c].rmse_um));
  };
  rows("no compensation", baseline_train, baseline_validate);
  rows("constant (train mean)", constant_train, constant_validate);
  for (const auto& m : models) rows(m.name, m.train, m.validate);
  return out;
}

namespace {

std::vector<Eigen::Index> Complement(Eigen::Index n, const std::vector<Eigen::Index>& rows) {
  std::vector<bool> in(static_cast<std::size_t>(n), false);
  for (Eigen::Index r : rows) in[static_cast<std::size_t>(r)] = true;
  std::vector<Eigen::Index> out;
  for (Eigen::Index r = 0; r < n; ++r)
    if (!in[static_cast<std::size_t>(r)]) out.push_back(r);
  return out;
}

// "A-B[,C-D]" of numbers (rows or hours) as closed ranges.
std::vector<std::pair<double, double>> ParseRanges(const std::string& text, const std::string& field) {
  std::vector<std::pair<double, double>> out;
  std::size_t pos = 0;
  const std::string t(Trim(text));
  while (pos <= t.size()) {
    const auto comma = t.find(',', pos);
    const std::string part(Trim(std::string_view(t).substr(pos, comma == std::string::npos ? std::string::npos : comma - pos)));
    pos = comma == std::string::npos ? t.size() + 1 : comma + 1;
    const auto dash = part.find('-', 1);
    const auto a = ParseDouble(part.substr(0, dash));
    const auto b = dash == std::string::npos ? a : ParseDouble(part.substr(dash + 1));
    if (!a || !b || *a > *b || *a < 0)
      throw InputError("command line", 0, field, fmt::format("'{}' is not a range such as 100-200", part));
    out.emplace_back(*a, *b);
  }
  return out;
}

// The folds of the requested split, and its description.
void ChooseSplit(const ThermalSeries& s, const EvaluationOptions& o, ThermalEvaluation* ev) {
  const Eigen::Index n = s.Rows();
  const int nb = static_cast<int>(ev->blocks.size());
  const int experiments = s.ExperimentCount();
  const bool blocks_given = o.train_blocks != "auto" || o.validate_blocks != "auto";
  int given = (blocks_given ? 1 : 0) + (o.validate_last_fraction != 0 ? 1 : 0) + (!o.validate_rows.empty() ? 1 : 0) +
              (!o.validate_hours.empty() ? 1 : 0) + (!o.validate_experiments.empty() ? 1 : 0);
  if (given > 1)
    throw InputError("command line", 0, "--split",
                     "give one split: blocks, --validate-last, --validate-rows, --validate-hours or --validate-experiments");
  std::string by_experiment = o.validate_experiments;
  if (given == 0 && experiments > 1) by_experiment = "each";
  SplitFold fold;
  bool train_chosen = false;  // the training rows are set, even when none are left
  if (!by_experiment.empty()) {
    if (experiments < 2)
      throw InputError("command line", 0, "--validate-experiments",
                       "the series is a single experiment: give several --series files (or workbook sheets)");
    std::vector<int> held;
    if (by_experiment == "each") {
      for (int e = 0; e < experiments; ++e) held.push_back(e);
    } else {
      held = ParseBlockList(by_experiment, experiments, "--validate-experiments");
      if (static_cast<int>(held.size()) == experiments)
        throw InputError("command line", 0, "--validate-experiments", "nothing left to train on");
    }
    auto rows_of = [&](int e) {
      std::vector<Eigen::Index> rows;
      for (Eigen::Index r = 0; r < n; ++r)
        if (s.ExperimentOf(r) == e) rows.push_back(r);
      return rows;
    };
    if (by_experiment == "each") {
      for (int e : held) {
        SplitFold f;
        f.name = fmt::format("experiment {} ({})", e, s.experiment_names[static_cast<std::size_t>(e)]);
        f.validate_rows = rows_of(e);
        f.train_rows = Complement(n, f.validate_rows);
        ev->folds.push_back(std::move(f));
      }
      ev->split = fmt::format("leave one experiment out: {} folds, each experiment validated by the models fitted on "
                              "the others", experiments);
      ev->train_rows = Complement(n, {});
      ev->validate_rows = ev->train_rows;
      return;
    }
    for (int e : held) {
      auto rows = rows_of(e);
      fold.validate_rows.insert(fold.validate_rows.end(), rows.begin(), rows.end());
    }
    std::sort(fold.validate_rows.begin(), fold.validate_rows.end());
    std::vector<std::string> names;
    for (int e : held) names.push_back(s.experiment_names[static_cast<std::size_t>(e)]);
    ev->split = fmt::format("by experiment: validate on {}, train on the others", fmt::join(names, ", "));
  } else if (!o.validate_rows.empty() || !o.validate_hours.empty()) {
    const bool hours = !o.validate_hours.empty();
    if (hours && !s.has_time) throw InputError("command line", 0, "--validate-hours", "the series has no time_s");
    const auto ranges = ParseRanges(hours ? o.validate_hours : o.validate_rows, hours ? "--validate-hours" : "--validate-rows");
    for (Eigen::Index r = 0; r < n; ++r) {
      const double v = hours ? s.time_s[static_cast<std::size_t>(r)] / 3600.0 : static_cast<double>(r);
      for (const auto& [a, b] : ranges)
        if (v >= a && v <= b) {
          fold.validate_rows.push_back(r);
          break;
        }
    }
    if (fold.validate_rows.empty())
      throw InputError("command line", 0, hours ? "--validate-hours" : "--validate-rows",
                       fmt::format("selects no row (the series has rows 0..{}{})", n - 1,
                                   s.has_time ? fmt::format(", {:.2f}..{:.2f} h", s.time_s.front() / 3600,
                                                            s.time_s.back() / 3600)
                                              : std::string()));
    // A drift recording is a time series: rows after the validated ones hold its future, and a
    // model trained on them interpolates instead of predicting. Only the rows before are trained on.
    const std::string what = fmt::format("validate on {} {} ({} rows)", hours ? "hours" : "rows",
                                         hours ? o.validate_hours : o.validate_rows, fold.validate_rows.size());
    if (o.train_after_validation) {
      ev->split = fmt::format("{}, train on the other {} rows, including those after them", what,
                              n - static_cast<Eigen::Index>(fold.validate_rows.size()));
    } else {
      for (Eigen::Index r = 0; r < fold.validate_rows.front(); ++r) fold.train_rows.push_back(r);
      train_chosen = true;
      const auto unused = n - static_cast<Eigen::Index>(fold.validate_rows.size() + fold.train_rows.size());
      ev->split = fmt::format("{}, train on the {} rows before them{}", what, fold.train_rows.size(),
                              unused > 0 ? fmt::format(" (not on the {} rows after: --train-after-validation trains "
                                                       "on those too)", unused)
                                         : std::string());
    }
  } else {
    double fraction = o.validate_last_fraction;
    if (!(fraction >= 0 && fraction < 1))
      throw InputError("--validate-last", "the validated fraction must be in (0, 1)");
    if (fraction == 0 && nb == 1 && !blocks_given) fraction = 0.3;
    if (fraction > 0) {
      const Eigen::Index n_train = static_cast<Eigen::Index>(std::floor((1 - fraction) * static_cast<double>(n)));
      if (n_train < 3 || n - n_train < 1)
        throw InputError("--validate-last", fmt::format("{} rows cannot be split {:.0f} % / {:.0f} %", n,
                                                        100 * (1 - fraction), 100 * fraction));
      ev->time_split_fraction = fraction;
      for (Eigen::Index r = n_train; r < n; ++r) fold.validate_rows.push_back(r);
    } else {
      if (o.train_blocks == "auto") {
        const int ntrain = nb == 1 ? 1 : std::min(nb - 1, (nb * 6 + 9) / 10);
        for (int b = 0; b < ntrain; ++b) ev->train_blocks.push_back(b);
      } else {
        ev->train_blocks = ParseBlockList(o.train_blocks, nb, "--train-blocks");
      }
      if (o.validate_blocks == "auto") {
        for (int b = 0; b < nb; ++b)
          if (std::find(ev->train_blocks.begin(), ev->train_blocks.end(), b) == ev->train_blocks.end())
            ev->validate_blocks.push_back(b);
        if (ev->validate_blocks.empty()) ev->validate_blocks = ev->train_blocks;
      } else {
        ev->validate_blocks = ParseBlockList(o.validate_blocks, nb, "--validate-blocks");
      }
      for (int b : ev->validate_blocks)
        if (std::find(ev->train_blocks.begin(), ev->train_blocks.end(), b) != ev->train_blocks.end()) ev->in_sample = true;
      fold.train_rows = RowsOfBlocks(ev->blocks, ev->train_blocks);
      fold.validate_rows = RowsOfBlocks(ev->blocks, ev->validate_blocks);
    }
  }
  if (fold.train_rows.empty() && !train_chosen) fold.train_rows = Complement(n, fold.validate_rows);
  fold.name = "split";
  ev->train_rows = fold.train_rows;
  ev->validate_rows = fold.validate_rows;
  ev->folds.push_back(std::move(fold));
}

std::string ModelLabel(const ThermalFitOptions& fo) {
  const bool all = fo.linear.selection.method == SelectionMethod::kAll &&
                   (fo.kind == ModelKind::kMlr || fo.kind == ModelKind::kRidge || fo.kind == ModelKind::kHysteresis);
  return std::string(ModelKindName(fo.kind)) + (!all ? "" : fo.sensors_listed ? " (listed sensors)" : " (all sensors)");
}

}  // namespace

ThermalEvaluation EvaluateThermalModels(const ThermalSeries& cleaned, SeriesCleaningReport cleaning,
                                        const EvaluationOptions& o) {
  ThermalEvaluation ev;
  ev.series = cleaned;
  ev.cleaning = std::move(cleaning);
  ev.blocks = SpeedBlocks(cleaned);
  ChooseSplit(cleaned, o, &ev);
  // Name the option that made the split: the block options only when no other split replaced them.
  const char* split_option = !o.validate_rows.empty()          ? "--validate-rows"
                             : !o.validate_hours.empty()       ? "--validate-hours"
                             : !o.validate_experiments.empty() ? "--validate-experiments"
                             : o.validate_last_fraction > 0    ? "--validate-last"
                                                               : "--train-blocks";
  for (const auto& f : ev.folds)
    if (f.train_rows.size() < 3)
      throw InputError("command line", 0, split_option,
                       fmt::format("{}: fewer than 3 training rows ({} of {} rows left to train on){}", f.name,
                                   f.train_rows.size(), cleaned.Rows(),
                                   (!o.validate_rows.empty() || !o.validate_hours.empty()) && !o.train_after_validation
                                       ? "; only rows before the validated ones are trained on (--train-after-validation "
                                         "also uses those after)"
                                       : ""));
  const Eigen::Index n = cleaned.Rows(), channels = cleaned.errors_um.cols();
  const bool pooled = ev.folds.size() > 1;
  ev.baseline_train = ResidualMetrics(cleaned, Eigen::MatrixXd(), ev.train_rows);
  ev.baseline_validate = ResidualMetrics(cleaned, Eigen::MatrixXd(), ev.validate_rows);
  {
    // Constant = training mean per channel, per fold (out of fold where pooled).
    auto mean_of = [&](const std::vector<Eigen::Index>& rows, Eigen::Index c) {
      double sum = 0;
      int k = 0;
      for (Eigen::Index r : rows)
        if (std::isfinite(cleaned.errors_um(r, c))) sum += cleaned.errors_um(r, c), ++k;
      return k ? sum / k : 0.0;
    };
    Eigen::MatrixXd in_sample(n, channels), out_of_fold(n, channels);
    for (Eigen::Index c = 0; c < channels; ++c) in_sample.col(c).setConstant(mean_of(ev.train_rows, c));
    out_of_fold = in_sample;
    for (const auto& f : ev.folds)
      for (Eigen::Index c = 0; c < channels; ++c) {
        const double m = mean_of(f.train_rows, c);
        for (Eigen::Index r : f.validate_rows) out_of_fold(r, c) = m;
      }
    ev.constant_train = ResidualMetrics(cleaned, in_sample, ev.train_rows);
    ev.constant_validate = ResidualMetrics(cleaned, out_of_fold, ev.validate_rows);
  }
  std::vector<ThermalFitOptions> models = o.models;
  if (o.all_sensors_reference) {
    ThermalFitOptions all;
    all.kind = ModelKind::kRidge;
    all.linear.selection.method = SelectionMethod::kAll;
    if (!models.empty()) all.ridge_lambda = models.front().ridge_lambda;
    // With a sensor list the series holds only the listed sensors: "all" of them is the list.
    for (const auto& m : models) all.sensors_listed = all.sensors_listed || m.sensors_listed;
    bool present = false;
    for (const auto& m : models) present = present || ModelLabel(m) == ModelLabel(all);
    if (!present) models.insert(models.begin(), all);
  }
  // Progress: one fit per model, plus one per fold where the folds are pooled.
  const std::size_t fits_per_model = 1 + (pooled ? ev.folds.size() : 0);
  std::size_t fits_done = 0;
  auto tell = [&](const std::string& what) {
    if (o.progress) o.progress(fits_done, models.size() * fits_per_model, what);
  };
  for (const auto& fo : models) {
    ModelEvaluation me;
    me.name = ModelLabel(fo);
    const auto t0 = std::chrono::steady_clock::now();
    tell(fmt::format("{}: fitting on the training rows", me.name));
    me.model = FitThermalModel(SelectRows(cleaned, ev.train_rows), fo, &me.fit_report);
    ++fits_done;
    if (fo.kind == ModelKind::kAuto) me.name += fmt::format(" ({})", me.model->Kind());
    me.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    me.predicted_um = PredictSeries(*me.model, cleaned);
    me.train = ResidualMetrics(cleaned, me.predicted_um, ev.train_rows);
    if (pooled) {
      for (const auto& f : ev.folds) {
        tell(fmt::format("{}: fold {}", me.name, f.name));
        auto fold_model = FitThermalModel(SelectRows(cleaned, f.train_rows), fo, nullptr);
        const Eigen::MatrixXd p = PredictSeries(*fold_model, cleaned);
        for (Eigen::Index r : f.validate_rows) me.predicted_um.row(r) = p.row(r);
        ++fits_done;
      }
    }
    me.validate = ResidualMetrics(cleaned, me.predicted_um, ev.validate_rows);
    ev.models.push_back(std::move(me));
  }
  if (o.progress) o.progress(fits_done, fits_done, "done");
  return ev;
}

}  // namespace trueaxis::thermal
