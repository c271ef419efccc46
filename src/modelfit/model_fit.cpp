#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/thermal_lag.hpp"
#include "trueaxis/modelfit/motion_heat.hpp"
#include "trueaxis/model/thermal_state.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"

namespace trueaxis::model {
namespace {

constexpr double kSameTargetTolMm = 1e-6;

std::string StateName(const FitState& s) { return s.label.empty() ? s.path : s.label; }

int FirstLine(const measure::Measurement& m) { return m.points.empty() ? 0 : m.points.front().source_line; }

double MeanOfSensor(const measure::Measurement& m, std::size_t idx) {
  double sum = 0;
  int n = 0;
  for (const auto& p : m.points)
    if (idx < p.temperatures_c.size() && std::isfinite(p.temperatures_c[idx])) sum += p.temperatures_c[idx], ++n;
  return n ? sum / n : kNaN;
}

double MeanOfSensor(const measure::Measurement& m, const std::string& name) {
  auto idx = m.SensorIndex(name);
  return idx ? MeanOfSensor(m, *idx) : kNaN;
}

// Cold-state means per target for one direction.
struct TargetMeans {
  std::vector<double> x, mean;
  int runs = 0;
  double noise_um = kNaN;  // standard error of a mean, from the pooled run-to-run scatter
};

TargetMeans MeansForDirection(const measure::Measurement& m, Direction d) {
  std::vector<std::pair<double, double>> pts;
  for (const auto& p : m.points)
    if (p.direction == d) pts.emplace_back(p.target_mm, p.deviation_um);
  std::sort(pts.begin(), pts.end());
  TargetMeans tm;
  std::vector<std::vector<double>> groups;
  for (const auto& [x, y] : pts) {
    if (tm.x.empty() || x - tm.x.back() > kSameTargetTolMm) {
      tm.x.push_back(x);
      groups.emplace_back();
    }
    groups.back().push_back(y);
  }
  double ss = 0, dof = 0, runs_sum = 0;
  for (const auto& g : groups) {
    double mu = 0;
    for (double v : g) mu += v;
    mu /= static_cast<double>(g.size());
    tm.mean.push_back(mu);
    for (double v : g) ss += (v - mu) * (v - mu);
    dof += static_cast<double>(g.size()) - 1;
    runs_sum += static_cast<double>(g.size());
  }
  if (!groups.empty()) tm.runs = static_cast<int>(std::lround(runs_sum / static_cast<double>(groups.size())));
  if (dof > 0 && tm.runs >= 2) tm.noise_um = std::sqrt(ss / dof) / std::sqrt(runs_sum / static_cast<double>(groups.size()));
  return tm;
}

// One point of a non-cold state, ready for the thermal regression.
struct ThermalPoint {
  std::size_t state = 0;  // index into the axis' thermal states
  int dir = 0;
  double x = 0;
  double lever_mm = 0;   // Px − x (filled once Px is known)
  double r = 0;          // measured − Er(x)
  std::vector<double> rise;  // per candidate sensor, °C (NaN if unread)
  double amb_rise = kNaN;
};

struct GainFit {
  bool ok = false;
  std::vector<double> k;
  double rho = 0;
  std::vector<double> ko;  // each key's own pivot (GainForm::key_offsets): µm per °C of its rise
  double ambient_offset = 0;  // the same for the room's change, µm per °C
};

// How the gains are solved: the ridge on the keys after the first (FitOptions::secondary_key_ridge)
// and whether each key (and the room) also shifts the error over the whole travel (key_offsets).
struct GainForm {
  double secondary_ridge = 0;
  bool key_offsets = false;
  // The room's shift is fitted only when the rows' room temperature varied by this much (°C): a
  // fold without the other-ambient states cannot determine it (FitOptions::min_ambient_range_c).
  double min_room_range_c = 1.0;
  // A coolant's own gains keep the off-coolant gains' response to a soak (every key and the room
  // risen alike): Σk + ρ and Σko + o_a held at these values (NaN: free). The coolant's few states
  // of one season cannot determine that direction; the machine soaked with the coolant at the
  // room's temperature expands as it does dry.
  double soak_slope = std::numeric_limits<double>::quiet_NaN();
  double soak_shift = std::numeric_limits<double>::quiet_NaN();
};

// Least squares r = Σ k_j·rise_j·L (+ ρ·amb·L) (+ Σ o_j·rise_j + o_a·amb with form.key_offsets) over
// the selected points of one direction, the terms of keys after the first shrunk by
// form.secondary_ridge (FitOptions::secondary_key_ridge).
template <typename Pred>
GainFit SolveGains(const std::vector<ThermalPoint>& pts, Pred use, const std::vector<std::size_t>& keys, bool fit_rho,
                   double fixed_rho, const GainForm& form) {
  std::vector<const ThermalPoint*> rows;
  for (const auto& p : pts) {
    if (!use(p)) continue;
    bool finite = true;
    for (auto k : keys) finite = finite && std::isfinite(p.rise[k]);
    if (fit_rho) finite = finite && std::isfinite(p.amb_rise);
    if (finite) rows.push_back(&p);
  }
  bool room_everywhere = true;
  double room_lo = std::numeric_limits<double>::infinity(), room_hi = -room_lo;
  for (const auto* r : rows) {
    room_everywhere = room_everywhere && std::isfinite(r->amb_rise);
    room_lo = std::min(room_lo, r->amb_rise), room_hi = std::max(room_hi, r->amb_rise);
  }
  room_everywhere = room_everywhere && !rows.empty() && room_hi - room_lo >= form.min_room_range_c;
  // Columns: the keys' slopes, ρ (when fitted), then with key offsets each key's and the room's shift.
  const Eigen::Index slope_cols = static_cast<Eigen::Index>(keys.size()) + (fit_rho ? 1 : 0);
  const Eigen::Index offset_cols =
      form.key_offsets && !keys.empty() ? static_cast<Eigen::Index>(keys.size()) + (room_everywhere ? 1 : 0) : 0;
  const Eigen::Index cols = slope_cols + offset_cols;
  GainFit g;
  g.rho = fixed_rho;
  if (cols == 0) {
    g.ok = true;
    return g;
  }
  if (static_cast<Eigen::Index>(rows.size()) < cols) return g;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(rows.size()), cols);
  Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    const ThermalPoint& p = *rows[static_cast<std::size_t>(i)];
    for (std::size_t j = 0; j < keys.size(); ++j) a(i, static_cast<Eigen::Index>(j)) = p.rise[keys[j]] * p.lever_mm;
    double y = p.r;
    if (fit_rho) a(i, slope_cols - 1) = p.amb_rise * p.lever_mm;
    else if (std::isfinite(p.amb_rise)) y -= fixed_rho * p.amb_rise * p.lever_mm;
    if (offset_cols > 0) {
      for (std::size_t j = 0; j < keys.size(); ++j) a(i, slope_cols + static_cast<Eigen::Index>(j)) = p.rise[keys[j]];
      if (room_everywhere) a(i, cols - 1) = p.amb_rise;
    }
    b(i) = y;
  }
  // Scale columns to unit norm so the pivoting QR's rank decision is not fooled by units.
  Eigen::VectorXd scale = a.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < cols; ++j)
    if (scale(j) > 0) a.col(j) /= scale(j);
    else scale(j) = 1;
  // The ridge as extra rows √λ·c_j = 0 for the slope (and offset) of every key after the first, in
  // the unit-norm system: λ is relative to a column's norm².
  const Eigen::Index shrunk = form.secondary_ridge > 0 ? static_cast<Eigen::Index>(keys.size()) - 1 : 0;
  if (shrunk > 0) {
    const Eigen::Index extra = offset_cols > 0 ? 2 * shrunk : shrunk;
    const Eigen::Index first_extra = a.rows();
    a.conservativeResize(a.rows() + extra, Eigen::NoChange);
    b.conservativeResize(b.rows() + extra);
    a.bottomRows(extra).setZero();
    b.tail(extra).setZero();
    const double w = std::sqrt(form.secondary_ridge);
    for (Eigen::Index j = 0; j < shrunk; ++j) {
      a(first_extra + j, 1 + j) = w;
      if (offset_cols > 0) a(first_extra + shrunk + j, slope_cols + 1 + j) = w;
    }
  }
  // The soak constraints as heavily weighted rows in the unit-norm system (coefficients 1/scale).
  auto constrain = [&](Eigen::Index first, Eigen::Index count, double target) {
    if (!std::isfinite(target) || count <= 0) return;
    Eigen::VectorXd row = Eigen::VectorXd::Zero(cols);
    for (Eigen::Index j = first; j < first + count; ++j) row(j) = 1.0 / scale(j);
    const double w = 1e6 / row.norm();
    a.conservativeResize(a.rows() + 1, Eigen::NoChange);
    b.conservativeResize(b.rows() + 1);
    a.row(a.rows() - 1) = w * row.transpose();
    b(b.rows() - 1) = w * target;
  };
  constrain(0, slope_cols, form.soak_slope - (fit_rho ? 0.0 : fixed_rho));
  if (offset_cols > 0) constrain(slope_cols, offset_cols, form.soak_shift);
  Eigen::VectorXd c = a.colPivHouseholderQr().solve(b);
  c = c.cwiseQuotient(scale);
  g.k.assign(c.data(), c.data() + keys.size());
  if (fit_rho) g.rho = c(slope_cols - 1);
  if (offset_cols > 0) {
    g.ko.assign(c.data() + slope_cols, c.data() + slope_cols + keys.size());
    if (room_everywhere) g.ambient_offset = c(cols - 1);
  }
  g.ok = c.allFinite();
  return g;
}

double PredictThermal(const ThermalPoint& p, const std::vector<std::size_t>& keys, const GainFit& g) {
  double tan_beta = 0;
  for (std::size_t j = 0; j < keys.size(); ++j) tan_beta += g.k[j] * p.rise[keys[j]];
  double out = tan_beta * p.lever_mm;
  if (std::isfinite(p.amb_rise)) out += (g.rho * p.lever_mm + g.ambient_offset) * p.amb_rise;
  for (std::size_t j = 0; j < g.ko.size(); ++j) out += g.ko[j] * p.rise[keys[j]];
  return out;
}

bool RowUsable(const ThermalPoint& p, const std::vector<std::size_t>& keys, bool fit_rho) {
  for (auto k : keys)
    if (!std::isfinite(p.rise[k])) return false;
  return !fit_rho || std::isfinite(p.amb_rise);
}

// Leave-one-state-out CV RMS over both directions, on the states in `states`.
// `scored` (optional): only those states are held out and scored, the fits still use every other
// state of `states`.
double CrossValidate(const std::vector<ThermalPoint>& pts, const std::set<std::size_t>& states,
                     const std::vector<std::size_t>& keys, bool fit_rho, double fixed_rho, const GainForm& form,
                     const std::set<std::size_t>* scored = nullptr) {
  double ss = 0;
  std::size_t n = 0;
  for (int dir = 0; dir < 2; ++dir) {
    for (std::size_t s : states) {
      if (scored && !scored->count(s)) continue;
      auto g = SolveGains(
          pts, [&](const ThermalPoint& p) { return p.dir == dir && p.state != s && states.count(p.state); }, keys,
          fit_rho, fixed_rho, form);
      if (!g.ok) return std::numeric_limits<double>::infinity();
      for (const auto& p : pts) {
        if (p.dir != dir || p.state != s || !RowUsable(p, keys, fit_rho)) continue;
        ss += std::pow(p.r - PredictThermal(p, keys, g), 2);
        ++n;
      }
    }
  }
  return n ? std::sqrt(ss / static_cast<double>(n)) : kNaN;
}

// ρ fitted jointly with the gains of `keys` on the off-coolant states: one ρ per axis (one screw),
// the mean of the two directions' estimates.
double JointRho(const std::vector<ThermalPoint>& pts, const std::set<std::size_t>& off_states,
                const std::vector<std::size_t>& keys, const GainForm& form) {
  double rs = 0;
  int rn = 0;
  for (int dir = 0; dir < 2; ++dir) {
    auto g = SolveGains(pts, [&](const ThermalPoint& p) { return p.dir == dir && off_states.count(p.state); }, keys,
                        true, 0, form);
    if (g.ok) rs += g.rho, ++rn;
  }
  return rn ? rs / rn : 0.0;
}

double Correlation(const std::vector<ThermalPoint>& pts, const std::set<std::size_t>& states, std::size_t a,
                   std::size_t b) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  double n = 0;
  for (const auto& p : pts) {
    if (!states.count(p.state) || !std::isfinite(p.rise[a]) || !std::isfinite(p.rise[b])) continue;
    sa += p.rise[a], sb += p.rise[b], saa += p.rise[a] * p.rise[a], sbb += p.rise[b] * p.rise[b];
    sab += p.rise[a] * p.rise[b];
    n += 1;
  }
  if (n < 2) return 0;
  const double va = saa - sa * sa / n, vb = sbb - sb * sb / n, cab = sab - sa * sb / n;
  if (va <= 0 || vb <= 0) return 1;  // a constant rise cannot be told apart from anything
  return cab / std::sqrt(va * vb);
}

std::string JoinNames(const std::vector<std::string>& v) { return v.empty() ? "none" : fmt::format("{}", fmt::join(v, ", ")); }

