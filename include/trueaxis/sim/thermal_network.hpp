#pragma once
// ThermalNetwork: a lumped thermal RC network (capacities at nodes,
// conductances on edges, heat sources at nodes, boundary nodes held at a given
// temperature). Integrated explicitly, sub-stepped below the stability limit
// (dt ≤ 0.5·min C_i/ΣG_i), so any step the caller asks for is stable.
#include <cstddef>
#include <string>
#include <vector>

namespace trueaxis::sim {

class ThermalNetwork {
 public:
  // capacity_j_per_k <= 0 makes a boundary node (temperature set by the caller).
  std::size_t AddNode(std::string name, double capacity_j_per_k, double temp_c);
  std::size_t AddEdge(std::size_t a, std::size_t b, double conductance_w_per_k);

  void SetConductance(std::size_t edge, double w_per_k) { edges_[edge].g = w_per_k; }
  void SetHeat(std::size_t node, double watts) { nodes_[node].q = watts; }
  void SetTemperature(std::size_t node, double temp_c) { nodes_[node].t = temp_c; }
  void SetAllTemperatures(double temp_c);
  double Temperature(std::size_t node) const { return nodes_[node].t; }
  const std::string& NodeName(std::size_t node) const { return nodes_[node].name; }
  std::size_t NodeCount() const { return nodes_.size(); }
  // Index of a node by name, or NodeCount() when absent.
  std::size_t FindNode(const std::string& name) const;

  // Advances by dt_s (sub-stepping as needed).
  void Step(double dt_s);
  // Largest stable explicit step for the current conductances.
  double StableStepS() const;

 private:
  struct Node { std::string name; double c, t, q; };
  struct Edge { std::size_t a, b; double g; };
  std::vector<Node> nodes_;
  std::vector<Edge> edges_;
  std::vector<double> flow_;  // scratch, sized with nodes_
  mutable std::vector<double> g_sum_;  // scratch for StableStepS
};

}  // namespace trueaxis::sim
