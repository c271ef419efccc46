#include "trueaxis/thermal/pso_bp_network.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "json_fields.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::thermal {
namespace {

constexpr int kMaxNetworkInputs = 32;

inline double LogSig(double a) { return 1.0 / (1.0 + std::exp(-a)); }

double ScaleInput(double v, double lo, double hi) { return hi > lo ? 2.0 * (v - lo) / (hi - lo) - 1.0 : 0.0; }

double ScaleTarget(const PsoBpChannel& n, double y_um) {
  const double span = n.target_max_um - n.target_min_um;
  if (!(span > 0)) return 0.5 * (n.target_low + n.target_high);
  return n.target_low + (y_um - n.target_min_um) / span * (n.target_high - n.target_low);
}

double UnscaleTarget(const PsoBpChannel& n, double o) {
  const double span = n.target_max_um - n.target_min_um;
  if (!(span > 0)) return n.target_min_um;
  return n.target_min_um + (o - n.target_low) / (n.target_high - n.target_low) * span;
}

// Batch forward pass over scaled inputs X (inputs x samples) for the parameter
// vector p in the seed's layout; returns the sum of squared errors against the
// scaled targets t.
double BatchSse(const Eigen::MatrixXd& x, const Eigen::RowVectorXd& t, const double* p, int inputs, int hidden) {
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> w1(p, hidden, inputs);
  Eigen::Map<const Eigen::VectorXd> b1(p + hidden * inputs, hidden);
  Eigen::Map<const Eigen::RowVectorXd> w2(p + hidden * inputs + hidden, hidden);
  const double b2 = p[hidden * inputs + 2 * hidden];
  Eigen::MatrixXd h = (w1 * x).colwise() + b1;
  h = h.unaryExpr([](double a) { return LogSig(a); });
  Eigen::RowVectorXd o = ((w2 * h).array() + b2).unaryExpr([](double a) { return LogSig(a); });
  return (o - t).squaredNorm();
}

}  // namespace

bool PsoBpOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (temperature_inputs < 0 || temperature_inputs > kMaxNetworkInputs - 1)
    return fail(fmt::format("temperature_inputs must be in [0, {}]", kMaxNetworkInputs - 1));
  if (hidden_units < 1 || hidden_units > 1000) return fail("hidden_units must be in [1, 1000]");
  if (!(learning_rate > 0) || !std::isfinite(learning_rate)) return fail("learning_rate must be > 0");
  if (epochs < 0) return fail("epochs must be >= 0");
  if (particles < 1) return fail("particles must be >= 1");
  if (pso_iterations < 0) return fail("pso_iterations must be >= 0");
  if (!(c1 >= 0 && c2 >= 0 && inertia >= 0)) return fail("c1, c2 and inertia must be >= 0");
  if (!(velocity_limit > 0)) return fail("velocity_limit must be > 0");
  if (!(initial_position_range > 0)) return fail("initial_position_range must be > 0");
  if (pso_max_samples < 1) return fail("pso_max_samples must be >= 1");
  if (!(target_low > 0 && target_low < target_high && target_high < 1))
    return fail("targets must scale into a range inside the sigmoid's (0, 1): 0 < target_low < target_high < 1");
  return true;
}

std::vector<double> PsoBpChannel::Parameters() const {
  std::vector<double> p = w_hidden;
  p.insert(p.end(), b_hidden.begin(), b_hidden.end());
  p.insert(p.end(), w_output.begin(), w_output.end());
  p.push_back(b_output);
  return p;
}

void PsoBpChannel::SetParameters(const std::vector<double>& p) {
  const int in = NetworkInputs();
  auto it = p.begin();
  w_hidden.assign(it, it + hidden * in);
  it += hidden * in;
  b_hidden.assign(it, it + hidden);
  it += hidden;
  w_output.assign(it, it + hidden);
  it += hidden;
  b_output = *it;
}