// What PrepareThermal's stages decide, one after the other, for one axis: each stage reads what the
// stages before it chose and adds its own choice (the order of the members is the order of the stages).
struct ThermalWork {
  std::string amb;                 // the ambient sensor ("" for none)
  std::optional<double> cte;       // µm/m/°C of the axis's feedback: option, else the cold file's metadata
  std::string cte_source;          // where the CTE came from, for the notes
  double px = kNaN;                // the reference point Px (mm) and why
  std::string px_source;
  std::vector<std::string> candidates;  // key-sensor candidates (columns of ThermalPoint::rise)
  std::vector<double> base;             // each candidate's cold-state mean (°C)
  double amb_base = kNaN;               // the ambient sensor's cold-state mean (°C)
  // Each candidate's rise lagged by its own τ, `fall_factor` times longer while it falls (dry);
  // the motion-heat input's τ (0: none yet) and its place in each point's rises, after the
  // candidates: a key like the sensors, with M (m/min) as its rise.
  double fall_factor = 1;
  double motion_tau = 0;
  std::size_t motion_col = 0;
  std::vector<ThermalPoint> pts;        // the thermal points as the stages so far build them
  std::set<std::size_t> off_states;     // the states the gains are fitted on (the dry ones; all with coolant memory)
  double amb_lo = 0, amb_hi = 0;        // the room's rise over the dry states (the cold state is the 0 rise)
  bool fit_rho = false;                 // ρ fitted jointly with the gains
  std::optional<double> physical_rho;   // −cte/1000, replacing the fitted ρ for the final gains
  double rho = 0;
  std::string rho_source;
  bool thermal = false;                 // a thermal part is (still) being fitted
  std::vector<std::size_t> keys;        // the chosen keys: candidate columns (+ motion_col last)
  std::vector<double> key_lag_s;        // each column's lag τ (s)
  std::vector<double> plain_lag_s;      // the lag chosen before the fall factor (empty: none chosen)
  std::array<double, kCoolantStateCount> key_loss{};  // the coolant memory's loss τ per coolant state
};

class AxisFitter {
 public:
  AxisFitter(std::string axis, std::vector<const FitState*> states, const FitOptions& o, std::vector<std::string>& warnings)
      : axis_name_(std::move(axis)), all_(std::move(states)), o_(o), warnings_(warnings) {
    form_.secondary_ridge = o.secondary_key_ridge;
    form_.min_room_range_c = o.min_ambient_range_c;
    form_.key_offsets = o.key_offsets == FitOptions::KeyOffsets::kOn;
  }

  AxisModel Fit(AxisFitSummary& sum) {
    sum.axis = axis_name_;
    model_.axis = axis_name_;
    PickCold(sum);
    for (const auto* s : all_)
      if (auto why = measure::DeviationUnitWarning(s->measurement)) Warn(fmt::format("{}: {}", s->path, *why));
    FitGeometric(sum);
    PrepareThermal(sum);
    ComputeStateStats(sum);
    return model_;
  }

 private:
  void Warn(std::string w) { warnings_.push_back(fmt::format("axis {}: {}", axis_name_, std::move(w))); }

  void PickCold(AxisFitSummary& sum) {
    std::vector<const FitState*> colds;
    for (auto* s : all_)
      if (s->kind == StateKind::kCold) colds.push_back(s);
    if (colds.empty()) {
      // Infer: the state with the lowest mean temperature over the sensors all states share.
      std::set<std::string> common;
      bool first = true;
      for (auto* s : all_) {
        std::set<std::string> names(s->measurement.sensor_names.begin(), s->measurement.sensor_names.end());
        if (first) common = names, first = false;
        else {
          std::set<std::string> keep;
          for (const auto& n : common)
            if (names.count(n)) keep.insert(n);
          common = keep;
        }
      }
      if (all_.size() == 1) {
        colds.push_back(all_.front());
        Warn(all_.front()->label.empty()
                 ? fmt::format("'{}' has no '# state:' line; as the only file it is taken as the cold state",
                               all_.front()->path)
                 : fmt::format("'{}' is the only file (state '{}'), so it is taken as the cold state: its error is "
                               "the geometric part and no thermal part can be fitted", all_.front()->path,
                               all_.front()->label));
      } else if (common.empty()) {
        throw InputError(all_.front()->path, 0, "state",
                         "no file is marked '# state: cold' and the files share no temperature sensor to tell which "
                         "one is cold; add '# state: cold' to the cold-state file (or \"state\" in the manifest)");
      } else {
        const FitState* best = nullptr;
        double best_t = std::numeric_limits<double>::infinity();
        for (auto* s : all_) {
          double t = 0;
          for (const auto& n : common) t += MeanOfSensor(s->measurement, n);
          t /= static_cast<double>(common.size());
          if (std::isfinite(t) && t < best_t) best_t = t, best = s;
        }
        if (!best)
          throw InputError(all_.front()->path, 0, "state", "no file is marked cold and no temperatures could be read");
        colds.push_back(best);
        Warn(fmt::format("no file is marked '# state: cold'; took '{}' (lowest mean temperature {:.2f} °C over {})",
                         best->path, best_t, fmt::join(common, ", ")));
      }
    }
    cold_states_ = colds;
    for (auto* s : all_)
      if (std::find(colds.begin(), colds.end(), s) == colds.end()) thermal_.push_back(s);
    // One combined cold measurement: runs of later files renumbered after the earlier ones.
    cold_ = colds.front()->measurement;
    int run_offset = 0;
    for (const auto& p : cold_.points) run_offset = std::max(run_offset, p.run);
    for (std::size_t i = 1; i < colds.size(); ++i) {
      const auto& m = colds[i]->measurement;
      if (m.sensor_names != cold_.sensor_names)
        throw InputError(m.source, 0, "t_<sensor>_c",
                         fmt::format("cold-state files must have the same temperature columns as '{}'", cold_.source));
      int max_run = 0;
      for (auto p : m.points) {
        max_run = std::max(max_run, p.run);
        p.run += run_offset;
        cold_.points.push_back(p);
      }
      run_offset += max_run;
    }
    std::vector<std::string> names;
    for (auto* c : colds) names.push_back(c->path);
    sum.cold_source = fmt::format("{}", fmt::join(names, " + "));
  }

  void FitGeometric(AxisFitSummary& sum) {
    const auto& m = cold_;
    if (m.points.empty()) throw InputError(m.source, "the cold state has no measurement points (empty file?)");
    const auto targets = m.Targets();
    if (targets.size() < 2)
      throw InputError(m.source, FirstLine(m), "target_mm",
                       fmt::format("all {} points are at the same target {} mm: the geometric error Er(x) needs at "
                                   "least 2 distinct targets (degenerate positions)",
                                   m.points.size(), FormatShortest(targets.front())));
    for (Direction d : {Direction::kForward, Direction::kReverse}) {
      const int di = static_cast<int>(DirectionIndex(d));
      TargetMeans tm = MeansForDirection(m, d);
      if (tm.x.empty())
        throw InputError(m.source, FirstLine(m), "direction",
                         fmt::format("the cold state has no points approached in the '{}' direction; forward and "
                                     "reverse are modelled apart, so both are needed",
                                     DirectionSymbol(d)));
      if (tm.x.size() < 2)
        throw InputError(m.source, FirstLine(m), "target_mm",
                         fmt::format("direction '{}' has points at one target only ({} mm); Er(x) needs at least 2",
                                     DirectionSymbol(d), FormatShortest(tm.x.front())));
      auto& ds = sum.directions[di];
      ds.targets = tm.x.size();
      ds.runs = tm.runs;
      ds.table_cv_rms_um = TableCrossValidationRms(tm.x, tm.mean);
      GeometricError& g = model_.directions[di].geometric;
      g.center_mm = 0.5 * (tm.x.front() + tm.x.back());
      g.half_span_mm = 0.5 * (tm.x.back() - tm.x.front());
      bool table = o_.geometric == FitOptions::Geometric::kTable;
      if (!table) {
        g.kind = GeometricError::Kind::kPolynomial;
        ds.degree = SelectPolynomialDegree(tm.x, tm.mean, g.center_mm, g.half_span_mm, o_.max_degree, tm.noise_um);
        std::vector<double> u;
        for (double x : tm.x) u.push_back((x - g.center_mm) / g.half_span_mm);
        g.coefficients_um = FitPolynomial(u, tm.mean, ds.degree.degree);
        for (const auto& c : ds.degree.candidates)
          if (c.degree == ds.degree.degree) ds.geometric_fit_rms_um = c.fit_rms_um, ds.geometric_cv_rms_um = c.cv_rms_um;
        ds.kind = g.kind;
        ds.choice = "polynomial (asked for)";
        // Per run, per target (NaN: not measured): for the leave-one-run-out comparison.
        std::map<int, std::vector<double>> by_run;
        for (const auto& p : m.points) {
          if (p.direction != d) continue;
          auto& row = by_run.try_emplace(p.run, std::vector<double>(tm.x.size(), kNaN)).first->second;
          const auto it = std::lower_bound(tm.x.begin(), tm.x.end(), p.target_mm - kSameTargetTolMm);
          if (it != tm.x.end() && std::abs(*it - p.target_mm) <= kSameTargetTolMm)
            row[static_cast<std::size_t>(it - tm.x.begin())] = p.deviation_um;
        }
        std::vector<std::vector<double>> runs;
        for (auto& [r, row] : by_run) runs.push_back(std::move(row));
        ds.table_loro_rms_um = LeaveOneRunOutRms(tm.x, runs, -1, g.center_mm, g.half_span_mm);
        ds.polynomial_loro_rms_um = LeaveOneRunOutRms(tm.x, runs, ds.degree.degree, g.center_mm, g.half_span_mm);
        if (o_.geometric == FitOptions::Geometric::kAuto && std::isfinite(ds.table_loro_rms_um) &&
            std::isfinite(ds.polynomial_loro_rms_um)) {
          // Judged by held-out RUNS: a repeatable short-wavelength error is in the held-out run too
          // and the table keeps it; noise is not, and the table pays for fitting it. The table must
          // win by auto_table_run_margin to replace the smoother model.
          table = ds.table_loro_rms_um < (1 - o_.auto_table_run_margin) * ds.polynomial_loro_rms_um;
          ds.choice = fmt::format("auto → {}: leave-one-run-out CV over {} runs: table {:.3f} µm vs polynomial "
                                  "(degree {}) {:.3f} µm",
                                  table ? "table" : "polynomial", runs.size(), ds.table_loro_rms_um,
                                  ds.degree.degree, ds.polynomial_loro_rms_um);
        } else if (o_.geometric == FitOptions::Geometric::kAuto) {
          const bool systematic =
              std::isfinite(tm.noise_um) && ds.geometric_fit_rms_um > o_.auto_systematic_factor * tm.noise_um;
          const bool table_ok = std::isfinite(ds.table_cv_rms_um) && std::isfinite(ds.geometric_cv_rms_um) &&
                                ds.table_cv_rms_um <= o_.auto_table_cv_ratio * ds.geometric_cv_rms_um;
          table = systematic && table_ok;
          ds.choice = fmt::format(
              "auto → {}: polynomial fit RMS {:.3f} µm {} {:.0f}× the noise of the means ({}), table LOTO CV {:.3f} "
              "vs polynomial {:.3f} µm",
              table ? "table" : "polynomial", ds.geometric_fit_rms_um, systematic ? ">" : "≤",
              o_.auto_systematic_factor, std::isfinite(tm.noise_um) ? fmt::format("{:.3f} µm", tm.noise_um) : "unknown",
              ds.table_cv_rms_um, ds.geometric_cv_rms_um);
        }
      } else {
        ds.choice = "table (asked for)";
      }
      if (table) {
        g.kind = GeometricError::Kind::kTable;
        g.coefficients_um.clear();
        g.table_position_mm = tm.x;
        g.table_error_um = tm.mean;
        ds.kind = g.kind;
        ds.geometric_fit_rms_um = 0;
        ds.geometric_cv_rms_um = ds.table_cv_rms_um;
      }
      if (tm.runs < 2) Warn(fmt::format("direction '{}': one cold run only, so the run-to-run scatter is unknown",
                                        DirectionSymbol(d)));
    }
  }

  std::string AmbientSensorName() {
    if (LowerAscii(o_.ambient_sensor) == "none") return "";
    auto in_all = [&](const std::string& n) {
      for (auto* s : all_)
        if (!s->measurement.SensorIndex(n)) return false;
      return true;
    };
    if (!o_.ambient_sensor.empty()) {
      for (auto* s : all_)
        if (!s->measurement.SensorIndex(o_.ambient_sensor))
          throw InputError(s->path, 0, fmt::format("t_{}_c", o_.ambient_sensor),
                           fmt::format("the ambient sensor '{}' is missing in this file", o_.ambient_sensor));
      return o_.ambient_sensor;
    }
    for (const auto& n : cold_.sensor_names) {
      const std::string l = LowerAscii(n);
      if ((l == "ambient" || l == "air" || l == "env" || l == "environment" || l == "room") && in_all(n)) return n;
    }
    return "";
  }

  // A number of the cold file's metadata (`# key: value`), refused with its file line when it is not
  // a number or not plausible (core/plausibility.hpp); nullopt when the file has no such line.
  std::optional<double> ColdMetaNumber(const char* key, std::optional<std::string> (*implausible)(double)) const {
    const auto meta = cold_.Meta(key);
    if (!meta) return std::nullopt;
    const auto v = ParseDouble(*meta);
    if (!v || !std::isfinite(*v))
      throw InputError(cold_.source, cold_.MetaLine(key), key, fmt::format("'{}' is not a number", *meta));
    if (auto why = implausible(*v)) throw InputError(cold_.source, cold_.MetaLine(key), key, *why);
    return v;
  }

