#include "trueaxis/thermal/model_fitting.hpp"

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::thermal {

const char* ModelKindName(ModelKind k) {
  switch (k) {
    case ModelKind::kMlr: return "mlr";
    case ModelKind::kRidge: return "ridge";
    case ModelKind::kPsoBp: return "pso-bp";
    case ModelKind::kHysteresis: return "hysteresis";
  }
  return "?";
}

bool ParseModelKind(const std::string& text, ModelKind* out) {
  for (auto k : {ModelKind::kMlr, ModelKind::kRidge, ModelKind::kPsoBp, ModelKind::kHysteresis})
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
    case ModelKind::kHysteresis: return linear.IsValid(why) && hysteresis.classifier.IsValid(why);
  }
  return true;
}

std::unique_ptr<ThermalErrorModel> FitThermalModel(const ThermalSeries& s, const ThermalFitOptions& o,
                                                   std::string* fit_report) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("fit options", why);
  if (s.error_names.empty()) throw InputError(s.source, 0, "", "no error channel to fit");
  switch (o.kind) {
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
      auto m = std::make_unique<HysteresisThermalModel>(FitHysteresisModel(s, ho));
      if (fit_report) {
        std::vector<ThermalInterval> cls = m->ClassifyRows(s);
        int count[kThermalIntervalCount] = {0, 0, 0};
        for (auto c : cls) ++count[static_cast<int>(c)];
        *fit_report = fmt::format("training rows: {} heating, {} steady, {} cooling\n", count[0], count[1], count[2]);
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

ThermalEvaluation EvaluateThermalModels(const ThermalSeries& cleaned, SeriesCleaningReport cleaning,
                                        const EvaluationOptions& o) {
  ThermalEvaluation ev;
  ev.series = cleaned;
  ev.cleaning = std::move(cleaning);
  ev.blocks = SpeedBlocks(cleaned);
  const int nb = static_cast<int>(ev.blocks.size());
  double fraction = o.validate_last_fraction;
  if (!(fraction >= 0 && fraction < 1))
    throw InputError("--validate-last", "the validated fraction must be in (0, 1)");
  if (fraction == 0 && nb == 1 && o.train_blocks == "auto" && o.validate_blocks == "auto") fraction = 0.3;
  if (fraction > 0) {
    const Eigen::Index n = cleaned.Rows();
    const Eigen::Index n_train = static_cast<Eigen::Index>(std::floor((1 - fraction) * static_cast<double>(n)));
    if (n_train < 3 || n - n_train < 1)
      throw InputError("--validate-last", fmt::format("{} rows cannot be split {:.0f} % / {:.0f} %", n,
                                                      100 * (1 - fraction), 100 * fraction));
    ev.time_split_fraction = fraction;
    for (Eigen::Index r = 0; r < n; ++r) (r < n_train ? ev.train_rows : ev.validate_rows).push_back(r);
  } else if (o.train_blocks == "auto") {
    const int ntrain = nb == 1 ? 1 : std::min(nb - 1, (nb * 6 + 9) / 10);
    for (int b = 0; b < ntrain; ++b) ev.train_blocks.push_back(b);
  } else {
    ev.train_blocks = ParseBlockList(o.train_blocks, nb, "--train-blocks");
  }
  if (fraction > 0) {
    // time split: rows chosen above, blocks unused
  } else if (o.validate_blocks == "auto") {
    for (int b = 0; b < nb; ++b)
      if (std::find(ev.train_blocks.begin(), ev.train_blocks.end(), b) == ev.train_blocks.end())
        ev.validate_blocks.push_back(b);
    if (ev.validate_blocks.empty()) ev.validate_blocks = ev.train_blocks;
  } else {
    ev.validate_blocks = ParseBlockList(o.validate_blocks, nb, "--validate-blocks");
  }
  if (fraction == 0) {
    for (int b : ev.validate_blocks)
      if (std::find(ev.train_blocks.begin(), ev.train_blocks.end(), b) != ev.train_blocks.end()) ev.in_sample = true;
    ev.train_rows = RowsOfBlocks(ev.blocks, ev.train_blocks);
    ev.validate_rows = RowsOfBlocks(ev.blocks, ev.validate_blocks);
  }
  if (ev.train_rows.size() < 3) throw InputError("--train-blocks", "fewer than 3 training rows");
  const ThermalSeries train = SelectRows(cleaned, ev.train_rows);
  ev.baseline_train = ResidualMetrics(cleaned, Eigen::MatrixXd(), ev.train_rows);
  ev.baseline_validate = ResidualMetrics(cleaned, Eigen::MatrixXd(), ev.validate_rows);
  {
    Eigen::MatrixXd constant(cleaned.errors_um.rows(), cleaned.errors_um.cols());
    for (Eigen::Index c = 0; c < cleaned.errors_um.cols(); ++c) {
      double sum = 0;
      int n = 0;
      for (Eigen::Index r : ev.train_rows)
        if (std::isfinite(cleaned.errors_um(r, c))) sum += cleaned.errors_um(r, c), ++n;
      constant.col(c).setConstant(n ? sum / n : 0.0);
    }
    ev.constant_train = ResidualMetrics(cleaned, constant, ev.train_rows);
    ev.constant_validate = ResidualMetrics(cleaned, constant, ev.validate_rows);
  }
  for (const auto& fo : o.models) {
    ModelEvaluation me;
    me.name = ModelKindName(fo.kind);
    const auto t0 = std::chrono::steady_clock::now();
    me.model = FitThermalModel(train, fo, &me.fit_report);
    me.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    me.predicted_um = PredictSeries(*me.model, cleaned);
    me.train = ResidualMetrics(cleaned, me.predicted_um, ev.train_rows);
    me.validate = ResidualMetrics(cleaned, me.predicted_um, ev.validate_rows);
    ev.models.push_back(std::move(me));
  }
  return ev;
}

}  // namespace trueaxis::thermal