double EvaluateNetwork(const PsoBpChannel& n, std::span<const double> temperatures_c, double position_mm) {
  std::array<double, kMaxNetworkInputs> x{};
  const int in = n.NetworkInputs();
  for (std::size_t i = 0; i < n.inputs.size(); ++i)
    x[i] = ScaleInput(temperatures_c[static_cast<std::size_t>(n.inputs[i])], n.input_min[i], n.input_max[i]);
  if (n.uses_position) x[n.inputs.size()] = ScaleInput(position_mm, n.input_min.back(), n.input_max.back());
  double a_out = n.b_output;
  for (int h = 0; h < n.hidden; ++h) {
    double a = n.b_hidden[static_cast<std::size_t>(h)];
    for (int i = 0; i < in; ++i) a += n.w_hidden[static_cast<std::size_t>(h * in + i)] * x[static_cast<std::size_t>(i)];
    a_out += n.w_output[static_cast<std::size_t>(h)] * LogSig(a);
  }
  return UnscaleTarget(n, LogSig(a_out));
}

PsoBpNetworkModel::PsoBpNetworkModel(std::vector<std::string> sensors, std::vector<PsoBpChannel> channels,
                                     PsoBpOptions options)
    : sensors_(std::move(sensors)), channels_(std::move(channels)), options_(options) {
  for (const auto& c : channels_) channel_names_.push_back(c.name);
}

bool PsoBpNetworkModel::UsesPosition() const {
  for (const auto& c : channels_)
    if (c.uses_position) return true;
  return false;
}

void PsoBpNetworkModel::Predict(const ThermalSample& sample, std::span<double> out_um) const {
  for (std::size_t c = 0; c < channels_.size(); ++c)
    out_um[c] = EvaluateNetwork(channels_[c], sample.temperatures_c, sample.position_mm);
}

nlohmann::json PsoBpNetworkModel::ToJson() const {
  nlohmann::json nets = nlohmann::json::array();
  for (const auto& c : channels_) {
    std::vector<std::string> names;
    for (int i : c.inputs) names.push_back(sensors_[static_cast<std::size_t>(i)]);
    nets.push_back({{"name", c.name},
                    {"sensors", names},
                    {"uses_position", c.uses_position},
                    {"hidden", c.hidden},
                    {"input_min", c.input_min},
                    {"input_max", c.input_max},
                    {"target_min_um", c.target_min_um},
                    {"target_max_um", c.target_max_um},
                    {"target_low", c.target_low},
                    {"target_high", c.target_high},
                    {"parameters", c.Parameters()}});
  }
  const PsoBpOptions& o = options_;
  return {{"kind", "pso_bp"},
          {"sensors", sensors_},
          {"training",
           {{"learning_rate", o.learning_rate}, {"epochs", o.epochs}, {"particles", o.particles},
            {"pso_iterations", o.pso_iterations}, {"c1", o.c1}, {"c2", o.c2}, {"inertia", o.inertia},
            {"velocity_limit", o.velocity_limit}, {"bp_shuffle", o.bp_shuffle}, {"seed", o.seed}}},
          {"channels", nets}};
}

std::string PsoBpNetworkModel::Describe() const {
  std::string out;
  for (const auto& c : channels_) {
    std::vector<std::string> names;
    for (int i : c.inputs) names.push_back(sensors_[static_cast<std::size_t>(i)]);
    if (c.uses_position) names.push_back("position_mm");
    out += fmt::format("{}: {}-{}-1 log-sigmoid network on [{}], {} parameters\n", c.name, c.NetworkInputs(), c.hidden,
                       fmt::join(names, ", "), c.Parameters().size());
  }
  return out;
}