  // The CTE's soak against what the calibration's room changes say: a CTE that does not match the
  // files (the laser's material compensation on, which takes most of the soak out of them; a scale's
  // CTE given for a screw) is a wrong ρ in every other season, so a large disagreement is warned
  // about. The room's changes within a season never soak the machine fully, so some difference is
  // normal (about 20 % on the virtual machines).
  void CheckCteAgainstRoom(double fitted_rho, double cte_rho, const std::string& cte_source, double room_range_c,
                           AxisFitSummary& sum) {
    sum.rho_fitted_for_check = fitted_rho;
    const double diff = std::fabs(fitted_rho - cte_rho);
    if (diff <= 0.5 * std::fabs(cte_rho) || diff < 0.003) return;
    Warn(fmt::format("the room's changes over the calibration ({:.1f} °C) fit ρ = {:.4f} µm/mm/°C, the CTE ({}) gives "
                     "{:.4f}: check the CTE (with the laser's material compensation on, give the feedback's CTE minus "
                     "the material's), or fit --rho-fit to use the fitted ρ",
                     room_range_c, fitted_rho, cte_source, cte_rho));
  }

  // The thermal part of the axis (docs/model-file.md "How the fit works"), stage by stage; each
  // stage is one decision, made on what the stages before it chose (ThermalWork).
  void PrepareThermal(AxisFitSummary& sum) {
    ThermalWork w;
    w.amb = AmbientSensorName();
    ResolveCte(w);
    ReferenceFromOptionOrFile(w);
    CheckThermalStatesHaveTemperatures();
    ChooseCandidateSensors(w, sum);
    SetColdBaselines(w);
    w.motion_col = w.candidates.size();
    motion_col_ = w.motion_col;
    w.pts = BuildPoints(w, {});
    if (std::isnan(w.px)) FitCommonPivot(w);
    RecordReferencePoint(w, sum);
    StageOneSlopes(w);
    ChooseRho(w, sum);
    RecordAmbientSensor(w, sum);
    w.thermal = ThermalPartPossible(w);
    ChooseKeySensors(w, sum);
    ChooseKeyLags(w, sum);
    ChooseKeyOffsets(w, sum);
    ChooseMotionHeat(w, sum);
    ChooseCoolantMemory(w, sum);
    if (w.thermal) {
      SolveFinalGains(w, sum);
    } else if (!thermal_.empty() && sum.key_selection_reason.empty()) {
      sum.key_selection_reason = "no thermal part fitted";
    }
    // No key sensor (none present everywhere, or none helped) does not stop ρ: the other-ambient
    // states still determine it on their own.
    if (w.fit_rho && !sum.thermal_fitted) {
      w.rho = JointRho(w.pts, w.off_states, {}, form_);
      ApplyPhysicalRho(w, sum);
    }
    model_.rho_um_per_mm_per_c = w.rho;
    sum.rho_um_per_mm_per_c = w.rho;
    sum.rho_source = w.rho_source;
    if (thermal_.empty()) sum.key_selection_reason = "no heated states: nothing to select from";
  }

  // The CTE of the axis's feedback: the option wins over the files' metadata (a laser file that does
  // not record it, or records the material's instead of the feedback's). The file's is checked
  // whether or not ρ comes from it: an absurd CTE is a broken file either way.
  void ResolveCte(ThermalWork& w) {
    const auto file_cte = ColdMetaNumber("cte_um_per_m_c", ImplausibleCteUmPerMC);
    w.cte = std::isnan(o_.cte_um_per_m_c) ? file_cte : std::optional(o_.cte_um_per_m_c);
    w.cte_source =
        !std::isnan(o_.cte_um_per_m_c)
            ? fmt::format("fit --cte {}", FormatShortest(o_.cte_um_per_m_c))
            : file_cte ? fmt::format("{} line {}: cte_um_per_m_c = {}", cold_.source, cold_.MetaLine("cte_um_per_m_c"),
                                     *cold_.Meta("cte_um_per_m_c"))
                       : std::string();
  }

  // Reference point from option or metadata first (needed even for a geometric-only model's ρ term);
  // NaN when neither gives it (FitCommonPivot then fits it).
  void ReferenceFromOptionOrFile(ThermalWork& w) {
    w.px = o_.reference_position_mm;
    w.px_source = "option";
    if (std::isnan(w.px)) {
      if (auto v = ColdMetaNumber("reference_position_mm", ImplausiblePositionMm)) {
        w.px = *v;
        w.px_source = "metadata of the cold file";
      }
    }
  }

  // Temperatures: every thermal state needs some, and then the cold state too (the baseline); and
  // two targets for a slope.
  void CheckThermalStatesHaveTemperatures() {
    if (thermal_.empty()) {
      Warn("no heated or ambient state was given: geometric-only model (no thermal part)");
    }
    for (auto* s : thermal_) {
      if (s->measurement.sensor_names.empty())
        throw InputError(s->path, 0, "t_<sensor>_c",
                         fmt::format("state '{}' has no temperature columns; a heated or ambient state needs the "
                                     "temperatures it was measured at",
                                     StateName(*s)));
      const auto targets = s->measurement.Targets();
      if (targets.size() < 2)
        throw InputError(s->path, FirstLine(s->measurement), "target_mm",
                         fmt::format("state '{}': all points are at the same target{}: the thermal slope tanβ needs "
                                     "at least 2 distinct targets (degenerate positions)",
                                     StateName(*s), targets.empty() ? "" : " " + FormatShortest(targets.front()) + " mm"));
    }
    if (!thermal_.empty() && cold_.sensor_names.empty())
      throw InputError(cold_.source, 0, "t_<sensor>_c",
                       "the cold state has no temperature columns, so there is no baseline for the temperature rises "
                       "of the heated states");
  }

  // Candidates: sensors read in the cold state and in every thermal state, not the ambient, not
  // excluded, not another axis's (own_axis_sensors_only); the forced keys instead when given.
  void ChooseCandidateSensors(ThermalWork& w, AxisFitSummary& sum) {
    const std::string& amb = w.amb;
    std::vector<std::string> candidates;
    const bool above_ambient = !amb.empty();
    // "x_nut" belongs to axis X; a one-letter prefix other than this axis' marks another axis' sensor.
    const std::string own_prefix = axis_name_.size() == 1 ? LowerAscii(axis_name_) + "_" : "";
    auto axis_prefixed = [](const std::string& n) {
      return n.size() > 2 && n[1] == '_' && std::isalpha(static_cast<unsigned char>(n[0]));
    };
    bool per_axis_names = false;
    for (const auto& n : cold_.sensor_names) per_axis_names = per_axis_names || (!own_prefix.empty() && LowerAscii(n).rfind(own_prefix, 0) == 0);
    std::vector<std::string> other_axis;
    for (const auto& n : cold_.sensor_names) {
      if (above_ambient && n == amb) continue;
      if (std::find(o_.excluded_sensors.begin(), o_.excluded_sensors.end(), n) != o_.excluded_sensors.end()) continue;
      if (o_.own_axis_sensors_only && per_axis_names && o_.key_sensors.empty() && axis_prefixed(n) &&
          LowerAscii(n).rfind(own_prefix, 0) != 0) {
        other_axis.push_back(n);
        continue;
      }
      std::vector<std::string> missing;
      for (auto* s : thermal_)
        if (!s->measurement.SensorIndex(n)) missing.push_back(s->path);
      if (!missing.empty()) {
        Warn(fmt::format("sensor '{}' is missing in {}: not a key-sensor candidate", n, fmt::join(missing, ", ")));
        continue;
      }
      if (!std::isfinite(MeanOfSensor(cold_, n))) {
        Warn(fmt::format("sensor '{}' has no reading in the cold state: not a key-sensor candidate", n));
        continue;
      }
      // A column that is there but never read (a broken channel) is as good as missing: its CV
      // would be computed on fewer points and look better than it is.
      std::vector<std::string> unread;
      for (auto* s : thermal_)
        if (!std::isfinite(MeanOfSensor(s->measurement, n))) unread.push_back(s->path);
      if (!unread.empty()) {
        Warn(fmt::format("sensor '{}' has no reading in {}: not a key-sensor candidate", n, fmt::join(unread, ", ")));
        continue;
      }
      candidates.push_back(n);
    }
    for (auto* s : thermal_)
      for (const auto& n : s->measurement.sensor_names)
        if (!cold_.SensorIndex(n) && !(above_ambient && n == amb))
          Warn(fmt::format("sensor '{}' of '{}' is missing in the cold state: not a key-sensor candidate", n, s->path));
    // Forced keys must be everywhere.
    for (const auto& k : o_.key_sensors) {
      for (const measure::Measurement* m : AllMeasurements())
        if (!m->SensorIndex(k))
          throw InputError(m->source, 0, fmt::format("t_{}_c", k),
                           fmt::format("key sensor '{}' (asked for in the options) is missing in this file", k));
      if (k == amb) throw InputError(cold_.source, 0, "key_sensors", fmt::format("'{}' is the ambient sensor", k));
    }
    if (!o_.key_sensors.empty()) candidates = o_.key_sensors;
    sum.candidate_sensors = candidates;
    candidates_ = candidates;
    if (!other_axis.empty())
      sum.candidate_note = fmt::format("sensors of other axes are not candidates (own_axis_sensors_only): {}",
                                       fmt::join(other_axis, ", "));
    w.candidates = std::move(candidates);
  }

  // The cold state's mean of each candidate and of the ambient sensor: the 0 of every rise.
  void SetColdBaselines(ThermalWork& w) {
    for (const auto& n : w.candidates) w.base.push_back(MeanOfSensor(cold_, n));
    w.amb_base = w.amb.empty() ? kNaN : MeanOfSensor(cold_, w.amb);
    if (!w.amb.empty() && !std::isfinite(w.amb_base))
      throw InputError(cold_.source, 0, fmt::format("t_{}_c", w.amb), "the ambient sensor has no reading in the cold state");
  }

  // The thermal points of every thermal state: each candidate's rise through the dynamics chosen so
  // far (its lag `tau_s`, w.fall_factor, the coolant loss `loss_s`), above the room when there is an
  // ambient sensor, and the motion-heat input (w.motion_tau) as the last column. Lever arms not set.
  std::vector<ThermalPoint> BuildPoints(const ThermalWork& w, const std::vector<double>& tau_s,
                                        const std::array<double, kCoolantStateCount>& loss_s = {}) const {
    const auto& candidates = w.candidates;
    const auto& base = w.base;
    std::vector<ThermalPoint> pts;
    for (std::size_t si = 0; si < thermal_.size(); ++si) {
      const auto& m = thermal_[si]->measurement;
      std::vector<std::optional<std::size_t>> idx;
      for (const auto& n : candidates) idx.push_back(m.SensorIndex(n));
      const auto amb_idx = w.amb.empty() ? std::nullopt : m.SensorIndex(w.amb);
      std::vector<std::vector<double>> lagged(candidates.size());
      for (std::size_t j = 0; j < candidates.size(); ++j)
        if (idx[j] && j < tau_s.size() && tau_s[j] > 0) {
          KeySeriesDynamics d;
          d.tau_lag_s = tau_s[j];
          d.fall_factor = w.fall_factor;
          d.tau_loss_s = loss_s;
          d.baseline_c = base[j];
          if (amb_idx) d.ambient_index = amb_idx, d.ambient_baseline_c = w.amb_base;
          d.coolant = thermal_[si]->coolant;
          lagged[j] = ObservedSensorSeries(m, *idx[j], d, &thermal_[si]->history);
        }
      const std::vector<double> motion = MotionHeatAtPoints(m, thermal_[si]->history, w.motion_tau);
      for (std::size_t pi = 0; pi < m.points.size(); ++pi) {
        const auto& p = m.points[pi];
        ThermalPoint t;
        t.state = si;
        t.dir = static_cast<int>(DirectionIndex(p.direction));
        t.x = p.target_mm;
        t.r = p.deviation_um - model_.directions[t.dir].geometric.Evaluate(p.target_mm);
        double amb_shift = 0;
        if (amb_idx) {
          t.amb_rise = p.temperatures_c[*amb_idx] - w.amb_base;
          amb_shift = std::isfinite(t.amb_rise) ? t.amb_rise : kNaN;
        }
        for (std::size_t j = 0; j < candidates.size(); ++j) {
          const double temp = !idx[j] ? kNaN : lagged[j].empty() ? p.temperatures_c[*idx[j]] : lagged[j][pi];
          t.rise.push_back(temp - base[j] - amb_shift);
        }
        t.rise.push_back(motion[pi]);  // motion_col (NaN without a motion τ)
        pts.push_back(std::move(t));
      }
    }
    return pts;
  }

  // BuildPoints with the lever arms about the chosen Px: the points a trial of the later stages scores.
  std::vector<ThermalPoint> BuildLeveredPoints(const ThermalWork& w, const std::vector<double>& tau_s,
                                               const std::array<double, kCoolantStateCount>& loss_s = {}) const {
    auto pts = BuildPoints(w, tau_s, loss_s);
    for (auto& p : pts) p.lever_mm = w.px - p.x;
    return pts;
  }

