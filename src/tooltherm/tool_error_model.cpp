#include "trueaxis/tooltherm/tool_error_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/tooltherm/zone_temperature.hpp"

namespace trueaxis::tooltherm {
namespace {

constexpr int kMinIntervalRows = 20;
// Weight of the free growth in the zones fit, as a share of the mean diagonal of XᵀX: it settles
// what the zone means cannot tell apart (zones that warm together) and leaves what they can to the data.
constexpr double kZoneGrowthRidge = 0.1;

// First-order lag of Tv, restarting at Tv on every mounting.
std::vector<double> LagSeries(const std::vector<ToolRecord>& rows, double tau_s) {
  std::vector<double> out(rows.size());
  double l = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].restart || i == 0) l = rows[i].tv_c;
    else l += (1.0 - std::exp(-(rows[i].time_s - rows[i - 1].time_s) / tau_s)) * (rows[i].tv_c - l);
    out[i] = l;
  }
  return out;
}

// Least squares y ≈ X·β; the RMS of the residual in *rms.
Eigen::VectorXd Solve(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double* rms) {
  Eigen::VectorXd beta = x.colPivHouseholderQr().solve(y);
  if (rms) *rms = std::sqrt((x * beta - y).squaredNorm() / static_cast<double>(y.size()));
  return beta;
}

LinearTerm FitLine(const std::vector<double>& t_c, const std::vector<double>& e_um, double t_std, double* rms) {
  const auto n = static_cast<Eigen::Index>(t_c.size());
  Eigen::MatrixXd x(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    x(i, 0) = 1;
    x(i, 1) = t_c[static_cast<std::size_t>(i)] - t_std;
    y(i) = e_um[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd b = Solve(x, y, rms);
  return {b(0), b(1)};
}

std::vector<double> TauGrid() {
  std::vector<double> g;
  for (double tau = 5; tau <= 7200 * 1.0001; tau *= 1.25) g.push_back(tau);
  return g;
}

double Rms(const std::vector<double>& a, const std::vector<ToolRecord>& rows) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - rows[i].error_um) * (a[i] - rows[i].error_um);
  return std::sqrt(s / static_cast<double>(a.size()));
}

double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
  double saa = 0, sbb = 0, sab = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
    sab += (a[i] - ma) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 1.0;
}

// Fits the interval sub-models for one classifier setting; returns their training RMS.
// The classes and the rise since each interval's start come from the predictor itself, so the
// fit sees exactly what a runtime will. An interval whose Tv span is under half the whole
// course's span cannot fix a slope of its own: it keeps the one model's slope. The rise term
// is fitted for heating and cooling (a steady interval has no branch to follow) and only where
// it is not Tv again (|correlation| < 0.95: the branches began from different temperatures). Prediction holds the difference from the one model at the edges of
// the interval's training ranges (no wild extrapolation).
double FitIntervals(ToolErrorModel& m, const std::vector<ToolRecord>& rows) {
  std::vector<ThermalInterval> cls(rows.size());
  std::vector<double> rise(rows.size());
  {
    ToolErrorPredictor p(m, ToolModelKind::kOne);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      p.Push(rows[i].time_s, rows[i].tv_c, rows[i].restart || i == 0);
      cls[i] = p.interval();
      rise[i] = p.rise_c();
    }
  }
  double lo_all = INFINITY, hi_all = -INFINITY;
  for (const auto& r : rows) lo_all = std::min(lo_all, r.tv_c), hi_all = std::max(hi_all, r.tv_c);
  for (int k = 0; k < 3; ++k) {
    std::vector<double> d, r, y;
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (static_cast<int>(cls[i]) == k) {
        d.push_back(rows[i].tv_c - m.standard_temp_c);
        r.push_back(rise[i]);
        y.push_back(rows[i].error_um);
      }
    m.interval_rows[k] = static_cast<int>(d.size());
    m.interval_fitted[k] = d.size() >= kMinIntervalRows;
    m.interval[k] = IntervalTerm{m.one};
    if (!m.interval_fitted[k]) continue;
    IntervalTerm& it = m.interval[k];
    const auto [dl, dh] = std::minmax_element(d.begin(), d.end());
    const auto [rl, rh] = std::minmax_element(r.begin(), r.end());
    it.tv_from_c = *dl + m.standard_temp_c;
    it.tv_to_c = *dh + m.standard_temp_c;
    it.rise_from_c = *rl;
    it.rise_to_c = *rh;
    const bool own_slope = *dh - *dl >= 0.5 * (hi_all - lo_all);
    const bool use_rise = k != static_cast<int>(ThermalInterval::kSteady) && *rh > *rl && std::abs(Correlation(d, r)) < 0.95;
    const auto n = static_cast<Eigen::Index>(d.size());
    Eigen::MatrixXd x(n, 1 + (own_slope ? 1 : 0) + (use_rise ? 1 : 0));
    Eigen::VectorXd yy(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto j = static_cast<std::size_t>(i);
      Eigen::Index c = 0;
      x(i, c++) = 1;
      if (own_slope) x(i, c++) = d[j];
      if (use_rise) x(i, c++) = r[j];
      yy(i) = y[j] - (own_slope ? 0.0 : m.one.per_c_um * d[j]);
    }
    const Eigen::VectorXd b = Solve(x, yy, nullptr);
    Eigen::Index c = 0;
    it.line.intercept_um = b(c++);
    it.line.per_c_um = own_slope ? b(c++) : m.one.per_c_um;
    it.per_c_since_start_um = use_rise ? b(c++) : 0.0;
  }
  return Rms(PredictSeries(m, ToolModelKind::kIntervals, rows), rows);
}

}  // namespace