PsoBpNetworkModel PsoBpNetworkModel::FromJson(const nlohmann::json& doc, const std::string& source,
                                              const std::string& path) {
  detail::JsonFields f(source);
  std::vector<std::string> sensors = f.Strings(doc, path, "sensors");
  PsoBpOptions options;
  if (doc.contains("training") && doc["training"].is_object()) {
    const auto& t = doc["training"];
    const std::string tp = f.Join(path, "training");
    options.learning_rate = f.Number(t, tp, "learning_rate");
    options.epochs = f.Int(t, tp, "epochs", 0, 100000000);
    options.particles = f.Int(t, tp, "particles", 1, 100000000);
  }
  const auto& arr = f.Array(doc, path, "channels");
  std::vector<PsoBpChannel> channels;
  for (std::size_t k = 0; k < arr.size(); ++k) {
    const std::string p = f.Index(f.Join(path, "channels"), k);
    const auto& j = arr[k];
    PsoBpChannel c;
    c.name = f.String(j, p, "name");
    std::vector<std::string> names;
    if (!f.Get(j, p, "sensors").empty()) names = f.Strings(j, p, "sensors");
    const auto& up = f.Get(j, p, "uses_position");
    if (!up.is_boolean()) f.Fail(f.Join(p, "uses_position"), "expected true or false");
    c.uses_position = up.get<bool>();
    c.hidden = f.Int(j, p, "hidden", 1, 1000);
    for (const auto& n : names) {
      auto it = std::find(sensors.begin(), sensors.end(), n);
      if (it == sensors.end()) f.Fail(f.Join(p, "sensors"), "'" + n + "' is not in the model's sensors list");
      c.inputs.push_back(static_cast<int>(it - sensors.begin()));
    }
    if (c.NetworkInputs() < 1 || c.NetworkInputs() > kMaxNetworkInputs)
      f.Fail(f.Join(p, "sensors"), fmt::format("network needs 1..{} inputs", kMaxNetworkInputs));
    c.input_min = f.Numbers(j, p, "input_min");
    c.input_max = f.Numbers(j, p, "input_max");
    if (static_cast<int>(c.input_min.size()) != c.NetworkInputs() || c.input_max.size() != c.input_min.size())
      f.Fail(f.Join(p, "input_min"), fmt::format("need {} values (one per network input)", c.NetworkInputs()));
    c.target_min_um = f.Number(j, p, "target_min_um");
    c.target_max_um = f.Number(j, p, "target_max_um");
    c.target_low = f.Number(j, p, "target_low");
    c.target_high = f.Number(j, p, "target_high");
    if (!(c.target_low > 0 && c.target_low < c.target_high && c.target_high < 1))
      f.Fail(f.Join(p, "target_low"), "need 0 < target_low < target_high < 1");
    std::vector<double> params = f.Numbers(j, p, "parameters");
    const int dim = c.NetworkInputs() * c.hidden + 2 * c.hidden + 1;
    if (static_cast<int>(params.size()) != dim)
      f.Fail(f.Join(p, "parameters"), fmt::format("{} values, a {}-{}-1 network has {}", params.size(),
                                                  c.NetworkInputs(), c.hidden, dim));
    c.SetParameters(params);
    channels.push_back(std::move(c));
  }
  return PsoBpNetworkModel(std::move(sensors), std::move(channels), options);
}

std::string PsoBpFitSummary::BriefReport() const {
  std::string out;
  for (const auto& c : channels)
    out += fmt::format(
        "{}: {} parameters; PSO best SSE {:.6g} -> {:.6g} ({} iterations, {} rows); all {} rows: {:.6g} after PSO, "
        "{:.6g} after BP; "
        "train RMSE {:.4g} um, max |e| {:.4g} um\n",
        c.name, c.dimension, c.pso_best_sse.empty() ? 0.0 : c.pso_best_sse.front(),
        c.pso_best_sse.empty() ? 0.0 : c.pso_best_sse.back(), c.pso_best_sse.empty() ? 0 : c.pso_best_sse.size() - 1,
        c.pso_samples, c.bp_samples, c.sse_after_pso, c.sse_after_bp, c.train_rmse_um, c.train_max_abs_um);
  return out;
}