  // Px: the common pivot of the residual lines r_s(x) = a + b·x (both directions, every state);
  // the measured end nearer machine zero when the states show no slope to pivot on.
  void FitCommonPivot(ThermalWork& w) {
    const auto& pts = w.pts;
    double num = 0, den = 0;
    double max_abs_b = 0;
    for (std::size_t si = 0; si < thermal_.size(); ++si)
      for (int dir = 0; dir < 2; ++dir) {
        double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
        for (const auto& p : pts)
          if (p.state == si && p.dir == dir) sx += p.x, sy += p.r, sxx += p.x * p.x, sxy += p.x * p.r, n += 1;
        const double var = sxx - sx * sx / std::max(n, 1.0);
        if (n < 2 || var <= 0) continue;
        const double b = (sxy - sx * sy / n) / var;
        const double a = (sy - b * sx) / n;
        num += a * b;
        den += b * b;
        max_abs_b = std::max(max_abs_b, std::abs(b));
      }
    const double span = std::max(std::abs(cold_.Targets().back() - cold_.Targets().front()), 1e-9);
    // A fan needs slopes: below 0.1 µm over the whole travel there is no pivot to find.
    if (den > 0 && max_abs_b * span > 0.1) {
      w.px = -num / den;
      w.px_source = fmt::format("fitted: common pivot of {} residual lines (−Σ a·b / Σ b²)", 2 * thermal_.size());
      const auto t = cold_.Targets();
      if (w.px < t.front() - span || w.px > t.back() + span)
        Warn(fmt::format("the fitted reference point Px = {:.1f} mm lies more than one travel outside the measured "
                         "range [{}, {}] mm: the residual fans hardly pivot; consider giving --reference-mm",
                         w.px, FormatShortest(t.front()), FormatShortest(t.back())));
    } else {
      const auto t = cold_.Targets();
      w.px = std::abs(t.front()) <= std::abs(t.back()) ? t.front() : t.back();
      w.px_source = thermal_.empty() ? "default: the measured end nearer machine zero (no heated state to fit it)"
                                     : "default: the measured end nearer machine zero (the heated states show no "
                                       "slope to pivot on)";
      if (!thermal_.empty()) Warn("the heated states show no thermal slope; Px set to the measured end nearer 0");
    }
  }

  void RecordReferencePoint(ThermalWork& w, AxisFitSummary& sum) {
    model_.reference_position_mm = w.px;
    sum.reference_position_mm = w.px;
    sum.reference_source = w.px_source;
    for (auto& p : w.pts) p.lever_mm = w.px - p.x;
  }

  // Stage-1 diagnostics: each state's own slope about Px (reported, not fitted on).
  void StageOneSlopes(const ThermalWork& w) {
    stage1_.assign(thermal_.size(), {kNaN, kNaN});
    for (std::size_t si = 0; si < thermal_.size(); ++si)
      for (int dir = 0; dir < 2; ++dir) {
        double num = 0, den = 0;
        for (const auto& p : w.pts)
          if (p.state == si && p.dir == dir) num += p.r * p.lever_mm, den += p.lever_mm * p.lever_mm;
        if (den > 0) stage1_[si][dir] = num / den;
      }
  }

  // ρ, the soak of the axis's feedback with the room: the option's; else the physical −cte/1000
  // when the CTE is known (and fit_rho_with_cte not asked for); else fitted from the room's changes
  // over the dry states when they vary enough; else 0. With the CTE and a room that varied, the
  // keys, lags and pivots are still chosen with ρ fitted alongside (a subset of keys leans on it);
  // the final gains are solved with the physical ρ (SolveFinalGains).
  void ChooseRho(ThermalWork& w, AxisFitSummary& sum) {
    for (std::size_t si = 0; si < thermal_.size(); ++si)
      if (thermal_[si]->coolant == CoolantState::kOff) w.off_states.insert(si);
    for (const auto& p : w.pts)
      if (w.off_states.count(p.state) && std::isfinite(p.amb_rise))
        w.amb_lo = std::min(w.amb_lo, p.amb_rise), w.amb_hi = std::max(w.amb_hi, p.amb_rise);
    const double amb_lo = w.amb_lo, amb_hi = w.amb_hi;
    const bool rho_can_be_fitted = amb_hi - amb_lo >= o_.min_ambient_range_c && w.off_states.size() >= 2;
    if (w.amb.empty()) {
      w.rho_source = "no ambient sensor: no ambient adjustment";
    } else if (!std::isnan(o_.rho_um_per_mm_per_c)) {
      w.rho = o_.rho_um_per_mm_per_c;
      w.rho_source = "option";
    } else if (w.cte && !(o_.fit_rho_with_cte && rho_can_be_fitted)) {
      w.rho = -*w.cte / 1000.0;
      if (rho_can_be_fitted) w.fit_rho = true, w.physical_rho = w.rho;
      sum.rho_from_cte = true;
      w.rho_source = fmt::format("−cte/1000 from {} (the axis's feedback soaks with the room: the screw grows away "
                                 "from Px, in every season)",
                                 w.cte_source);
      if (auto unusual = UnusualCteUmPerMC(*w.cte))
        Warn(fmt::format("{}: cte_um_per_m_c {}; ρ = {} µm/mm/°C taken from it",
                         std::isnan(o_.cte_um_per_m_c)
                             ? fmt::format("{} line {}", cold_.source, cold_.MetaLine("cte_um_per_m_c"))
                             : std::string("fit --cte"),
                         *unusual, FormatShortest(w.rho)));
    } else if (rho_can_be_fitted) {
      w.fit_rho = true;
      w.rho_source = fmt::format("fitted (room temperature varied by {:.2f} °C over the states)", amb_hi - amb_lo);
      if (!w.cte)
        Warn(fmt::format("ρ is fitted from the room's changes over the calibration ({:.1f} °C); a room outside them, as "
                         "in another season, extrapolates that fit: give the CTE of the axis's feedback (the files' "
                         "'# cte_um_per_m_c:' or fit --cte) for the physical soak instead",
                         amb_hi - amb_lo));
    } else {
      w.rho_source = "not determined (room temperature constant within the states, no cte metadata): ρ = 0";
      Warn(fmt::format("ρ could not be determined: the room temperature varied by only {:.2f} °C and the cold file "
                       "has no '# cte_um_per_m_c:'; ρ = 0",
                       amb_hi - amb_lo));
    }
  }

  // The fitted ρ checked against the CTE's, then replaced by it (ChooseRho: physical soak).
  void ApplyPhysicalRho(ThermalWork& w, AxisFitSummary& sum) {
    if (!w.physical_rho) return;
    CheckCteAgainstRoom(w.rho, *w.physical_rho, w.cte_source, w.amb_hi - w.amb_lo, sum);
    w.rho = *w.physical_rho;
  }

  void RecordAmbientSensor(const ThermalWork& w, AxisFitSummary& sum) {
    if (w.amb.empty()) return;
    model_.ambient_sensor = w.amb;
    model_.ambient_baseline_c = w.amb_base;
    model_.key_rise_above_ambient = true;
    if (const auto range = SensorRange(w.amb); range[0] <= range[1]) model_.ambient_fitted_range_c = range, sum.room_range_c = range;
  }

  // A thermal part needs thermal states, enough dry ones (min_thermal_states) and a candidate.
  bool ThermalPartPossible(const ThermalWork& w) {
    const std::size_t n_off = w.off_states.size();
    bool thermal = !thermal_.empty();
    if (thermal && n_off < static_cast<std::size_t>(o_.min_thermal_states)) {
      Warn(fmt::format("only {} off-coolant heated/ambient state(s); the thermal part needs at least {}: "
                       "geometric-only model",
                       n_off, o_.min_thermal_states));
      thermal = false;
    }
    if (thermal && w.candidates.empty()) {
      Warn("no temperature sensor is present in every state: geometric-only model");
      thermal = false;
    }
    return thermal;
  }

  // ρ fitted with `keys` (fit_rho), else the ρ chosen: the ρ every CV of the later stages uses.
  double RhoFor(const ThermalWork& w, const std::vector<ThermalPoint>& pts, const std::vector<std::size_t>& keys,
                const GainForm& form) const {
    return w.fit_rho ? JointRho(pts, w.off_states, keys, form) : w.rho;
  }

  // The key sensors: the forced ones, else forward stepwise selection by LOSO CV (SelectKeys).
  // ρ is informed only by the states at another room temperature, so leaving such a state out
  // would leave ρ undetermined: for the selection ρ is held at a preliminary estimate (all
  // candidates + ρ fitted jointly), then refitted jointly with the chosen keys.
  void ChooseKeySensors(ThermalWork& w, AxisFitSummary& sum) {
    if (w.thermal && w.fit_rho) {
      std::vector<std::size_t> all_keys;
      for (std::size_t j = 0; j < w.candidates.size(); ++j) all_keys.push_back(j);
      w.rho = JointRho(w.pts, w.off_states, all_keys, form_);
    }
    if (!w.thermal) return;
    sum.no_thermal_cv_rms_um = CrossValidate(w.pts, w.off_states, {}, false, w.rho, form_);
    sum.selection_steps.push_back({{}, sum.no_thermal_cv_rms_um, w.fit_rho ? "no key sensor (ρ term only)" : "no thermal term"});
    if (!o_.key_sensors.empty()) {
      for (std::size_t j = 0; j < w.candidates.size(); ++j) w.keys.push_back(j);
      const double cv = CrossValidate(w.pts, w.off_states, w.keys, false, w.rho, form_);
      sum.selection_steps.push_back({w.candidates, cv, "given in the options"});
      sum.key_selection_reason = "key sensors given in the options, not selected from the data";
    } else {
      SelectKeys(w.pts, w.off_states, w.candidates, w.rho, w.keys, sum);
    }
    if (w.keys.empty()) {
      Warn("no temperature sensor lowered the cross-validated error: thermal part omitted (geometric-only model)");
      w.thermal = false;
    }
  }

  // Thermal lag: first one τ for all the axis' key sensors, from the grid, by the same LOSO CV;
  // then each key's own τ in turn (coordinate descent over the grid, two passes: the nut and the
  // bearing reach the screw on different time scales); then a falling key's longer lag. Each step
  // is kept only when it lowers the CV by min_lag_cv_improvement (τ = 0 everywhere leaves the
  // points exactly as before).
  void ChooseKeyLags(ThermalWork& w, AxisFitSummary& sum) {
    const auto& candidates = w.candidates;
    const auto& keys = w.keys;
    auto& key_lag_s = w.key_lag_s;
    key_lag_s.assign(candidates.size() + 1, 0.0);  // + the motion column's: never lagged again
    bool lag_grid = false;
    for (double tau : o_.key_lag_grid_s) lag_grid = lag_grid || tau > 0;
    if (!(w.thermal && lag_grid)) return;
    auto cv_of = [&](const std::vector<double>& taus, std::vector<ThermalPoint>* out) {
      auto trial = BuildLeveredPoints(w, taus);
      const double cv = CrossValidate(trial, w.off_states, keys, false, RhoFor(w, trial, keys, form_), form_);
      if (out) *out = std::move(trial);
      return cv;
    };
    const double cv0 = CrossValidate(w.pts, w.off_states, keys, false, RhoFor(w, w.pts, keys, form_), form_);
    sum.lag_candidates.push_back({0, cv0});
    double best_cv = cv0, best_tau = 0;
    // With each τ, each factor of a falling key's longer lag (jointly: a longer fall pairs with a
    // shorter rise); the factor is judged after the plain τ, below.
    double best_fall_cv = std::numeric_limits<double>::infinity(), best_fall_tau = 0, best_fall = 1;
    for (double tau : o_.key_lag_grid_s) {
      if (!(tau > 0)) continue;
      std::vector<double> taus(candidates.size(), 0.0);
      for (auto k : keys) taus[k] = tau;
      const double cv = cv_of(taus, nullptr);
      sum.lag_candidates.push_back({tau, cv});
      if (cv < best_cv) best_cv = cv, best_tau = tau;
      for (double f : o_.key_lag_fall_grid) {
        if (f == 1) continue;
        w.fall_factor = f;
        const double cv_f = cv_of(taus, nullptr);
        if (cv_f < best_fall_cv) best_fall_cv = cv_f, best_fall_tau = tau, best_fall = f;
      }
      w.fall_factor = 1;
    }
    const double gain = 1 - o_.min_lag_cv_improvement;
    double cur_cv = cv0;
    if (best_tau > 0 && best_cv <= gain * cv0) {
      for (auto k : keys) key_lag_s[k] = best_tau;
      cur_cv = best_cv;
    }
    std::string per_key;
    if (keys.size() > 1 && o_.per_key_lag)
      for (int pass = 0; pass < 2; ++pass)
        for (auto k : keys)
          for (double tau : o_.key_lag_grid_s) {
            if (tau == key_lag_s[k]) continue;
            auto trial = key_lag_s;
            trial[k] = tau;
            const double cv = cv_of(trial, nullptr);
            if (cv <= gain * cur_cv) {
              per_key += fmt::format("; {} τ {} → {} s: {:.3f} → {:.3f} µm", candidates[k],
                                     FormatShortest(key_lag_s[k]), FormatShortest(tau), cur_cv, cv);
              key_lag_s[k] = tau;
              cur_cv = cv;
            }
          }
    // A falling key lags longer (AxisModel::key_lag_fall_factor), kept by the same rule.
    // (With each key's own τ, per_key_lag, one τ both ways: the factor is searched with one τ.)
    std::string fall;
    w.plain_lag_s = key_lag_s;  // the lag before a longer fall: the motion input is also tried on it
    if (per_key.empty() && best_fall != 1 && best_fall_cv <= gain * cur_cv) {
      fall = fmt::format("; with a falling key lagging {}× longer (τ = {} s rising): {:.3f} → {:.3f} µm",
                         FormatShortest(best_fall), FormatShortest(best_fall_tau), cur_cv, best_fall_cv);
      for (auto k : keys) key_lag_s[k] = best_fall_tau;
      w.fall_factor = best_fall;
      cur_cv = best_fall_cv;
    }
    if (cur_cv < cv0) {
      cv_of(key_lag_s, &w.pts);
      sum.lag_reason = fmt::format("{}{}{}", best_tau > 0 && best_cv <= gain * cv0
                                                 ? fmt::format("τ = {} s lowers the LOSO CV from {:.3f} to {:.3f} µm",
                                                               FormatShortest(best_tau), cv0, best_cv)
                                                 : std::string("one τ for all keys: none helps"),
                                   per_key, fall);
    } else {
      sum.lag_reason = best_tau > 0 ? fmt::format("no lag: the best τ = {} s lowers the LOSO CV by less than {:.0f} % "
                                                  "({:.3f} → {:.3f} µm)",
                                                  FormatShortest(best_tau), 100 * o_.min_lag_cv_improvement, cv0, best_cv)
                                    : "no lag: no τ of the grid lowers the LOSO CV";
    }
    double largest = 0;
    for (auto k : keys) largest = std::max(largest, key_lag_s[k]);
    sum.key_lag_s = largest;
  }

