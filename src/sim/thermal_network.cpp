#include "trueaxis/sim/thermal_network.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trueaxis::sim {

std::size_t ThermalNetwork::AddNode(std::string name, double capacity_j_per_k, double temp_c) {
  nodes_.push_back({std::move(name), capacity_j_per_k, temp_c, 0.0});
  flow_.resize(nodes_.size());
  return nodes_.size() - 1;
}

std::size_t ThermalNetwork::AddEdge(std::size_t a, std::size_t b, double g) {
  edges_.push_back({a, b, g});
  return edges_.size() - 1;
}

void ThermalNetwork::SetAllTemperatures(double temp_c) {
  for (auto& n : nodes_) n.t = temp_c;
}

std::size_t ThermalNetwork::FindNode(const std::string& name) const {
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].name == name) return i;
  return nodes_.size();
}

double ThermalNetwork::StableStepS() const {
  std::vector<double>& g_sum = g_sum_;
  g_sum.assign(nodes_.size(), 0.0);
  for (const auto& e : edges_) {
    g_sum[e.a] += e.g;
    g_sum[e.b] += e.g;
  }
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].c > 0 && g_sum[i] > 0) best = std::min(best, nodes_[i].c / g_sum[i]);
  // Forward Euler is stable (and monotone, no overshoot) for dt ≤ C/ΣG; keep a margin.
  return 0.5 * best;
}

void ThermalNetwork::Step(double dt_s) {
  if (dt_s <= 0) return;
  const double stable = StableStepS();
  const int n_sub = std::max(1, static_cast<int>(std::ceil(dt_s / stable)));
  const double h = dt_s / n_sub;
  for (int s = 0; s < n_sub; ++s) {
    for (std::size_t i = 0; i < nodes_.size(); ++i) flow_[i] = nodes_[i].q;
    for (const auto& e : edges_) {
      const double q = e.g * (nodes_[e.a].t - nodes_[e.b].t);
      flow_[e.a] -= q;
      flow_[e.b] += q;
    }
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (nodes_[i].c > 0) nodes_[i].t += h * flow_[i] / nodes_[i].c;
  }
}

}  // namespace trueaxis::sim
