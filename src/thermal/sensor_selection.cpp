#include "trueaxis/thermal/sensor_selection.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::thermal {
namespace {

// Columns centred and scaled to unit (population) variance; constant columns become 0.
Eigen::MatrixXd Standardise(const Eigen::MatrixXd& x) {
  Eigen::MatrixXd z = x.rowwise() - x.colwise().mean();
  const double n = static_cast<double>(x.rows());
  for (Eigen::Index c = 0; c < z.cols(); ++c) {
    const double sd = std::sqrt(z.col(c).squaredNorm() / n);
    if (sd > 0) z.col(c) /= sd;
    else z.col(c).setZero();
  }
  return z;
}

std::vector<int> OrderByScore(std::vector<int> idx, const std::vector<double>& score) {
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return score[static_cast<std::size_t>(a)] > score[static_cast<std::size_t>(b)]; });
  return idx;
}

}  // namespace

const char* SelectionMethodName(SelectionMethod m) {
  switch (m) {
    case SelectionMethod::kAll: return "all";
    case SelectionMethod::kCorrelationClusters: return "correlation-clusters";
    case SelectionMethod::kLasso: return "lasso";
  }
  return "?";
}

bool ParseSelectionMethod(const std::string& text, SelectionMethod* out) {
  for (auto m : {SelectionMethod::kAll, SelectionMethod::kCorrelationClusters, SelectionMethod::kLasso})
    if (text == SelectionMethodName(m)) {
      *out = m;
      return true;
    }
  if (text == "clusters" || text == "correlation") {
    *out = SelectionMethod::kCorrelationClusters;
    return true;
  }
  return false;
}

bool SensorSelectionOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (max_sensors < 1) return fail("max_sensors must be >= 1");
  if (!(lasso_lambda_min_ratio > 0 && lasso_lambda_min_ratio < 1)) return fail("lasso_lambda_min_ratio must be in (0, 1)");
  if (lasso_path_steps < 2) return fail("lasso_path_steps must be >= 2");
  if (lasso_max_sweeps < 1) return fail("lasso_max_sweeps must be >= 1");
  if (!(lasso_tolerance > 0)) return fail("lasso_tolerance must be > 0");
  return true;
}

namespace {

// Coordinate descent in covariance form (glmnet's "covariance updates"): with the Gram matrix
// g = X'X/n and c = X'y/n each coordinate update costs O(p) instead of O(n), which makes a whole
// lambda path on a long recording (n >> p) cheap. `grad` = X'(y - X beta)/n is kept up to date.
int LassoGram(const Eigen::MatrixXd& g, const Eigen::VectorXd& c, double lambda, int max_sweeps, double tolerance,
              Eigen::VectorXd* beta) {
  const Eigen::Index p = g.cols();
  if (beta->size() != p) *beta = Eigen::VectorXd::Zero(p);
  Eigen::VectorXd grad = c - g * (*beta);
  int sweep = 0;
  for (; sweep < max_sweeps; ++sweep) {
    double max_change = 0;
    for (Eigen::Index j = 0; j < p; ++j) {
      const double gjj = g(j, j);
      if (gjj <= 0) continue;
      const double old = (*beta)(j);
      const double rho = grad(j) + gjj * old;
      const double shrunk = std::copysign(std::max(std::abs(rho) - lambda, 0.0), rho) / gjj;
      if (shrunk != old) {
        grad -= g.col(j) * (shrunk - old);
        (*beta)(j) = shrunk;
        max_change = std::max(max_change, std::abs(shrunk - old));
      }
    }
    if (max_change < tolerance) break;
  }
  return sweep + 1;
}

}  // namespace

int LassoCoordinateDescent(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double lambda, int max_sweeps,
                           double tolerance, Eigen::VectorXd* beta) {
  const double n = static_cast<double>(x.rows());
  const Eigen::MatrixXd g = x.transpose() * x / n;
  const Eigen::VectorXd c = x.transpose() * y / n;
  return LassoGram(g, c, lambda, max_sweeps, tolerance, beta);
}