  // Each key's own pivot (FitOptions::key_offsets): with the keys and lag chosen, kept when the
  // same LOSO CV says it predicts held-out states better by min_cv_improvement.
  void ChooseKeyOffsets(ThermalWork& w, AxisFitSummary& sum) {
    if (!(w.thermal && !w.keys.empty())) return;
    GainForm with = form_, without = form_;
    with.key_offsets = true;
    without.key_offsets = false;
    if (o_.key_offsets == FitOptions::KeyOffsets::kAuto) {
      const double cv_without = CrossValidate(w.pts, w.off_states, w.keys, false, RhoFor(w, w.pts, w.keys, without), without);
      const double cv_with = CrossValidate(w.pts, w.off_states, w.keys, false, RhoFor(w, w.pts, w.keys, with), with);
      form_.key_offsets = cv_with < (1 - o_.min_cv_improvement) * cv_without;
      sum.key_offsets_reason = fmt::format(
          "{}: LOSO CV {:.3f} µm with them against {:.3f} µm with the common pivot Px alone (kept at ≥ {:.0f} % better)",
          form_.key_offsets ? "each key's own pivot" : "one pivot Px for every key", cv_with, cv_without,
          100 * o_.min_cv_improvement);
    } else {
      sum.key_offsets_reason = form_.key_offsets ? "each key's own pivot: given in the options"
                                                 : "one pivot Px for every key: given in the options";
    }
    sum.key_offsets = form_.key_offsets;
  }

  // The motion-heat input (motion_heat.hpp): the axis's lagged feed as one more key, its τ from the
  // grid by the same LOSO CV, kept when it lowers the CV by min_cv_improvement. Only when every
  // state's history has the axis's travel (a real machine's log may not: then the seed's form).
  void ChooseMotionHeat(ThermalWork& w, AxisFitSummary& sum) {
    if (!(w.thermal && !w.keys.empty())) return;
    bool grid = false;
    for (double t : o_.motion_lag_grid_s) grid = grid || t > 0;
    std::vector<std::string> without_travel;
    for (auto* s : thermal_)
      if (!s->history.HasTravel()) without_travel.push_back(s->path);
    if (o_.motion_heat == FitOptions::MotionHeat::kOff) {
      sum.motion_reason = "not tried (off in the options)";
      return;
    }
    if (!grid) {
      sum.motion_reason = "not tried (no motion τ grid)";
      return;
    }
    if (!without_travel.empty()) {
      sum.motion_reason = fmt::format("not tried: {} of {} states have no travelled path of axis {} in their history "
                                      "(the machine log's {}_travel_mm column; first: {})",
                                      without_travel.size(), thermal_.size(), axis_name_, LowerAscii(axis_name_),
                                      without_travel.front());
      return;
    }
    const double cv0 = CrossValidate(w.pts, w.off_states, w.keys, false, RhoFor(w, w.pts, w.keys, form_), form_);
    auto with = w.keys;
    with.push_back(w.motion_col);
    // The CV with M lagged by `tau`, on the keys' lag `lag` with fall factor `fall`.
    auto motion_cv = [&](const std::vector<double>& lag, double fall, double tau) {
      const double keep_fall = w.fall_factor, keep_tau = w.motion_tau;
      w.fall_factor = fall, w.motion_tau = tau;
      auto trial = BuildLeveredPoints(w, lag);
      const double cv = CrossValidate(trial, w.off_states, with, false, RhoFor(w, trial, with, form_), form_);
      w.fall_factor = keep_fall, w.motion_tau = keep_tau;
      return cv;
    };
    // (a) on the keys' lag as chosen; (b) when a longer fall was chosen, also on the plain lag
    // with the fall factor chosen again alongside M: the longer fall and M both stand for the
    // screw's heat after the nut stops, and the one chosen first would otherwise take it all.
    double best_cv = std::numeric_limits<double>::infinity(), best_tau = 0, best_fall = w.fall_factor;
    std::vector<double> best_lag = w.key_lag_s;
    for (double tau : o_.motion_lag_grid_s) {
      if (!(tau > 0)) continue;
      double cv = motion_cv(w.key_lag_s, w.fall_factor, tau);
      if (cv < best_cv) best_cv = cv, best_tau = tau, best_fall = w.fall_factor, best_lag = w.key_lag_s;
      if (w.fall_factor != 1 && !w.plain_lag_s.empty())
        for (double f : o_.key_lag_fall_grid) {
          const double cv_b = motion_cv(w.plain_lag_s, f, tau);
          cv = std::min(cv, cv_b);
          if (cv_b < best_cv) best_cv = cv_b, best_tau = tau, best_fall = f, best_lag = w.plain_lag_s;
        }
      sum.motion_candidates.push_back({tau, cv});
    }
    const bool forced = o_.motion_heat == FitOptions::MotionHeat::kOn;
    if (best_tau > 0 && (forced || best_cv <= (1 - o_.min_cv_improvement) * cv0)) {
      const bool refall = best_fall != w.fall_factor || best_lag != w.key_lag_s;
      w.motion_tau = best_tau;
      w.fall_factor = best_fall;
      w.key_lag_s = best_lag;
      w.pts = BuildLeveredPoints(w, w.key_lag_s);
      w.keys = with;
      sum.motion_lag_s = best_tau;
      if (refall)  // the lag's reason above describes the choice without M: say it changed
        sum.lag_reason += fmt::format("; then, with the motion-heat input, τ {} s and a falling key {}× longer "
                                      "(motion heat below)",
                                      FormatShortest(w.key_lag_s[w.keys.front()]), FormatShortest(best_fall));
      double largest = 0;
      for (auto k : w.keys) largest = std::max(largest, w.key_lag_s[k]);
      sum.key_lag_s = largest;
      sum.motion_reason = fmt::format("the axis's feed lagged by τ = {} s as one more key lowers the LOSO CV from "
                                      "{:.3f} to {:.3f} µm{}{}",
                                      FormatShortest(best_tau), cv0, best_cv,
                                      refall ? fmt::format(" (with the keys' lag {} s and a falling key {}× "
                                                           "longer, chosen again alongside it)",
                                                           FormatShortest(sum.key_lag_s), FormatShortest(best_fall))
                                             : std::string(),
                                      forced ? " (on in the options)" : "");
    } else {
      sum.motion_reason = fmt::format("none: the best τ = {} s gives LOSO CV {:.3f} µm against {:.3f} µm without "
                                      "(kept at ≥ {:.0f} % better)",
                                      FormatShortest(best_tau), best_cv, cv0, 100 * o_.min_cv_improvement);
    }
  }

  // The coolant's memory (thermal_state.hpp): the key states drawn to the room with a loss τ while
  // a coolant runs, and ONE set of gains for every state, against today's table (own gains per
  // coolant state). Judged by the same LOSO CV, now over the off AND the coolant states; when kept,
  // the gains are fitted on every state (w.off_states becomes all of them).
  void ChooseCoolantMemory(ThermalWork& w, AxisFitSummary& sum) {
    const auto& keys = w.keys;
    const double rho = w.rho;
    shared_gains_ = false;
    std::set<std::size_t> all_states = w.off_states;
    std::map<CoolantState, std::set<std::size_t>> by_coolant;
    for (std::size_t si = 0; si < thermal_.size(); ++si)
      if (thermal_[si]->coolant != CoolantState::kOff) by_coolant[thermal_[si]->coolant].insert(si), all_states.insert(si);
    bool any_lag = false;
    for (auto k : keys) any_lag = any_lag || w.key_lag_s[k] > 0;
    bool grid = false;
    for (double t : o_.coolant_loss_grid_s) grid = grid || t >= 0;
    if (w.thermal && any_lag && !grid && !by_coolant.empty()) {
      sum.coolant_notes.push_back(
          "gains per coolant state; the coolant memory was not tried (no loss τ grid, the default; fit --coolant-loss-grid-s "
          "0,600,1200,2400,4800,9600 tries it)");
      return;
    }
    if (!(w.thermal && any_lag && grid && !by_coolant.empty())) return;
    const auto& pts = w.pts;
    const auto& off_states = w.off_states;
    auto count = [&](const std::vector<ThermalPoint>& v, const std::set<std::size_t>& st) {
      double n = 0;
      for (const auto& p : v) n += st.count(p.state) && RowUsable(p, keys, false) ? 1 : 0;
      return n;
    };
    GainFit off_fits[2];
    for (int dir = 0; dir < 2; ++dir)
      off_fits[dir] = SolveGains(pts, [&](const ThermalPoint& p) { return p.dir == dir && off_states.count(p.state); },
                                 keys, false, rho, form_);
    const double cv_off = CrossValidate(pts, off_states, keys, false, rho, form_);
    double ss = cv_off * cv_off * count(pts, off_states), n = count(pts, off_states);
    for (const auto& [c, st] : by_coolant) {
      const double cvc = CoolantCv(pts, keys, rho, off_fits, st, st.size() >= keys.size() + 1);
      ss += cvc * cvc * count(pts, st), n += count(pts, st);
    }
    const double cv_table = n > 0 ? std::sqrt(ss / n) : kNaN;
    double best_cv = std::numeric_limits<double>::infinity(), best_off_cv = kNaN;
    std::array<double, kCoolantStateCount> best_loss{};
    for (const auto& [c, st] : by_coolant) {
      auto loss = best_loss;
      for (double tau : o_.coolant_loss_grid_s) {
        if (!(tau >= 0)) continue;
        loss[static_cast<std::size_t>(c)] = tau;
        auto trial = BuildLeveredPoints(w, w.key_lag_s, loss);
        const double cv = CrossValidate(trial, all_states, keys, false, rho, form_);
        if (cv < best_cv)
          best_cv = cv, best_loss = loss, best_off_cv = CrossValidate(trial, all_states, keys, false, rho,
                                                                     form_, &off_states);
      }
    }
    std::string losses;
    for (const auto& [c, st] : by_coolant)
      losses += fmt::format("{}{} {} s", losses.empty() ? "" : ", ", CoolantStateName(c),
                            FormatShortest(best_loss[static_cast<std::size_t>(c)]));
    // One set of gains must also keep the dry states as good as their own gains do: it is a
    // compromise over every state, and the dry states are most of a working day.
    const double off_limit = (1 + o_.coolant_memory_off_tolerance) * cv_off;
    if (best_cv < cv_table && best_off_cv <= off_limit) {
      shared_gains_ = true;
      w.key_loss = best_loss;
      w.pts = BuildLeveredPoints(w, w.key_lag_s, w.key_loss);
      w.off_states = all_states;
      sum.coolant_notes.push_back(fmt::format(
          "coolant memory: one set of gains for every state, the key states drawn to the room with loss τ {} "
          "(LOSO CV over all {} states {:.3f} µm against {:.3f} µm with gains per coolant state; on the dry "
          "states {:.3f} µm against their own gains' {:.3f} µm)",
          losses, all_states.size(), best_cv, cv_table, best_off_cv, cv_off));
    } else {
      sum.coolant_notes.push_back(fmt::format(
          "gains per coolant state: one set of gains with a coolant loss ({}) gives LOSO CV {:.3f} µm over all "
          "states against {:.3f} µm, and {:.3f} µm on the dry states against their own gains' {:.3f} µm (limit "
          "{:.3f} µm)",
          losses, best_cv, cv_table, best_off_cv, cv_off, off_limit));
    }
  }