PsoBpNetworkModel FitPsoBpNetwork(const ThermalSeries& s, const PsoBpOptions& o, PsoBpFitSummary* summary) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("pso_bp options", why);
  const Eigen::Index n = s.Rows();
  if (n < 2) throw InputError(s.source, 0, "", "need at least 2 rows to train a network");
  if (s.temperatures_c.hasNaN() || s.errors_um.hasNaN())
    throw InputError(s.source, 0, "", "series holds missing values; clean it first (CleanSeries)");
  const bool use_position = o.position == PsoBpOptions::Position::kYes ||
                            (o.position == PsoBpOptions::Position::kAuto && s.has_position);
  if (use_position && !s.has_position)
    throw InputError(s.source, 0, "position_mm", "the network is to use the position, but the series has no position_mm column");
  const int temp_inputs = std::min<int>(o.temperature_inputs, static_cast<int>(s.temperatures_c.cols()));
  if (temp_inputs + (use_position ? 1 : 0) < 1)
    throw InputError("pso_bp options", "the network has no input: give temperature_inputs >= 1 or use the position");

  std::vector<std::string> used;
  std::vector<PsoBpChannel> channels;
  if (summary) summary->channels.clear();
  for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
    const Eigen::VectorXd y = s.errors_um.col(c);
    PsoBpChannel net;
    net.name = s.error_names[static_cast<std::size_t>(c)];
    net.hidden = o.hidden_units;
    net.uses_position = use_position;
    net.target_low = o.target_low;
    net.target_high = o.target_high;
    std::vector<int> columns;  // series temperature columns
    if (temp_inputs > 0) {
      SensorSelectionOptions so = o.selection;
      so.max_sensors = temp_inputs;
      columns = SelectSensors(s.temperatures_c, y, so).sensors;
    }
    for (int col : columns) {
      const std::string& name = s.temperature_names[static_cast<std::size_t>(col)];
      auto it = std::find(used.begin(), used.end(), name);
      if (it == used.end()) {
        used.push_back(name);
        it = used.end() - 1;
      }
      net.inputs.push_back(static_cast<int>(it - used.begin()));
    }
    const int in = net.NetworkInputs();
    // Raw inputs (inputs x n) and their training range.
    Eigen::MatrixXd raw(in, n);
    for (std::size_t i = 0; i < columns.size(); ++i) raw.row(static_cast<Eigen::Index>(i)) = s.temperatures_c.col(columns[i]).transpose();
    if (use_position)
      for (Eigen::Index r = 0; r < n; ++r) raw(in - 1, r) = s.position_mm[static_cast<std::size_t>(r)];
    Eigen::MatrixXd x(in, n);
    for (int i = 0; i < in; ++i) {
      net.input_min.push_back(raw.row(i).minCoeff());
      net.input_max.push_back(raw.row(i).maxCoeff());
      for (Eigen::Index r = 0; r < n; ++r) x(i, r) = ScaleInput(raw(i, r), net.input_min.back(), net.input_max.back());
    }
    net.target_min_um = y.minCoeff();
    net.target_max_um = y.maxCoeff();
    Eigen::RowVectorXd t(n);
    for (Eigen::Index r = 0; r < n; ++r) t(r) = ScaleTarget(net, y(r));

    // PSO fitness rows: evenly spaced subset on long series.
    const Eigen::Index m = std::min<Eigen::Index>(n, o.pso_max_samples);
    Eigen::MatrixXd xp(in, m);
    Eigen::RowVectorXd tp(m);
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Index r = m == n ? k : (k * (n - 1)) / std::max<Eigen::Index>(m - 1, 1);
      xp.col(k) = x.col(r);
      tp(k) = t(r);
    }

    // --- PSO ---
    const int dim = o.Dimension(in);
    std::mt19937_64 rng(o.seed + static_cast<std::uint64_t>(c) * 0x9E3779B97F4A7C15ULL);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    auto uniform = [&](double a, double b) { return a + (b - a) * u01(rng); };
    Eigen::MatrixXd pos(dim, o.particles), vel(dim, o.particles);
    for (int k = 0; k < o.particles; ++k)
      for (int d = 0; d < dim; ++d) {
        pos(d, k) = uniform(-o.initial_position_range, o.initial_position_range);
        vel(d, k) = uniform(-o.velocity_limit, o.velocity_limit);
      }
    Eigen::MatrixXd pbest = pos;
    Eigen::VectorXd pbest_sse(o.particles);
    for (int k = 0; k < o.particles; ++k) pbest_sse(k) = BatchSse(xp, tp, pos.col(k).data(), in, o.hidden_units);
    Eigen::Index gi = 0;
    double gbest_sse = pbest_sse.minCoeff(&gi);
    Eigen::VectorXd gbest = pbest.col(gi);
    PsoBpChannelSummary sum;
    sum.name = net.name;
    sum.dimension = dim;
    sum.pso_samples = static_cast<int>(m);
    sum.bp_samples = static_cast<int>(n);
    sum.pso_best_sse.push_back(gbest_sse);
    for (int it = 0; it < o.pso_iterations; ++it) {
      for (int k = 0; k < o.particles; ++k) {
        for (int d = 0; d < dim; ++d) {
          double v = o.inertia * vel(d, k) + o.c1 * u01(rng) * (pbest(d, k) - pos(d, k)) +
                     o.c2 * u01(rng) * (gbest(d) - pos(d, k));
          vel(d, k) = std::clamp(v, -o.velocity_limit, o.velocity_limit);
          pos(d, k) += vel(d, k);
        }
        const double sse = BatchSse(xp, tp, pos.col(k).data(), in, o.hidden_units);
        if (sse < pbest_sse(k)) {
          pbest_sse(k) = sse;
          pbest.col(k) = pos.col(k);
          if (sse < gbest_sse) {
            gbest_sse = sse;
            gbest = pos.col(k);
          }
        }
      }
      sum.pso_best_sse.push_back(gbest_sse);
    }
    sum.sse_after_pso = BatchSse(x, t, gbest.data(), in, o.hidden_units);

    // --- BP (online, training order, no momentum) ---
    const int hid = o.hidden_units;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> w1 =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(gbest.data(), hid, in);
    Eigen::VectorXd b1 = gbest.segment(hid * in, hid);
    Eigen::VectorXd w2 = gbest.segment(hid * in + hid, hid);
    double b2 = gbest(hid * in + 2 * hid);
    Eigen::VectorXd h(hid), delta_h(hid);
    std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
    for (Eigen::Index r = 0; r < n; ++r) order[static_cast<std::size_t>(r)] = r;
    for (int epoch = 0; epoch < o.epochs; ++epoch) {
      if (o.bp_shuffle)  // Fisher-Yates with our own draws: same sequence on every platform
        for (std::size_t i = order.size(); i > 1; --i)
          std::swap(order[i - 1], order[static_cast<std::size_t>(u01(rng) * static_cast<double>(i)) % i]);
      for (Eigen::Index r : order) {
        h = (w1 * x.col(r) + b1).unaryExpr([](double a) { return LogSig(a); });
        const double out = LogSig(w2.dot(h) + b2);
        const double delta_o = (out - t(r)) * out * (1.0 - out);
        delta_h = (w2 * delta_o).cwiseProduct(h.cwiseProduct((1.0 - h.array()).matrix()));
        w2 -= o.learning_rate * delta_o * h;
        b2 -= o.learning_rate * delta_o;
        w1 -= o.learning_rate * delta_h * x.col(r).transpose();
        b1 -= o.learning_rate * delta_h;
      }
    }
    std::vector<double> params(w1.data(), w1.data() + hid * in);
    params.insert(params.end(), b1.data(), b1.data() + hid);
    params.insert(params.end(), w2.data(), w2.data() + hid);
    params.push_back(b2);
    net.SetParameters(params);
    sum.sse_after_bp = BatchSse(x, t, params.data(), in, hid);
    double sq = 0, mx = 0;
    for (Eigen::Index r = 0; r < n; ++r) {
      const double e = y(r) - UnscaleTarget(net, [&] {
                         const Eigen::VectorXd hh = (w1 * x.col(r) + b1).unaryExpr([](double a) { return LogSig(a); });
                         return LogSig(w2.dot(hh) + b2);
                       }());
      sq += e * e;
      mx = std::max(mx, std::abs(e));
    }
    sum.train_rmse_um = std::sqrt(sq / static_cast<double>(n));
    sum.train_max_abs_um = mx;
    if (summary) summary->channels.push_back(std::move(sum));
    channels.push_back(std::move(net));
  }
  return PsoBpNetworkModel(std::move(used), std::move(channels), o);
}

}  // namespace trueaxis::thermal