ToolColumns ColumnsOf(const std::vector<ToolRecord>& rows) {
  ToolColumns c;
  for (const auto& r : rows) {
    c.time_s.push_back(r.time_s);
    c.tv_c.push_back(r.tv_c);
    c.error_um.push_back(r.error_um);
    c.restart.push_back(r.restart);
  }
  return c;
}

const char* ToolModelKindName(ToolModelKind k) {
  switch (k) {
    case ToolModelKind::kNone: return "none";
    case ToolModelKind::kOne: return "one";
    case ToolModelKind::kIntervals: return "intervals";
    case ToolModelKind::kLag: return "lag";
    case ToolModelKind::kTwoBody: return "two_body";
    case ToolModelKind::kZones: return "zones";
    case ToolModelKind::kBest: return "best";
  }
  return "?";
}

ToolModelKind ParseToolModelKind(const std::string& name) {
  for (ToolModelKind k : kToolModelKinds)
    if (name == ToolModelKindName(k)) return k;
  throw std::invalid_argument("unknown model '" + name + "' (none, one, intervals, lag, two_body, zones, best)");
}

ToolErrorPredictor::ToolErrorPredictor(const ToolErrorModel& model, ToolModelKind kind)
    : m_(&model), kind_(kind), classifier_(model.classifier) {}

double ToolErrorPredictor::Push(double time_s, double tv_c, bool restart, std::span<const double> zone_c) {
  const ToolErrorModel& m = *m_;
  const double dt_s = restart ? 0.0 : std::max(time_s - last_t_, 0.0);
  if (restart) {
    classifier_.Reset();
    lag_c_ = two_body_lag_c_ = tv_c;
  } else {
    lag_c_ += (1.0 - std::exp(-dt_s / m.lag_tau_s)) * (tv_c - lag_c_);
    two_body_lag_c_ += (1.0 - std::exp(-dt_s / m.two_body_tau_s)) * (tv_c - two_body_lag_c_);
  }
  last_t_ = time_s;
  const ThermalInterval before = interval_;
  interval_ = classifier_.Push(time_s, tv_c);
  if (restart) {
    smooth_tv_c_ = interval_start_tv_c_ = tv_c;
  } else {
    smooth_tv_c_ += (1.0 - std::exp(-dt_s / (0.5 * classifier_.window_s()))) * (tv_c - smooth_tv_c_);
    if (interval_ != before) interval_start_tv_c_ = smooth_tv_c_;
  }
  rise_c_ = tv_c - interval_start_tv_c_;
  const double d = tv_c - m.standard_temp_c;
  ToolModelKind kind = kind_;
  if (kind == ToolModelKind::kBest)  // zones need this tool's zone means; else the Tv models' choice
    kind = m.best == ToolModelKind::kZones && zone_c.size() == m.zone_um_per_c.size() ? ToolModelKind::kZones
                                                                                        : m.best_without_zones;
  switch (kind) {
    case ToolModelKind::kNone: return 0;
    case ToolModelKind::kOne: return m.one.intercept_um + m.one.per_c_um * d;
    case ToolModelKind::kIntervals: {
      const auto k = static_cast<std::size_t>(interval_);
      const double one = m.one.intercept_um + m.one.per_c_um * d;
      if (k >= 3 || !m.interval_fitted[k]) return one;
      const IntervalTerm& it = m.interval[k];
      const double dc = std::clamp(tv_c, it.tv_from_c, it.tv_to_c) - m.standard_temp_c;
      const double rc = std::clamp(rise_c_, it.rise_from_c, it.rise_to_c);
      return one + it.weight * ((it.line.intercept_um - m.one.intercept_um) + (it.line.per_c_um - m.one.per_c_um) * dc +
                                it.per_c_since_start_um * rc);
    }
    case ToolModelKind::kLag: return m.lag.intercept_um + m.lag.per_c_um * (lag_c_ - m.standard_temp_c);
    case ToolModelKind::kZones:
      if (!m.zone_um_per_c.empty() && zone_c.size() == m.zone_um_per_c.size()) {
        const bool beyond = m.zone_training_range_c.size() == zone_c.size() && m.zone_beyond_um_per_c.size() == zone_c.size();
        double e = m.zone_intercept_um;
        for (std::size_t r = 0; r < zone_c.size(); ++r) {
          const double inside = beyond ? std::clamp(zone_c[r], m.zone_training_range_c[r].first, m.zone_training_range_c[r].second)
                                       : zone_c[r];
          e += m.zone_um_per_c[r] * (inside - m.standard_temp_c);
          if (beyond) e += m.zone_beyond_um_per_c[r] * (zone_c[r] - inside);
        }
        return e;
      }
      return m.one.intercept_um + m.one.per_c_um * d;
    case ToolModelKind::kBest:  // resolved above
    case ToolModelKind::kTwoBody:
      return m.two_body_intercept_um + m.two_body_tv_um_per_c * d +
             m.two_body_lag_um_per_c * (two_body_lag_c_ - m.standard_temp_c);
  }
  return 0;
}