  // The final gains with every choice made: ρ refitted with the keys (then the physical ρ when the
  // CTE gives it), the gains per direction, the held-out residuals, the model's keys, lags and
  // shifts, the coolant's gains (FitCoolant, unless one set covers every state) and the envelopes.
  void SolveFinalGains(ThermalWork& w, AxisFitSummary& sum) {
    const auto& keys = w.keys;
    const auto& candidates = w.candidates;
    const auto& pts = w.pts;
    const auto& off_states = w.off_states;
    GainFit fits[2];
    if (w.fit_rho) w.rho = JointRho(pts, off_states, keys, form_);
    ApplyPhysicalRho(w, sum);
    const double rho = w.rho;
    for (int dir = 0; dir < 2; ++dir) {
      fits[dir] = SolveGains(pts, [&](const ThermalPoint& p) { return p.dir == dir && off_states.count(p.state); },
                             keys, false, rho, form_);
      if (!fits[dir].ok)
        throw InputError(thermal_.front()->path, 0, "t_<sensor>_c",
                         "the thermal gains cannot be determined from these states (too few usable points)");
    }
    sum.thermal_cv_rms_um = CrossValidate(pts, off_states, keys, false, rho, form_);
    HeldOutResiduals(pts, off_states, keys, rho);
    sum.thermal_fitted = true;
    if (keys.size() > 1 && o_.secondary_key_ridge > 0) {
      // Traceable: the shrunk gains next to what plain least squares would have given.
      const auto plain = SolveGains(
          pts, [&](const ThermalPoint& p) { return p.dir == 0 && off_states.count(p.state); }, keys, false, rho,
          GainForm{0.0, form_.key_offsets});
      std::vector<std::string> shrunk_names;
      for (std::size_t j = 1; j < keys.size(); ++j)
        shrunk_names.push_back(keys[j] < candidates.size() ? candidates[keys[j]] : std::string("motion heat"));
      sum.key_selection_reason += fmt::format(
          "; the gains of {} shrunk toward the {}-only fit (ridge λ {}, FitOptions::secondary_key_ridge): forward "
          "{:.5f} µm/mm/°C, plain least squares {}",
          JoinNames(shrunk_names), candidates[keys[0]], FormatShortest(form_.secondary_ridge),
          fmt::join(fits[0].k, " / "), plain.ok ? fmt::format("{:.5f}", fmt::join(plain.k, " / ")) : std::string("–"));
    }
    for (auto k : keys) {
      if (k == w.motion_col) continue;  // the motion input is not a sensor (always the last key)
      model_.key_sensors.push_back(candidates[k]);
      model_.baseline_temp_c.push_back(w.base[k]);
    }
    model_.motion_lag_s = w.motion_tau;
    bool any_lag = false;
    for (auto k : keys) any_lag = any_lag || w.key_lag_s[k] > 0;
    if (any_lag) {
      for (auto k : keys)
        if (k != w.motion_col) model_.key_lag_s.push_back(w.key_lag_s[k]);
      model_.key_lag_fall_factor = w.fall_factor;
    }
    for (const auto& name : model_.key_sensors) model_.key_fitted_range_c.push_back(SensorRange(name));
    sum.key_sensors = model_.key_sensors;
    for (int dir = 0; dir < 2; ++dir) {
      ThermalGains off;
      off.k_um_per_mm_per_c = fits[dir].k;
      model_.directions[dir].thermal.push_back(std::move(off));
      if (form_.key_offsets) model_.key_shifts[dir].push_back({fits[dir].ko, fits[dir].ambient_offset});
    }
    if (shared_gains_) {
      // Every coolant of the data is recorded, with 0 when the shared gains cover it without a
      // loss: the file says which coolant states the one set of gains was fitted on.
      for (std::size_t si = 0; si < thermal_.size(); ++si) {
        const auto c = static_cast<std::size_t>(thermal_[si]->coolant);
        if (thermal_[si]->coolant != CoolantState::kOff && model_.key_loss_s[c].empty())
          model_.key_loss_s[c].assign(model_.key_sensors.size(), w.key_loss[c]);
      }
    } else {
      FitCoolant(pts, keys, rho, fits, sum);
    }
    SetTanBetaEnvelopes(pts, keys, sum);
  }

  void SelectKeys(const std::vector<ThermalPoint>& pts, const std::set<std::size_t>& off_states,
                  const std::vector<std::string>& candidates, double rho, std::vector<std::size_t>& keys,
                  AxisFitSummary& sum) {
    const bool fit_rho = false;  // ρ is held fixed during the selection (see ChooseKeySensors)
    double cv_cur = sum.no_thermal_cv_rms_um;
    std::vector<std::string> reasons;
    const std::size_t n_states = off_states.size();
    std::set<std::string> noted_collinear;
    // LOSO CV trains on n − 1 states: never more gains (+ ρ) than that.
    const std::size_t max_params = std::max<std::size_t>(1, n_states - 1);
    while (static_cast<int>(keys.size()) < o_.max_key_sensors && keys.size() + 1 + (fit_rho ? 1 : 0) <= max_params) {
      std::size_t best = candidates.size();
      double best_cv = std::numeric_limits<double>::infinity();
      for (std::size_t c = 0; c < candidates.size(); ++c) {
        if (std::find(keys.begin(), keys.end(), c) != keys.end()) continue;
        bool collinear = false;
        for (auto k : keys) {
          const double r = Correlation(pts, off_states, c, k);
          if (std::abs(r) > o_.max_key_correlation) {
            collinear = true;
            if (noted_collinear.insert(candidates[c]).second)
              reasons.push_back(fmt::format("{} skipped: its rise correlates r = {:.3f} with {} (collinear)",
                                            candidates[c], r, candidates[k]));
          }
        }
        if (collinear) continue;
        auto trial = keys;
        trial.push_back(c);
        const double cv = CrossValidate(pts, off_states, trial, fit_rho, rho, form_);
        if (cv < best_cv) best_cv = cv, best = c;
      }
      if (best == candidates.size()) break;
      auto trial = keys;
      trial.push_back(best);
      std::vector<std::string> names;
      for (auto k : trial) names.push_back(candidates[k]);
      if (!(best_cv < cv_cur * (1 - o_.min_cv_improvement))) {
        reasons.push_back(fmt::format("stopped: the best next sensor, {}, would change the CV RMS {:.3f} → {:.3f} µm "
                                      "(less than {:.0f} % better)",
                                      candidates[best], cv_cur, best_cv, 100 * o_.min_cv_improvement));
        sum.selection_steps.push_back({names, best_cv, "rejected"});
        break;
      }
      reasons.push_back(fmt::format("{}: CV RMS {:.3f} → {:.3f} µm", candidates[best], cv_cur, best_cv));
      sum.selection_steps.push_back({names, best_cv, "added " + candidates[best]});
      keys.push_back(best);
      cv_cur = best_cv;
    }
    if (static_cast<int>(keys.size()) == o_.max_key_sensors) reasons.push_back("stopped at max_key_sensors");
    else if (keys.size() + 1 + (fit_rho ? 1 : 0) > max_params && keys.size() < candidates.size())
      reasons.push_back(fmt::format("stopped: {} states allow at most {} gain(s)", n_states, keys.size()));
    sum.key_selection_reason = fmt::format("forward stepwise selection by leave-one-state-out CV over {} states "
                                           "from candidates {}: {}{}",
                                           n_states, JoinNames(candidates), fmt::join(reasons, "; "),
                                           sum.candidate_note.empty() ? "" : "; " + sum.candidate_note);
  }

  // With the motion-heat input among `keys` (always the last), a coolant's own gains are fitted on
  // the key sensors only, with M's gain held at the off-coolant value: a coolant's few states (4 or
  // 5 of one session) cannot tell M from the keys, and own gains for it swung to the opposite sign
  // on drawn machines (rnd3_09_gantry Y warm + coolant 14.6 → 53.0 µm). `keys` without M, and the
  // points with the off gains' M part taken out of r.
  bool HasMotionKey(const std::vector<std::size_t>& keys) const { return !keys.empty() && keys.back() == motion_col_; }
  std::vector<std::size_t> SensorKeys(const std::vector<std::size_t>& keys) const {
    return HasMotionKey(keys) ? std::vector<std::size_t>(keys.begin(), keys.end() - 1) : keys;
  }
  std::vector<ThermalPoint> WithoutMotionPart(const std::vector<ThermalPoint>& pts, const std::vector<std::size_t>& keys,
                                              const GainFit* off_fits) const {
    std::vector<ThermalPoint> out = pts;
    if (!HasMotionKey(keys)) return out;
    const std::size_t j = keys.size() - 1;
    for (auto& p : out) {
      const GainFit& g = off_fits[p.dir];
      const double m = p.rise[motion_col_];
      if (!std::isfinite(m) || j >= g.k.size()) continue;
      p.r -= g.k[j] * m * p.lever_mm + (j < g.ko.size() ? g.ko[j] * m : 0.0);
    }
    return out;
  }
  // A coolant's own gains for the sensor keys completed with the off gains' M entry.
  static void AppendMotionGain(const GainFit& off, GainFit& g) {
    if (off.k.size() == g.k.size() + 1) g.k.push_back(off.k.back());
    if (!g.ko.empty() && off.ko.size() == g.ko.size() + 1) g.ko.push_back(off.ko.back());
  }

  // A coolant's own gains for `sensor_keys` on the points `use` selects, with the off ρ. With the
  // soak constraint (FitOptions::coolant_soak_constraint) and two keys or more, Σk (and the keys'
  // and the room's shifts summed) held at the off gains' `off`: the machine soaked under the
  // coolant expands as it does dry, and what the coolant changes is how the keys share it. With
  // one key the constraint would leave the off gain itself, so it is not applied.
  template <typename Use>
  GainFit CoolantOwnGains(const std::vector<ThermalPoint>& pts, Use use, const std::vector<std::size_t>& sensor_keys,
                          double rho, const GainFit& off) const {
    GainForm f = form_;
    if (o_.coolant_soak_constraint && sensor_keys.size() >= 2) {
      f.soak_slope = rho;
      for (std::size_t j = 0; j < sensor_keys.size() && j < off.k.size(); ++j) f.soak_slope += off.k[j];
      if (form_.key_offsets) {
        f.soak_shift = off.ambient_offset;
        for (std::size_t j = 0; j < sensor_keys.size() && j < off.ko.size(); ++j) f.soak_shift += off.ko[j];
      }
    }
    return SolveGains(pts, use, sensor_keys, false, rho, f);
  }

  // The off-coolant gains times one factor fitted on `use`'s points of direction `dir` (the
  // coolant fallback: one parameter, so it cannot swing far from what the off states showed).
  template <typename Use>
  double CoolantFactor(const std::vector<ThermalPoint>& pts, const std::vector<std::size_t>& keys, double rho,
                       const GainFit& off_fit, int dir, Use use) const {
    double num = 0, den = 0;
    GainFit no_rho = off_fit;
    no_rho.rho = 0;
    no_rho.ambient_offset = 0;  // the room's terms are not the coolant's: not scaled
    for (const auto& p : pts) {
      if (p.dir != dir || !use(p) || !RowUsable(p, keys, false)) continue;
      const double pred = PredictThermal(p, keys, no_rho);
      const double y =
          p.r - (std::isfinite(p.amb_rise) ? (rho * p.lever_mm + off_fit.ambient_offset) * p.amb_rise : 0);
      num += y * pred, den += pred * pred;
    }
    return den > 0 ? num / den : 1;
  }

  // Leave-one-state-out CV RMS over the coolant's states of the two coolant forms: its own gains
  // (`own`) or the off gains × one factor.
  double CoolantCv(const std::vector<ThermalPoint>& pts, const std::vector<std::size_t>& keys, double rho,
                   const GainFit* off_fits, const std::set<std::size_t>& states, bool own) const {
    double ss = 0;
    std::size_t n = 0;
    const auto sensor_keys = SensorKeys(keys);
    const auto own_pts = own ? WithoutMotionPart(pts, keys, off_fits) : std::vector<ThermalPoint>{};
    for (int dir = 0; dir < 2; ++dir)
      for (std::size_t s : states) {
        auto train = [&](const ThermalPoint& p) { return p.dir == dir && p.state != s && states.count(p.state); };
        GainFit g;
        if (own) {
          g = CoolantOwnGains(own_pts, train, sensor_keys, rho, off_fits[dir]);
          if (!g.ok) return std::numeric_limits<double>::infinity();
          AppendMotionGain(off_fits[dir], g);
        } else {
          g = off_fits[dir];
          const double f = CoolantFactor(pts, keys, rho, off_fits[dir], dir, train);
          for (double& k : g.k) k *= f;
          for (double& k : g.ko) k *= f;
        }
        g.rho = rho;
        for (const auto& p : pts) {
          if (p.dir != dir || p.state != s || !RowUsable(p, keys, false)) continue;
          ss += std::pow(p.r - PredictThermal(p, keys, g), 2);
          ++n;
        }
      }
    return n ? std::sqrt(ss / static_cast<double>(n)) : std::numeric_limits<double>::infinity();
  }