SensorSelection SelectSensors(const Eigen::MatrixXd& t, const Eigen::VectorXd& y, const SensorSelectionOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("sensor selection options", why);
  if (t.rows() != y.size() || t.rows() < 3)
    throw InputError("sensor selection", "need at least 3 samples with one error value per temperature row");
  SensorSelection sel;
  sel.method = o.method;
  const auto p = static_cast<int>(t.cols());
  const Eigen::MatrixXd z = Standardise(t);
  const double n = static_cast<double>(t.rows());
  Eigen::VectorXd yc = y.array() - y.mean();
  const double ysd = std::sqrt(yc.squaredNorm() / n);
  sel.abs_correlation.assign(static_cast<std::size_t>(p), 0.0);
  if (ysd > 0)
    for (int j = 0; j < p; ++j) sel.abs_correlation[static_cast<std::size_t>(j)] = std::abs(z.col(j).dot(yc) / n / ysd);
  std::vector<int> all(static_cast<std::size_t>(p));
  std::iota(all.begin(), all.end(), 0);

  switch (o.method) {
    case SelectionMethod::kAll:
      sel.sensors = all;
      return sel;
    case SelectionMethod::kCorrelationClusters: {
      const Eigen::MatrixXd r = (z.transpose() * z) / n;  // correlation matrix
      std::vector<std::vector<int>> clusters;
      for (int j = 0; j < p; ++j) clusters.push_back({j});
      auto dist = [&](const std::vector<int>& a, const std::vector<int>& b) {
        double s = 0;
        for (int i : a)
          for (int j : b) s += 1.0 - std::abs(r(i, j));
        return s / static_cast<double>(a.size() * b.size());
      };
      while (static_cast<int>(clusters.size()) > o.max_sensors) {
        std::size_t ba = 0, bb = 1;
        double best = 1e300;
        for (std::size_t a = 0; a < clusters.size(); ++a)
          for (std::size_t b = a + 1; b < clusters.size(); ++b) {
            const double d = dist(clusters[a], clusters[b]);
            if (d < best) {
              best = d;
              ba = a;
              bb = b;
            }
          }
        clusters[ba].insert(clusters[ba].end(), clusters[bb].begin(), clusters[bb].end());
        clusters.erase(clusters.begin() + static_cast<long>(bb));
      }
      sel.cluster.assign(static_cast<std::size_t>(p), 0);
      for (std::size_t c = 0; c < clusters.size(); ++c) {
        int pick = clusters[c].front();
        for (int j : clusters[c]) {
          sel.cluster[static_cast<std::size_t>(j)] = static_cast<int>(c);
          if (sel.abs_correlation[static_cast<std::size_t>(j)] > sel.abs_correlation[static_cast<std::size_t>(pick)]) pick = j;
        }
        sel.sensors.push_back(pick);
      }
      sel.sensors = OrderByScore(sel.sensors, sel.abs_correlation);
      return sel;
    }
    case SelectionMethod::kLasso: {
      Eigen::VectorXd beta = Eigen::VectorXd::Zero(p);
      const double lambda_max = (z.transpose() * yc).cwiseAbs().maxCoeff() / n;
      if (!(lambda_max > 0)) {  // nothing correlates: fall back to correlation order
        sel.sensors = OrderByScore(all, sel.abs_correlation);
        sel.sensors.resize(static_cast<std::size_t>(std::min(o.max_sensors, p)));
        return sel;
      }
      std::vector<double> score(static_cast<std::size_t>(p), 0.0);
      const Eigen::MatrixXd gram = z.transpose() * z / n;
      const Eigen::VectorXd zy = z.transpose() * yc / n;
      for (int step = 1; step <= o.lasso_path_steps; ++step) {
        const double frac = static_cast<double>(step) / o.lasso_path_steps;
        const double lambda = lambda_max * std::pow(o.lasso_lambda_min_ratio, frac);
        LassoGram(gram, zy, lambda, o.lasso_max_sweeps, o.lasso_tolerance * std::max(ysd, 1e-12), &beta);
        int nonzero = 0;
        for (int j = 0; j < p; ++j) nonzero += beta(j) != 0 ? 1 : 0;
        sel.lasso_lambda = lambda;
        if (nonzero >= o.max_sensors || step == o.lasso_path_steps) break;
      }
      std::vector<int> active;
      for (int j = 0; j < p; ++j) {
        score[static_cast<std::size_t>(j)] = std::abs(beta(j));
        if (beta(j) != 0) active.push_back(j);
      }
      active = OrderByScore(active, score);
      if (static_cast<int>(active.size()) > o.max_sensors) active.resize(static_cast<std::size_t>(o.max_sensors));
      if (active.empty()) active.push_back(OrderByScore(all, sel.abs_correlation).front());
      sel.sensors = active;
      return sel;
    }
  }
  return sel;
}

}  // namespace trueaxis::thermal