std::vector<double> PredictSeries(const ToolErrorModel& model, ToolModelKind kind, const std::vector<ToolRecord>& rows) {
  ToolErrorPredictor p(model, kind);
  std::vector<double> out;
  out.reserve(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) out.push_back(p.Push(rows[i].time_s, rows[i].tv_c, rows[i].restart || i == 0, rows[i].zone_c));
  return out;
}

namespace {

// Zones: e = a + Σ b_r·(Tr − T_std), ridge least squares. Without the free growth per zone the
// ridge pulls towards 0 (λ = 1e-4·mean diagonal). With it (`growth`, from the tool file) the ridge
// pulls the slopes towards −growth_r (λ = kZoneGrowthRidge·mean diagonal), the fit is continued
// beyond each zone's training range of Tr by −growth_r (docs/tool-thermal.md, "Beyond the training
// range"), and a tool with too few rows for its own zone slopes takes −growth_r and fits the
// intercept alone.
void FitZones(ToolErrorModel& m, const std::vector<ToolRecord>& rows, std::span<const double> growth) {
  const double t_std = m.standard_temp_c;
  const std::size_t nz = rows.front().zone_c.size();
  const bool physics = growth.size() == nz;
  m.zone_um_per_c.clear();
  m.zone_training_range_c.clear();
  m.zone_beyond_um_per_c.clear();
  if (rows.size() >= kMinZoneRowsPerCoefficient * (nz + 1)) {
    const auto n = static_cast<Eigen::Index>(rows.size());
    const auto nzi = static_cast<Eigen::Index>(nz);
    Eigen::MatrixXd x(n, nzi + 1);
    Eigen::VectorXd y(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const ToolRecord& row = rows[static_cast<std::size_t>(i)];
      x(i, 0) = 1;
      for (std::size_t r = 0; r < nz; ++r) x(i, static_cast<Eigen::Index>(r + 1)) = row.zone_c[r] - t_std;
      y(i) = row.error_um;
    }
    Eigen::MatrixXd xtx = x.transpose() * x;
    Eigen::VectorXd rhs = x.transpose() * y;
    const double lambda = (physics ? kZoneGrowthRidge : 1e-4) * xtx.diagonal().tail(nzi).mean();
    for (Eigen::Index r = 1; r <= nzi; ++r) {
      xtx(r, r) += lambda;
      if (physics) rhs(r) -= lambda * growth[static_cast<std::size_t>(r - 1)];
    }
    const Eigen::VectorXd b = xtx.ldlt().solve(rhs);
    m.zone_intercept_um = b(0);
    m.zone_um_per_c.assign(b.data() + 1, b.data() + b.size());
  } else if (physics) {
    double sum = 0;
    for (const auto& row : rows) {
      double e = row.error_um;
      for (std::size_t r = 0; r < nz; ++r) e += growth[r] * (row.zone_c[r] - t_std);
      sum += e;
    }
    m.zone_intercept_um = sum / static_cast<double>(rows.size());
    for (double g : growth) m.zone_um_per_c.push_back(-g);
  } else {
    return;
  }
  if (!physics) return;
  // The range a zone really had: each reading against its neighbours in the same mounting (median
  // of three), so one frame's reflection or coolant splash does not widen it.
  for (std::size_t r = 0; r < nz; ++r) {
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      double v = rows[i].zone_c[r];
      if (i > 0 && i + 1 < rows.size() && !rows[i].restart && !rows[i + 1].restart) {
        const double a = rows[i - 1].zone_c[r], c = rows[i + 1].zone_c[r];
        v = std::max(std::min(a, v), std::min(std::max(a, v), c));
      }
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
    m.zone_training_range_c.emplace_back(lo, hi);
    m.zone_beyond_um_per_c.push_back(-growth[r]);
  }
}

ToolErrorModel FitStructures(int tool, const std::vector<ToolRecord>& rows, double t_std,
                             std::span<const double> zone_growth_um_per_c, std::vector<std::string>* warnings) {
  if (rows.size() < 20) throw std::invalid_argument(fmt::format("tool {}: {} rows, a fit needs ≥ 20", tool, rows.size()));
  if (!rows.front().restart) throw std::invalid_argument("the first row must start a mounting (restart)");
  for (std::size_t i = 1; i < rows.size(); ++i)
    if (!rows[i].restart && !(rows[i].time_s > rows[i - 1].time_s))
      throw std::invalid_argument(fmt::format("row {}: time must increase within a mounting", i + 1));
  ToolErrorModel m;
  m.tool = tool;
  m.standard_temp_c = t_std;
  m.training_rows = static_cast<int>(rows.size());
  const ToolColumns cols = ColumnsOf(rows);
  const std::vector<double>&t = cols.time_s, &tv = cols.tv_c, &e = cols.error_um;
  const std::vector<bool>& restart = cols.restart;
  m.training = SeriesStatisticsOf(t, tv);
  const auto [tv_lo, tv_hi] = std::minmax_element(tv.begin(), tv.end());
  m.training_tv_from_c = *tv_lo;
  m.training_tv_to_c = *tv_hi;
  m.one = FitLine(tv, e, t_std, nullptr);

  // Lag and two-body: τ on the grid, least squares for the rest.
  double best_lag = INFINITY, best_two = INFINITY;
  const auto n = static_cast<Eigen::Index>(rows.size());
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) y(i) = e[static_cast<std::size_t>(i)];
  for (double tau : TauGrid()) {
    const std::vector<double> l = LagSeries(rows, tau);
    Eigen::MatrixXd x(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      x(i, 0) = 1;
      x(i, 1) = l[static_cast<std::size_t>(i)] - t_std;
      x(i, 2) = tv[static_cast<std::size_t>(i)] - t_std;
    }
    double rms_lag = 0, rms_two = 0;
    const Eigen::VectorXd bl = Solve(x.leftCols(2), y, &rms_lag);
    const Eigen::VectorXd bt = Solve(x, y, &rms_two);
    if (rms_lag < best_lag) {
      best_lag = rms_lag;
      m.lag_tau_s = tau;
      m.lag = {bl(0), bl(1)};
    }
    if (rms_two < best_two) {
      best_two = rms_two;
      m.two_body_tau_s = tau;
      m.two_body_intercept_um = bt(0);
      m.two_body_lag_um_per_c = bt(1);
      m.two_body_tv_um_per_c = bt(2);
    }
  }

