#pragma once
// Temperature-sensitive point selection: pick a few sensors out of many
// (docs/thermal-models.md "Sensor selection").
//
// kLasso is the default: on fl_thermal it validated better than the
// clusters on 4 of 5 channels (bench/results/thermal.md).
// kCorrelationClusters: sensors are clustered by agglomerative
//   average-linkage clustering with distance 1 - |r(Ti, Tj)| until
//   max_sensors clusters remain (sensors that move together carry the same
//   information and make a regression ill-conditioned); from each cluster the
//   sensor with the largest |r(Ti, error)| is chosen. Result ordered by
//   |r(Ti, error)|, largest first.
// kLasso: LASSO on standardised temperatures and the centred error, solved
//   by cyclic coordinate descent along a geometric lambda path from
//   lambda_max = max|X'y|/n down to lambda_min_ratio * lambda_max (warm
//   starts); the first lambda with >= max_sensors non-zero coefficients
//   gives the selection (largest |coefficient| first, at most max_sensors).
// kAll: every sensor, in series order.
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace trueaxis::thermal {

enum class SelectionMethod { kAll, kCorrelationClusters, kLasso };
const char* SelectionMethodName(SelectionMethod m);
bool ParseSelectionMethod(const std::string& text, SelectionMethod* out);

struct SensorSelectionOptions {
  SelectionMethod method = SelectionMethod::kLasso;
  int max_sensors = 4;
  double lasso_lambda_min_ratio = 1e-4;
  int lasso_path_steps = 60;
  int lasso_max_sweeps = 2000;
  double lasso_tolerance = 1e-9;

  bool IsValid(std::string* why) const;
};

struct SensorSelection {
  SelectionMethod method = SelectionMethod::kAll;
  std::vector<int> sensors;                 // column indices into the temperature matrix
  std::vector<double> abs_correlation;      // |r(T_sensor, error)| for every column
  std::vector<int> cluster;                 // cluster id per column (correlation method; else empty)
  double lasso_lambda = 0;                  // lambda that gave the selection (LASSO)
};

// temperatures_c: rows = samples, cols = sensors (no NaN); error_um: one value per row.
SensorSelection SelectSensors(const Eigen::MatrixXd& temperatures_c, const Eigen::VectorXd& error_um,
                              const SensorSelectionOptions& options);

// LASSO by cyclic coordinate descent: minimises 1/(2n)|y - Xb|^2 + lambda |b|_1
// for standardised columns of X (unit variance) and centred y. `beta` is the
// warm start and the result. Returns the number of sweeps used.
int LassoCoordinateDescent(const Eigen::MatrixXd& x_std, const Eigen::VectorXd& y_centred, double lambda,
                           int max_sweeps, double tolerance, Eigen::VectorXd* beta);

}  // namespace trueaxis::thermal