  void FitCoolant(const std::vector<ThermalPoint>& pts, const std::vector<std::size_t>& keys, double rho,
                  const GainFit* off_fits, AxisFitSummary& sum) {
    std::map<CoolantState, std::set<std::size_t>> by_coolant;
    for (std::size_t si = 0; si < thermal_.size(); ++si)
      if (thermal_[si]->coolant != CoolantState::kOff) by_coolant[thermal_[si]->coolant].insert(si);
    for (const auto& [coolant, states] : by_coolant) {
      // Own gains need keys + 1 states, and must predict a held-out coolant state better than the
      // one-factor form: with a few states of one warm-up the key rises move together, and own
      // gains fitted on them can be large and of opposite sign — they then extrapolate wildly on
      // any other mix of nut and bearing temperatures (gantry2000 X with flood coolant).
      const auto sensor_keys = SensorKeys(keys);
      bool own = states.size() >= sensor_keys.size() + 1 && !sensor_keys.empty();
      std::string why;
      if (own && states.size() >= 2 && o_.coolant_form_by_cv) {
        const double cv_own = CoolantCv(pts, keys, rho, off_fits, states, true);
        const double cv_factor = CoolantCv(pts, keys, rho, off_fits, states, false);
        own = cv_own < (1 - o_.min_cv_improvement) * cv_factor;
        why = fmt::format(" (leave-one-state-out CV: own gains {:.3f} µm, off gains × factor {:.3f} µm)", cv_own,
                          cv_factor);
      }
      for (int dir = 0; dir < 2; ++dir) {
        ThermalGains tg;
        KeyShifts shifts;  // each key's own pivot (kept only with key offsets)
        tg.coolant = coolant;
        if (own) {
          auto g = CoolantOwnGains(WithoutMotionPart(pts, keys, off_fits),
                                   [&](const ThermalPoint& p) { return p.dir == dir && states.count(p.state); },
                                   sensor_keys, rho, off_fits[dir]);
          if (g.ok) AppendMotionGain(off_fits[dir], g);
          const GainFit& used = g.ok ? g : off_fits[dir];
          tg.k_um_per_mm_per_c = used.k;
          shifts.offset_um_per_c = used.ko;
          shifts.ambient_offset_um_per_c = used.ambient_offset;
        } else {
          // The off-coolant gains scaled by one factor fitted on this coolant's states.
          const double f = CoolantFactor(pts, keys, rho, off_fits[dir], dir,
                                         [&](const ThermalPoint& p) { return states.count(p.state) > 0; });
          for (double k : off_fits[dir].k) tg.k_um_per_mm_per_c.push_back(f * k);
          for (double k : off_fits[dir].ko) shifts.offset_um_per_c.push_back(f * k);
          shifts.ambient_offset_um_per_c = off_fits[dir].ambient_offset;
          if (dir == 0)
            sum.coolant_notes.push_back(fmt::format("coolant {}: {} state(s){}: off-coolant gains × one fitted factor "
                                                    "({:.3f} forward",
                                                    CoolantStateName(coolant), states.size(),
                                                    why.empty() ? fmt::format(" < keys + 1 = {}", sensor_keys.size() + 1) : why,
                                                    f));
          else
            sum.coolant_notes.back() += fmt::format(", {:.3f} reverse)", f);
        }
        model_.directions[dir].thermal.push_back(std::move(tg));
        if (form_.key_offsets) model_.key_shifts[dir].push_back(std::move(shifts));
      }
      if (own)
        sum.coolant_notes.push_back(fmt::format("coolant {}: gains fitted on its own {} state(s){}{}",
                                                CoolantStateName(coolant), states.size(), why,
                                                HasMotionKey(keys) ? " (the motion-heat gain held at the off-coolant value)" : ""));
    }
  }

  // The thermal slope Σ k_i·ΔT_i each gains entry gave over the fit's states it describes (off: the
  // off-coolant states, a coolant: that coolant's states; 0 for the cold state), widened on both
  // sides by tan_beta_margin × its width: Predict holds tanβ there and flags it.
  void SetTanBetaEnvelopes(const std::vector<ThermalPoint>& pts, const std::vector<std::size_t>& keys,
                           AxisFitSummary& sum) {
    if (!(o_.tan_beta_margin >= 0)) return;
    for (int dir = 0; dir < 2; ++dir)
      for (auto& g : model_.directions[dir].thermal) {
        double lo = 0, hi = 0;
        std::vector<std::array<double, 2>> rise(keys.size(), {0.0, 0.0});
        for (const auto& p : pts) {
          if (p.dir != dir || (!shared_gains_ && thermal_[p.state]->coolant != g.coolant) || !RowUsable(p, keys, false))
            continue;
          double tb = g.offset_um_per_mm;
          for (std::size_t j = 0; j < keys.size() && j < g.k_um_per_mm_per_c.size(); ++j) {
            tb += g.k_um_per_mm_per_c[j] * p.rise[keys[j]];
            rise[j] = {std::min(rise[j][0], p.rise[keys[j]]), std::max(rise[j][1], p.rise[keys[j]])};
          }
          lo = std::min(lo, tb), hi = std::max(hi, tb);
        }
        const double m = o_.tan_beta_margin * (hi - lo);
        g.min_tan_beta_um_per_mm = lo - m;
        g.max_tan_beta_um_per_mm = hi + m;
        g.key_rise_range_c.clear();
        std::string rises;
        for (std::size_t j = 0; j < keys.size(); ++j) {
          const double mr = o_.tan_beta_margin * (rise[j][1] - rise[j][0]);
          g.key_rise_range_c.push_back({rise[j][0] - mr, rise[j][1] + mr});
          if (keys[j] < candidates_.size())
            rises += fmt::format(", {} rise [{:.2f}, {:.2f}] °C", candidates_[keys[j]], rise[j][0] - mr, rise[j][1] + mr);
          else
            rises += fmt::format(", motion heat [{:.2f}, {:.2f}] m/min", rise[j][0] - mr, rise[j][1] + mr);
        }
        sum.coolant_notes.push_back(fmt::format("envelope {} coolant {}: tanβ [{:.4f}, {:.4f}] µm/mm{} (fitted "
                                                "states ± {:.0f} %)",
                                                dir == 0 ? "forward" : "reverse", CoolantStateName(g.coolant),
                                                g.min_tan_beta_um_per_mm, g.max_tan_beta_um_per_mm, rises,
                                                100 * o_.tan_beta_margin));
      }
  }

  std::vector<const measure::Measurement*> AllMeasurements() const {
    std::vector<const measure::Measurement*> out;
    for (auto* s : all_) out.push_back(&s->measurement);
    return out;
  }

  void HeldOutResiduals(const std::vector<ThermalPoint>& pts, const std::set<std::size_t>& off_states,
                        const std::vector<std::size_t>& keys, double rho) {
    held_out_.clear();
    if (off_states.size() < 3) return;
    for (std::size_t s : off_states) {
      StateResidualInput st;
      st.label = thermal_[s]->label.empty() ? "(unlabelled)" : thermal_[s]->label;
      for (int dir = 0; dir < 2; ++dir) {
        const auto g = SolveGains(
            pts, [&](const ThermalPoint& p) { return p.dir == dir && p.state != s && off_states.count(p.state); }, keys,
            false, rho, form_);
        if (!g.ok) continue;
        for (const auto& p : pts) {
          if (p.dir != dir || p.state != s || !RowUsable(p, keys, false)) continue;
          st.position_mm.push_back(p.x);
          st.residual_um.push_back(p.r - PredictThermal(p, keys, g));
        }
      }
      if (!st.position_mm.empty()) held_out_.push_back(std::move(st));
    }
  }

  void ComputeStateStats(AxisFitSummary& sum) {
    ResidualDiagnosisInput diag;
    diag.key_sensors = model_.key_sensors;
    for (const auto& d : sum.directions)
      if (std::isfinite(d.degree.noise_um))
        diag.noise_um = std::isfinite(diag.noise_um) ? std::max(diag.noise_um, d.degree.noise_um) : d.degree.noise_um;
    auto stats_for = [&](const FitState& s, bool used, const std::array<double, 2>& tb) {
      StateFitStats st;
      st.label = s.label.empty() ? "(unlabelled)" : s.label;
      st.path = s.path;
      st.kind = s.kind == StateKind::kUnknown ? StateKind::kHeated : s.kind;
      st.coolant = s.coolant;
      st.used_for_thermal = used;
      st.tan_beta_um_per_mm = tb;
      const auto& m = s.measurement;
      st.points = m.points.size();
      for (std::size_t k = 0; k < model_.key_sensors.size(); ++k) {
        const double mean = MeanOfSensor(m, model_.key_sensors[k]);
        double shift = 0;
        if (model_.key_rise_above_ambient) shift = MeanOfSensor(m, model_.ambient_sensor) - model_.ambient_baseline_c;
        st.mean_key_rise_c.push_back(mean - model_.baseline_temp_c[k] - shift);
      }
      if (!model_.ambient_sensor.empty())
        st.mean_ambient_rise_c = MeanOfSensor(m, model_.ambient_sensor) - model_.ambient_baseline_c;
      double su = 0, sg = 0, sr = 0;
      const auto lagged = LaggedKeyTemperatures(model_, m, &s.history, s.coolant);
      StateResidualInput& dr = diag.states.emplace_back();
      dr.label = st.label;
      dr.cold = std::find(cold_states_.begin(), cold_states_.end(), &s) != cold_states_.end();
      dr.key_contribution_um.resize(model_.key_sensors.size());
      for (std::size_t pi = 0; pi < m.points.size(); ++pi) {
        const auto& p = m.points[pi];
        const auto& t = lagged[pi];
        const auto pr = Predict(model_, p.target_mm, p.direction, {t.key_temp_c, t.ambient_c, s.coolant, true, t.motion_m_per_min});
        const double res = p.deviation_um - pr.total_um;
        dr.position_mm.push_back(p.target_mm);
        dr.residual_um.push_back(res);
        for (std::size_t k = 0; k < model_.key_sensors.size() && k < t.key_temp_c.size(); ++k)
          dr.key_contribution_um[k].push_back(KeyContribution(p, t, s.coolant, k, pr.total_um));
        su += p.deviation_um * p.deviation_um;
        sg += std::pow(p.deviation_um - pr.geometric_um, 2);
        sr += res * res;
        st.uncorrected_max_um = std::max(st.uncorrected_max_um, std::abs(p.deviation_um));
        st.residual_max_um = std::max(st.residual_max_um, std::abs(res));
      }
      const double n = std::max<double>(1, static_cast<double>(m.points.size()));
      st.uncorrected_rms_um = std::sqrt(su / n);
      st.geometric_only_rms_um = std::sqrt(sg / n);
      st.residual_rms_um = std::sqrt(sr / n);
      return st;
    };
    for (auto* c : cold_states_) {
      auto st = stats_for(*c, false, {kNaN, kNaN});
      st.kind = StateKind::kCold;
      sum.states.push_back(std::move(st));
    }
    for (std::size_t si = 0; si < thermal_.size(); ++si)
      sum.states.push_back(stats_for(*thermal_[si], sum.thermal_fitted, stage1_.empty() ? std::array<double, 2>{kNaN, kNaN} : stage1_[si]));
    diag.cross_validated = false;  // the model's own residual on the states it was fitted on
    sum.diagnosis = DiagnoseResidual(diag);
    if (!held_out_.empty()) {
      // The shapes judged on what the model does on a state it has not seen (the dry states, each
      // predicted by the gains fitted without it); the key sensors' shares stay the model's own.
      ResidualDiagnosisInput cv;
      cv.key_sensors = diag.key_sensors;
      cv.noise_um = diag.noise_um;
      cv.cross_validated = true;
      for (const auto& st : diag.states)
        if (st.cold) cv.states.push_back(st);
      cv.states.insert(cv.states.end(), held_out_.begin(), held_out_.end());
      auto shares = std::move(sum.diagnosis.key_shares);
      sum.diagnosis = DiagnoseResidual(cv);
      sum.diagnosis.key_shares = std::move(shares);
    }
  }

  // Key sensor k's part of the model's prediction at point p: the prediction with every key less
  // the prediction with key k at its baseline (zero rise). Only reported, never fitted.
  double KeyContribution(const measure::MeasurementPoint& p, const PointTemperatures& t, CoolantState coolant,
                         std::size_t k, double total_um) const {
    std::vector<double> temps = t.key_temp_c;
    if (k >= temps.size() || k >= model_.baseline_temp_c.size() || !std::isfinite(temps[k])) return kNaN;
    double base = model_.baseline_temp_c[k];
    if (model_.key_rise_above_ambient && std::isfinite(t.ambient_c)) base += t.ambient_c - model_.ambient_baseline_c;
    temps[k] = base;
    const auto without = Predict(model_, p.target_mm, p.direction, {temps, t.ambient_c, coolant, true, t.motion_m_per_min});
    return total_um - without.total_um;
  }

  // The lowest and highest reading of sensor `name` over every measurement of the fit (±inf
  // reversed when it has none): the range the model was fitted on.
  std::array<double, 2> SensorRange(const std::string& name) const {
    std::array<double, 2> range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const auto* st : all_) {
      const auto idx = st->measurement.SensorIndex(name);
      if (!idx) continue;
      for (const auto& p : st->measurement.points) {
        const double t = p.temperatures_c[*idx];
        if (std::isfinite(t)) range[0] = std::min(range[0], t), range[1] = std::max(range[1], t);
      }
    }
    return range;
  }

  std::string axis_name_;
  std::vector<const FitState*> all_;
  const FitOptions& o_;
  std::vector<std::string>& warnings_;
  std::vector<const FitState*> cold_states_;
  std::vector<const FitState*> thermal_;
  std::vector<std::array<double, 2>> stage1_;
  // Per dry thermal state, its residual predicted by the gains fitted without it (leave-one-state-out),
  // for the residual's diagnosis; empty with fewer than three such states.
  std::vector<StateResidualInput> held_out_;
  std::vector<std::string> candidates_;  // the key-sensor candidates of PrepareThermal (for notes)
  bool shared_gains_ = false;            // one gains entry for every coolant state (coolant memory)
  std::size_t motion_col_ = std::numeric_limits<std::size_t>::max();  // the motion input's column in rise
  GainForm form_;                        // ridge and key offsets of every gains solve
  measure::Measurement cold_;
  AxisModel model_;
};

}  // namespace

PointTemperatures TemperaturesForPoint(const AxisModel& axis, const measure::Measurement& m,
                                       const measure::MeasurementPoint& p) {
  PointTemperatures t;
  for (const auto& k : axis.key_sensors) {
    auto idx = m.SensorIndex(k);
    t.key_temp_c.push_back(idx && *idx < p.temperatures_c.size() ? p.temperatures_c[*idx] : kNaN);
  }
  if (!axis.ambient_sensor.empty())
    if (auto idx = m.SensorIndex(axis.ambient_sensor); idx && *idx < p.temperatures_c.size())
      t.ambient_c = p.temperatures_c[*idx];
  return t;
}