  // Zones: ridge least squares on the zone means, when every row has them.
  const std::size_t nz = rows.front().zone_c.size();
  const bool zones = nz > 0 && std::all_of(rows.begin(), rows.end(), [&](const ToolRecord& r) { return r.zone_c.size() == nz; });
  if (zones) FitZones(m, rows, zone_growth_um_per_c);

  // Intervals: the classifier's window (in sample steps) and dead band floor from the data.
  double best_int = INFINITY;
  ToolErrorModel best = m;
  for (double steps : {5.0, 10.0, 20.0, 40.0, 80.0, 160.0}) {
    const double p90 = SlopePercentileCPerH(t, tv, restart, ClassifierOptionsFor(m.training, steps, 0).window_s);
    for (double f : {0.05, 0.1, 0.2, 0.4}) {
      ToolErrorModel trial = m;
      trial.classifier = ClassifierOptionsFor(m.training, steps, f * p90);
      const double rms = FitIntervals(trial, rows);
      if (rms < best_int) {
        best_int = rms;
        best = trial;
      }
    }
  }
  m = best;
  if (warnings)
    for (int k = 0; k < 3; ++k)
      if (!m.interval_fitted[k])
        warnings->push_back(fmt::format("tool {}: {} interval has {} training rows (< {}): the one model stands in", tool,
                                        thermal::ThermalIntervalName(static_cast<ThermalInterval>(k)), m.interval_rows[k],
                                        kMinIntervalRows));
  return m;
}

// Blocked cross-validation: four contiguous blocks of the rows, each predicted by the models
// fitted on the other three (a held-out block starts as a fresh mounting).
// The same folds weigh each interval sub-model: on the held-out rows the fold models put in its
// interval, the share w ∈ [0, 1] of its difference from the one curve that predicts them best
// (least squares of the blend one + w·(sub − one)). w = 0 (the sub-model did not help, or no
// held-out rows fell in it, or the data are too short to tell): the one model stands in.
void ChooseBest(ToolErrorModel& m, const std::vector<ToolRecord>& rows, std::span<const double> zone_growth_um_per_c,
                std::vector<std::string>* warnings) {
  constexpr std::size_t kFolds = 4;
  std::array<double, 3> sse_int{}, sse_one{}, blend_num{}, blend_den{};
  std::array<int, 3> n_int{};
  auto gate_intervals = [&] {
    for (std::size_t k = 0; k < 3; ++k) {
      IntervalTerm& it = m.interval[k];
      it.cv_rows = n_int[k];
      it.cv_rms_um = n_int[k] ? std::sqrt(sse_int[k] / n_int[k]) : 0.0;
      it.cv_one_rms_um = n_int[k] ? std::sqrt(sse_one[k] / n_int[k]) : 0.0;
      // The blend e = one + w·(sub-model − one) with the lowest held-out error, w in [0, 1].
      it.weight = blend_den[k] > 0 ? std::clamp(blend_num[k] / blend_den[k], 0.0, 1.0) : 0.0;
      if (!m.interval_fitted[k] || it.weight > 0) continue;
      m.interval_fitted[k] = false;
      const IntervalTerm kept = it;
      it = IntervalTerm{m.one};
      it.cv_rows = kept.cv_rows, it.cv_rms_um = kept.cv_rms_um, it.cv_one_rms_um = kept.cv_one_rms_um;
      it.weight = 0;
      if (warnings)
        warnings->push_back(fmt::format(
            "tool {}: the {} sub-model did not improve on one curve for held-out data ({} rows, {:.2f} vs {:.2f} µm): "
            "the one model stands in",
            m.tool, thermal::ThermalIntervalName(static_cast<ThermalInterval>(k)), n_int[k], it.cv_rms_um, it.cv_one_rms_um));
    }
  };
  if (rows.size() < kFolds * 40) {  // too short to tell: the one model
    gate_intervals();
    return;
  }
  const std::array<ToolModelKind, 5> kinds = {ToolModelKind::kOne, ToolModelKind::kIntervals, ToolModelKind::kLag,
                                              ToolModelKind::kTwoBody, ToolModelKind::kZones};
  std::array<double, 5> sse{};
  bool zones = true;
  for (std::size_t f = 0; f < kFolds; ++f) {
    const std::size_t lo = rows.size() * f / kFolds, hi = rows.size() * (f + 1) / kFolds;
    std::vector<ToolRecord> train(rows.begin(), rows.begin() + static_cast<long>(lo));
    const std::size_t join = train.size();
    train.insert(train.end(), rows.begin() + static_cast<long>(hi), rows.end());
    if (join < train.size()) train[join].restart = true;
    train.front().restart = true;
    std::vector<ToolRecord> test(rows.begin() + static_cast<long>(lo), rows.begin() + static_cast<long>(hi));
    test.front().restart = true;
    const ToolErrorModel fm = FitStructures(m.tool, train, m.standard_temp_c, zone_growth_um_per_c, nullptr);
    zones = zones && !fm.zone_um_per_c.empty();
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      const auto p = PredictSeries(fm, kinds[k], test);
      for (std::size_t i = 0; i < test.size(); ++i) sse[k] += std::pow(p[i] - test[i].error_um, 2);
    }
    ToolErrorPredictor pi(fm, ToolModelKind::kIntervals), po(fm, ToolModelKind::kOne);
    for (std::size_t i = 0; i < test.size(); ++i) {
      const double ei = pi.Push(test[i].time_s, test[i].tv_c, test[i].restart || i == 0) - test[i].error_um;
      const double eo = po.Push(test[i].time_s, test[i].tv_c, test[i].restart || i == 0) - test[i].error_um;
      const auto k = static_cast<std::size_t>(pi.interval());
      if (k >= 3) continue;
      ++n_int[k];
      sse_int[k] += ei * ei;
      sse_one[k] += eo * eo;
      blend_num[k] += eo * (eo - ei);
      blend_den[k] += (eo - ei) * (eo - ei);
    }
  }
  gate_intervals();
  double lowest = INFINITY;
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    if (kinds[k] == ToolModelKind::kZones && !zones) continue;
    const double rms = std::sqrt(sse[k] / static_cast<double>(rows.size()));
    m.cv_rms_um[static_cast<std::size_t>(kinds[k])] = rms;
    if (kinds[k] != ToolModelKind::kZones && rms < lowest) lowest = rms, m.best = m.best_without_zones = kinds[k];
  }
}

}  // namespace