std::vector<double> ObservedSensorSeries(const measure::Measurement& m, std::size_t sensor_index,
                                         const KeySeriesDynamics& d, const TemperatureHistory* history) {
  const auto& pts = m.points;
  std::vector<double> out(pts.size(), kNaN);
  std::vector<std::size_t> order(pts.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  // Time order (a file may list the runs grouped differently); points without time_s keep file order.
  const bool all_timed = std::all_of(pts.begin(), pts.end(), [](const auto& p) { return p.time_s.has_value(); });
  if (all_timed)
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return *pts[a].time_s < *pts[b].time_s; });
  // The temperature a coolant draws the key to: its baseline, moved with the room when known.
  auto sink = [&](const std::vector<double>& row) {
    if (!d.ambient_index || *d.ambient_index >= row.size() || !std::isfinite(d.ambient_baseline_c)) return d.baseline_c;
    const double amb = row[*d.ambient_index];
    return std::isfinite(amb) ? d.baseline_c + (amb - d.ambient_baseline_c) : d.baseline_c;
  };
  auto loss = [&](CoolantState c) { return d.tau_loss_s[static_cast<std::size_t>(c) % d.tau_loss_s.size()]; };
  // The lag's τ for one step (AxisModel::KeyLagS(k, state, raw)): longer while the reading falls, dry.
  auto tau_for = [&](double state_c, double raw_c, CoolantState c) {
    return raw_c < state_c && !(loss(c) > 0) ? d.fall_factor * d.tau_lag_s : d.tau_lag_s;
  };
  double state = kNaN, last_t = kNaN;
  if (history && d.tau_lag_s > 0 && all_timed)
    for (std::size_t r = 0; r < history->time_s.size(); ++r) {
      const auto& row = history->temps_c[r];
      const double raw = sensor_index < row.size() ? row[sensor_index] : kNaN;
      if (std::isnan(raw)) continue;  // a flagged reading: the filter carries on over the gap
      const CoolantState c = r < history->coolant.size() ? history->coolant[r] : CoolantState::kOff;
      state = std::isnan(last_t) ? raw
                                 : ObserverStep(state, raw, sink(row), history->time_s[r] - last_t, tau_for(state, raw, c), loss(c));
      last_t = history->time_s[r];
    }
  for (std::size_t i : order) {
    const auto& p = pts[i];
    const double raw = sensor_index < p.temperatures_c.size() ? p.temperatures_c[sensor_index] : kNaN;
    const double now = p.time_s ? *p.time_s : kNaN;
    // No time stamp: no lag can be applied, the filter restarts at the reading.
    state = std::isnan(now) || std::isnan(last_t)
                ? raw
                : ObserverStep(state, raw, sink(p.temperatures_c), now - last_t, tau_for(state, raw, d.coolant), loss(d.coolant));
    if (std::isnan(state)) state = raw;
    last_t = now;
    out[i] = state;
  }
  return out;
}

std::vector<double> LaggedSensorSeries(const measure::Measurement& m, std::size_t sensor_index, double tau_s,
                                       const TemperatureHistory* history) {
  KeySeriesDynamics d;
  d.tau_lag_s = tau_s;
  return ObservedSensorSeries(m, sensor_index, d, history);
}

std::vector<PointTemperatures> LaggedKeyTemperatures(const AxisModel& axis, const measure::Measurement& m,
                                                     const TemperatureHistory* history, CoolantState coolant) {
  std::vector<PointTemperatures> out;
  out.reserve(m.points.size());
  for (const auto& p : m.points) out.push_back(TemperaturesForPoint(axis, m, p));
  for (std::size_t k = 0; k < axis.key_sensors.size(); ++k) {
    if (!(axis.KeyLagS(k) > 0)) continue;
    const auto idx = m.SensorIndex(axis.key_sensors[k]);
    if (!idx) continue;
    KeySeriesDynamics d;
    d.tau_lag_s = axis.KeyLagS(k);
    d.fall_factor = axis.key_lag_fall_factor;
    for (std::size_t c = 0; c < d.tau_loss_s.size(); ++c) d.tau_loss_s[c] = axis.KeyLossS(k, static_cast<CoolantState>(c));
    d.baseline_c = k < axis.baseline_temp_c.size() ? axis.baseline_temp_c[k] : kNaN;
    if (axis.key_rise_above_ambient) {
      d.ambient_index = m.SensorIndex(axis.ambient_sensor);
      d.ambient_baseline_c = axis.ambient_baseline_c;
    }
    d.coolant = coolant;
    const auto series = ObservedSensorSeries(m, *idx, d, history);
    for (std::size_t i = 0; i < out.size(); ++i) out[i].key_temp_c[k] = series[i];
  }
  if (axis.HasMotionHeat()) {
    const auto motion = history ? MotionHeatAtPoints(m, *history, axis.motion_lag_s)
                                : std::vector<double>(out.size(), kNaN);
    for (std::size_t i = 0; i < out.size(); ++i) out[i].motion_m_per_min = motion[i];
  }
  return out;
}

measure::Measurement PredictedMeasurement(const AxisModel& axis, const measure::Measurement& m, CoolantState coolant,
                                          const TemperatureHistory* history) {
  measure::Measurement out = m;
  const auto temps = LaggedKeyTemperatures(axis, m, history, coolant);
  for (std::size_t i = 0; i < out.points.size(); ++i) {
    auto& p = out.points[i];
    const auto& t = temps[i];
    p.deviation_um = Predict(axis, p.target_mm, p.direction, {t.key_temp_c, t.ambient_c, coolant, true, t.motion_m_per_min}).total_um;
  }
  return out;
}

measure::Measurement PredictionResidual(const AxisModel& axis, const measure::Measurement& m, CoolantState coolant,
                                        const TemperatureHistory* history) {
  measure::Measurement out = PredictedMeasurement(axis, m, coolant, history);
  for (std::size_t i = 0; i < out.points.size(); ++i)
    out.points[i].deviation_um = m.points[i].deviation_um - out.points[i].deviation_um;
  return out;
}

namespace {
// AxisModel::fallbacks: the axis fitted again without each of its key sensors in turn, twice: its
// keys re-chosen by the same CV from the remaining candidates (the other keys, the motor, the bed,
// ...), and the model's other keys as they are (no re-selection); and without its ambient sensor,
// its keys re-chosen. Each names the sensor it replaces; the compensator averages the two when that
// sensor is lost. Why both: on the machine zoo and on drawn machines the campaign's CV did not rank
// them the way the working day did — the re-chosen keys (often a motor, which warms with the axis's
// own test motion) won on some axes and lost badly on others, the other keys the reverse, and the
// one that helped the day had up to 2.7 × the other's CV — and their average keeps more rows under
// the must line than either (bench/results/zoo.md). Every other option as asked; best LOSO CV first — also for a single-key
// model. A reduced fit that keeps no key (no other sensor explains the heat) is left out, and so is
// the second of two with the same keys. Its warnings repeat the main fit's and are dropped.
void FitFallbacks(const std::string& axis, const std::vector<const FitState*>& states, const FitOptions& options,
                  AxisModel& am, AxisFitSummary& sum, const std::function<void(const std::string&)>& tell) {
  std::vector<std::string> lost = am.key_sensors;
  if (!am.ambient_sensor.empty()) lost.push_back(am.ambient_sensor);
  std::vector<std::pair<double, AxisModel>> found;
  for (const auto& sensor : lost) {
    // Its redundant partners are lost with it when the pipeline finds them disagreeing.
    std::vector<std::string> partners;
    for (const auto& group : options.redundant_groups)
      if (std::find(group.begin(), group.end(), sensor) != group.end())
        for (const auto& other : group)
          if (other != sensor) partners.push_back(other);
    std::vector<std::string> other_keys;
    for (const auto& k : am.key_sensors)
      if (k != sensor && std::find(partners.begin(), partners.end(), k) == partners.end()) other_keys.push_back(k);
    std::vector<std::string> first_keys;
    std::vector<std::pair<double, AxisModel>> pair;  // this sensor's fallbacks, with their CV
    std::vector<std::string> pair_notes;
    // Without the room sensor, the model's keys as they are have nothing to stand for the room (the
    // re-chosen keys can take the bed or another slow sensor for it): only the re-chosen fallback.
    const int variants = sensor == am.ambient_sensor ? 1 : 2;
    tell("fallback models without " + sensor);
    for (int variant = 0; variant < variants; ++variant) {
      FitOptions fo = options;
      fo.fallback_models = false;
      fo.key_sensors.clear();
      if (variant == 1) {
        if (other_keys.empty()) break;
        fo.key_sensors = other_keys;
      }
      fo.excluded_sensors.push_back(sensor);
      for (const auto& other : partners) fo.excluded_sensors.push_back(other);
      if (sensor == am.ambient_sensor) fo.ambient_sensor = "none";  // no room term: the room is not read
      std::vector<std::string> warnings;
      AxisFitSummary fs;
      AxisFitter fitter(axis, states, fo, warnings);
      AxisModel fb = fitter.Fit(fs);
      const char* how = variant == 0 ? "keys re-chosen" : "the model's other keys";
      if (fb.key_sensors.empty()) {
        sum.fallback_notes.push_back(fmt::format("without {} ({}): no thermal part could be fitted, no fallback", sensor, how));
        continue;
      }
      auto sorted_keys = fb.key_sensors;
      std::sort(sorted_keys.begin(), sorted_keys.end());
      if (variant == 1 && sorted_keys == first_keys) {
        sum.fallback_notes.push_back(
            fmt::format("without {}: the model's other keys are the re-chosen ones, one fallback", sensor));
        continue;
      }
      if (variant == 0) first_keys = sorted_keys;
      pair_notes.push_back(fmt::format("fallback without {}{} ({}): keys {}{}, LOSO CV {:.3f} µm (the full model's {:.3f} µm)",
                                       sensor, partners.empty() ? "" : fmt::format(" (and its redundant {})", fmt::join(partners, ", ")),
                                       how, fmt::join(fb.key_sensors, ", "),
                                       fb.ambient_sensor.empty() ? ", no room term" : "", fs.thermal_cv_rms_um,
                                       sum.thermal_cv_rms_um));
      sum.fallbacks.push_back({sensor, partners, how, fb.key_sensors, !fb.ambient_sensor.empty(), fs.thermal_cv_rms_um, false});
      fb.replaces = sensor;
      pair.emplace_back(std::isfinite(fs.thermal_cv_rms_um) ? fs.thermal_cv_rms_um : 1e300, std::move(fb));
    }
    for (auto& note : pair_notes) sum.fallback_notes.push_back(std::move(note));
    for (auto& p : pair) found.push_back(std::move(p));
  }
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < found.size(); ++i) {
    if (i < static_cast<std::size_t>(options.max_fallback_models)) {
      for (auto& f : sum.fallbacks)
        if (f.without == found[i].second.replaces && f.key_sensors == found[i].second.key_sensors) f.kept = true;
      am.fallbacks.push_back(std::move(found[i].second));
    } else {
      sum.fallback_notes.push_back(fmt::format("not kept (at most {} fallbacks, the best by CV): keys {}",
                                               options.max_fallback_models, fmt::join(found[i].second.key_sensors, ", ")));
    }
  }
}
}  // namespace

FitResult FitCompositeModel(const std::vector<FitState>& states, const FitOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("invalid fit options: " + why);
  if (states.empty()) throw InputError("(fit input)", "no measurement files were given");
  // Group by axis, in the order axes first appear.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const FitState*>> by_axis;
  for (const auto& s : states) {
    std::string axis = s.axis.empty() ? options.default_axis : s.axis;
    if (axis.empty())
      throw InputError(s.path, 0, "axis", "no '# axis:' metadata line; add one (e.g. '# axis: X') or pass --axis");
    if (!by_axis.count(axis)) order.push_back(axis);
    by_axis[axis].push_back(&s);
  }
  FitResult res;
  res.model.created_utc = options.created_utc;
  res.model.generator = "trueaxis 0.1.0 fit";
  // One model is one machine's: files that name different machines are refused, not merged.
  const FitState* named = nullptr;
  for (const auto& s : states) {
    const auto mm = s.measurement.Meta("machine");
    const std::string machine = mm ? std::string(Trim(*mm)) : std::string();
    if (machine.empty()) continue;
    if (!named) {
      named = &s;
      res.model.machine = machine;
    } else if (machine != res.model.machine) {
      throw InputError(s.path, s.measurement.MetaLine("machine"), "machine",
                       fmt::format("machine '{}', but {} is of '{}': one model is fitted per machine (fit each "
                                   "machine's files on their own)",
                                   machine, named->path, res.model.machine));
    }
  }
  for (const auto& s : states) {
    res.model.sources.push_back({s.path, s.sha256, s.label.empty() ? std::string(StateKindName(s.kind)) : s.label,
                                 std::string(CoolantStateName(s.coolant)),
                                 s.axis.empty() ? options.default_axis : s.axis, s.temperature_log,
                                 s.temperature_log_sha256, s.start_time_s});
  }
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& axis = order[i];
    if (options.progress)
      options.progress(i, order.size(), fmt::format("axis {} ({} of {}): the model", axis, i + 1, order.size()));
    AxisFitSummary sum;
    AxisFitter fitter(axis, by_axis[axis], options, res.summary.warnings);
    AxisModel am = fitter.Fit(sum);
    if (options.fallback_models && !am.key_sensors.empty())
      FitFallbacks(axis, by_axis[axis], options, am, sum, [&](const std::string& what) {
        if (options.progress) options.progress(i, order.size(), fmt::format("axis {} ({} of {}): {}", axis, i + 1, order.size(), what));
      });
    res.model.axes.push_back(std::move(am));
    res.summary.axes.push_back(std::move(sum));
  }
  if (options.progress) options.progress(order.size(), order.size(), "done");
  res.model.fit_summary = res.summary.ToJson();
  return res;
}

}  // namespace trueaxis::model