ToolErrorModel FitToolErrorModel(int tool, const std::vector<ToolRecord>& rows, double t_std,
                                 std::vector<std::string>* warnings, std::span<const double> zone_growth_um_per_c) {
  ToolErrorModel m = FitStructures(tool, rows, t_std, zone_growth_um_per_c, warnings);
  ChooseBest(m, rows, zone_growth_um_per_c, warnings);
  // The growth is linear in the bodies' temperatures, which the zone means sample: with zone
  // means the zones model is the structure (cross-validation over the one or two mountings a
  // tool has in a day proved unreliable, docs/tool-thermal.md).
  if (!m.zone_um_per_c.empty()) m.best = ToolModelKind::kZones;
  return m;
}

std::optional<std::pair<double, double>> ToolErrorModel::TrainingTvRangeC() const {
  if (std::isfinite(training_tv_from_c) && std::isfinite(training_tv_to_c))
    return std::pair{training_tv_from_c, training_tv_to_c};
  constexpr double kUnset = 1e8;  // IntervalTerm's defaults (±1e9) mean "no range given"
  std::optional<std::pair<double, double>> range;
  for (std::size_t k = 0; k < interval.size(); ++k) {
    const IntervalTerm& it = interval[k];
    if (!interval_fitted[k] || !(std::abs(it.tv_from_c) < kUnset && std::abs(it.tv_to_c) < kUnset)) continue;
    range = range ? std::pair{std::min(range->first, it.tv_from_c), std::max(range->second, it.tv_to_c)}
                  : std::pair{it.tv_from_c, it.tv_to_c};
  }
  return range;
}

nlohmann::json ToolErrorModel::ZonesJson() const {
  nlohmann::json z = {{"intercept_um", zone_intercept_um}, {"um_per_c", zone_um_per_c}};
  if (!zone_beyond_um_per_c.empty()) {
    z["training_range_c"] = nlohmann::json::array();
    for (const auto& [lo, hi] : zone_training_range_c) z["training_range_c"].push_back({lo, hi});
    z["beyond_um_per_c"] = zone_beyond_um_per_c;
  }
  return z;
}

nlohmann::json ToolErrorModel::ToJson() const {
  auto term = [](const LinearTerm& l) { return nlohmann::json{{"intercept_um", l.intercept_um}, {"per_c_um", l.per_c_um}}; };
  nlohmann::json iv = nlohmann::json::array();
  for (int k = 0; k < 3; ++k) {
    auto j = term(interval[k].line);
    j["per_c_since_start_um"] = interval[k].per_c_since_start_um;
    j["tv_range_c"] = {interval[k].tv_from_c, interval[k].tv_to_c};
    j["rise_range_c"] = {interval[k].rise_from_c, interval[k].rise_to_c};
    j["interval"] = thermal::ThermalIntervalName(static_cast<ThermalInterval>(k));
    j["fitted"] = interval_fitted[k];
    j["training_rows"] = interval_rows[k];
    j["weight"] = interval[k].weight;
    j["held_out"] = {{"rows", interval[k].cv_rows}, {"rms_um", interval[k].cv_rms_um}, {"one_rms_um", interval[k].cv_one_rms_um}};
    iv.push_back(j);
  }
  nlohmann::json out = {{"tool", tool},
          {"standard_temp_c", standard_temp_c},
          {"one", term(one)},
          {"intervals", iv},
          {"classifier",
           {{"window_s", classifier.window_s}, {"dead_band_c_per_h", classifier.dead_band_c_per_h}, {"dwell_s", classifier.dwell_s}}},
          {"lag", {{"tau_s", lag_tau_s}, {"intercept_um", lag.intercept_um}, {"per_c_um", lag.per_c_um}}},
          {"two_body",
           {{"tau_s", two_body_tau_s},
            {"intercept_um", two_body_intercept_um},
            {"tv_um_per_c", two_body_tv_um_per_c},
            {"lag_um_per_c", two_body_lag_um_per_c}}},
          {"best", ToolModelKindName(best)},
          {"best_without_zones", ToolModelKindName(best_without_zones)},
          {"cv_rms_um",
           {{"one", cv_rms_um[1]}, {"intervals", cv_rms_um[2]}, {"lag", cv_rms_um[3]}, {"two_body", cv_rms_um[4]},
            {"zones", cv_rms_um[5]}}},
          {"zones", ZonesJson()},
          {"training", {{"rows", training_rows}, {"sample_s", training.sample_s}, {"noise_c", training.noise_c}}}};
  if (std::isfinite(training_tv_from_c) && std::isfinite(training_tv_to_c))
    out["training"]["tv_range_c"] = {training_tv_from_c, training_tv_to_c};
  if (!fallback_from_tools.empty()) out["fallback_from_tools"] = fallback_from_tools;
  return out;
}

ToolErrorModel ToolErrorModel::FromJson(const nlohmann::json& j, const std::string& source) {
  ToolErrorModel m;
  std::string at;
  auto num = [&](const nlohmann::json& o, const char* key) {
    if (!o.is_object() || !o.contains(key) || !o.at(key).is_number())
      throw InputError(source, 0, at + key, "missing or not a number");
    return o.at(key).get<double>();
  };
  auto obj = [&](const nlohmann::json& o, const char* key) -> const nlohmann::json& {
    if (!o.is_object() || !o.contains(key) || !o.at(key).is_object()) throw InputError(source, 0, at + key, "missing object");
    return o.at(key);
  };
  m.tool = static_cast<int>(num(j, "tool"));
  m.standard_temp_c = num(j, "standard_temp_c");
  at = "one.";
  m.one = {num(obj(j, "one"), "intercept_um"), num(obj(j, "one"), "per_c_um")};
  at = "";
  if (!j.contains("intervals") || !j.at("intervals").is_array() || j.at("intervals").size() != 3)
    throw InputError(source, 0, "intervals", "must be an array of 3 (heating, steady, cooling)");
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& o = j.at("intervals")[k];
    at = fmt::format("intervals[{}].", k);
    IntervalTerm& it = m.interval[k];
    it.line = {num(o, "intercept_um"), num(o, "per_c_um")};
    it.per_c_since_start_um = o.value("per_c_since_start_um", 0.0);  // absent in version-1 files: Tv only
    auto range = [&](const char* key, double* from, double* to) {
      if (!o.contains(key)) return;
      const auto& a = o.at(key);
      if (!a.is_array() || a.size() != 2 || !a[0].is_number() || !a[1].is_number() || a[0].get<double>() > a[1].get<double>())
        throw InputError(source, 0, at + key, "must be [from, to] with from <= to");
      *from = a[0].get<double>();
      *to = a[1].get<double>();
    };
    range("tv_range_c", &it.tv_from_c, &it.tv_to_c);
    it.weight = o.value("weight", 1.0);  // absent in files written before the held-out blend
    if (!(it.weight >= 0 && it.weight <= 1)) throw InputError(source, 0, at + "weight", "must be in [0, 1]");
    range("rise_range_c", &it.rise_from_c, &it.rise_to_c);
    m.interval_fitted[k] = o.value("fitted", false);
    m.interval_rows[k] = o.value("training_rows", 0);
  }
  at = "classifier.";
  const auto& c = obj(j, "classifier");
  m.classifier = {num(c, "window_s"), num(c, "dead_band_c_per_h"), num(c, "dwell_s")};
  std::string why;
  if (!m.classifier.IsValid(&why)) throw InputError(source, 0, "classifier", why);
  at = "lag.";
  const auto& l = obj(j, "lag");
  m.lag_tau_s = num(l, "tau_s");
  m.lag = {num(l, "intercept_um"), num(l, "per_c_um")};
  at = "two_body.";
  const auto& tb = obj(j, "two_body");
  m.two_body_tau_s = num(tb, "tau_s");
  m.two_body_intercept_um = num(tb, "intercept_um");
  m.two_body_tv_um_per_c = num(tb, "tv_um_per_c");
  m.two_body_lag_um_per_c = num(tb, "lag_um_per_c");
  if (!(m.lag_tau_s > 0 && m.two_body_tau_s > 0)) throw InputError(source, 0, "tau_s", "must be > 0");
  if (j.contains("zones")) {
    at = "zones.";
    const auto& z = obj(j, "zones");
    m.zone_intercept_um = num(z, "intercept_um");
    if (!z.contains("um_per_c") || !z.at("um_per_c").is_array()) throw InputError(source, 0, "zones.um_per_c", "missing array");
    for (const auto& v : z.at("um_per_c")) {
      if (!v.is_number()) throw InputError(source, 0, "zones.um_per_c", "must hold numbers");
      m.zone_um_per_c.push_back(v.get<double>());
    }
    // Absent in files written before the free-growth continuation: the fit extrapolates.
    if (z.contains("training_range_c") || z.contains("beyond_um_per_c")) {
      const auto& ranges = z.value("training_range_c", nlohmann::json());
      const auto& beyond = z.value("beyond_um_per_c", nlohmann::json());
      if (!ranges.is_array() || ranges.size() != m.zone_um_per_c.size())
        throw InputError(source, 0, "zones.training_range_c", "must hold one [from, to] per zone coefficient");
      if (!beyond.is_array() || beyond.size() != m.zone_um_per_c.size())
        throw InputError(source, 0, "zones.beyond_um_per_c", "must hold one number per zone coefficient");
      for (std::size_t r = 0; r < ranges.size(); ++r) {
        const auto& a = ranges[r];
        if (!a.is_array() || a.size() != 2 || !a[0].is_number() || !a[1].is_number() || !(a[0].get<double>() <= a[1].get<double>()))
          throw InputError(source, 0, fmt::format("zones.training_range_c[{}]", r), "must be [from, to] with from <= to");
        if (!beyond[r].is_number()) throw InputError(source, 0, fmt::format("zones.beyond_um_per_c[{}]", r), "must be a number");
        m.zone_training_range_c.emplace_back(a[0].get<double>(), a[1].get<double>());
        m.zone_beyond_um_per_c.push_back(beyond[r].get<double>());
      }
    }
  }
  auto kind_of = [&](const char* key) {
    if (!j.at(key).is_string()) throw InputError(source, 0, key, "must be a model name");
    ToolModelKind k;
    try {
      k = ParseToolModelKind(j.at(key).get<std::string>());
    } catch (const std::invalid_argument& e) {
      throw InputError(source, 0, key, e.what());
    }
    if (k == ToolModelKind::kBest || k == ToolModelKind::kNone) throw InputError(source, 0, key, "must name a fitted model");
    return k;
  };
  if (j.contains("best")) m.best = kind_of("best");
  if (j.contains("best_without_zones")) m.best_without_zones = kind_of("best_without_zones");
  if (m.best == ToolModelKind::kZones && m.zone_um_per_c.empty()) throw InputError(source, 0, "best", "zones without zone coefficients");
  if (j.contains("fallback_from_tools")) {
    const auto& f = j.at("fallback_from_tools");
    if (!f.is_array() || f.empty()) throw InputError(source, 0, "fallback_from_tools", "must be a non-empty array of tool numbers");
    for (const auto& v : f) {
      if (!v.is_number_integer() || v.get<int>() < 1)
        throw InputError(source, 0, "fallback_from_tools", "must hold tool numbers (integers >= 1)");
      m.fallback_from_tools.push_back(v.get<int>());
    }
  }
  if (j.contains("training") && j.at("training").is_object()) {
    m.training_rows = j.at("training").value("rows", 0);
    m.training.sample_s = j.at("training").value("sample_s", 0.0);
    m.training.noise_c = j.at("training").value("noise_c", 0.0);
    if (j.at("training").contains("tv_range_c")) {
      const auto& r = j.at("training").at("tv_range_c");
      if (!r.is_array() || r.size() != 2 || !r[0].is_number() || !r[1].is_number() ||
          !(r[0].get<double>() <= r[1].get<double>()) || !PlausibleToolTemperatureC(r[0].get<double>()) ||
          !PlausibleToolTemperatureC(r[1].get<double>()))
        throw InputError(source, 0, "training.tv_range_c", "must be [from, to] tool temperatures in °C with from <= to");
      m.training_tv_from_c = r[0].get<double>();
      m.training_tv_to_c = r[1].get<double>();
    }
  }
  return m;
}

}  // namespace trueaxis::tooltherm
