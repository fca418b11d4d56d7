#include "budget_slam/graph/IncrementalOrdering.h"

#include <map>
#include <stdexcept>

namespace budget_slam::graph {

namespace {
bool samePose(const VariableKey& v) { return v.kind == VariableKey::Kind::Pose; }
}  // namespace

bool IncrementalOrdering::fresh(const FactorGraph& graph, const Eigen::SparseMatrix<double>& H,
                                SparseCholesky* chol) {
  ++fresh_;
  if (!chol->factorize(H, 0, &graph.variableStarts())) return false;
  // The scalar ordering back to variables: a variable's first column stands for it (CHOLMOD may
  // split a variable's columns; keeping the order of first columns loses nothing essential).
  std::map<int, VariableKey> at_column;
  for (const auto& [s, p] : graph.poses())
    at_column[graph.column(VariableKey::pose(s))] = VariableKey::pose(s);
  for (const auto& [id, l] : graph.landmarks())
    at_column[graph.column(VariableKey::landmark(id))] = VariableKey::landmark(id);
  order_.clear();
  for (int c : chol->ordering()) {
    auto it = at_column.find(c);
    if (it != at_column.end()) order_.push_back(it->second);
  }
  fresh_ratio_ = chol->analysedNonZeros() / static_cast<double>(H.nonZeros());
  return true;
}

bool IncrementalOrdering::factorize(const FactorGraph& graph, const Eigen::SparseMatrix<double>& H,
                                    SparseCholesky* chol) {
  const std::uint64_t version = graph.structureVersion() + 1;
  const bool same_chol = chol == chol_;
  chol_ = chol;
  if (refresh_fill_ <= 0) {  // the batch path: CHOLMOD's analysis whenever the structure changed
    version_ = version;
    return chol->factorize(H, version, &graph.variableStarts());
  }
  if (same_chol && version == version_ && chol->size() == H.rows()) {
    ++reused_;
    if (chol->refactorize(H)) return true;
    version_ = 0;
    return false;
  }
  version_ = version;
  if (order_.empty() || !same_chol) return fresh(graph, H, chol);
  // Kept variables in their order, then the new ones.
  std::vector<VariableKey> order;
  order.reserve(order_.size() + 16);
  std::vector<int> perm;
  perm.reserve(static_cast<std::size_t>(H.rows()));
  std::vector<char> used(static_cast<std::size_t>(H.rows()), 0);
  auto place = [&](const VariableKey& v) {
    const int c = graph.column(v);
    for (std::size_t t = 0; t < v.dim(); ++t) {
      perm.push_back(c + static_cast<int>(t));
      used[static_cast<std::size_t>(c) + t] = 1;
    }
    order.push_back(v);
  };
  for (const VariableKey& v : order_) {
    const bool exists = samePose(v) ? graph.hasPose(static_cast<StepIndex>(v.id))
                                    : graph.hasLandmark(static_cast<LandmarkId>(v.id));
    if (exists) place(v);
  }
  for (const auto& [id, l] : graph.landmarks())
    if (!used[static_cast<std::size_t>(graph.column(VariableKey::landmark(id)))])
      place(VariableKey::landmark(id));
  for (const auto& [s, p] : graph.poses())
    if (!used[static_cast<std::size_t>(graph.column(VariableKey::pose(s)))])
      place(VariableKey::pose(s));
  if (perm.size() != static_cast<std::size_t>(H.rows()))
    throw std::logic_error("IncrementalOrdering: ordering does not cover the graph");
  ++reused_;
  if (!chol->factorizeOrdered(H, perm, /*simplicial=*/false)) {
    version_ = 0;
    return false;
  }
  order_ = std::move(order);
  const double ratio = chol->analysedNonZeros() / static_cast<double>(H.nonZeros());
  if (ratio > refresh_fill_ * fresh_ratio_) return fresh(graph, H, chol);
  return true;
}

}  // namespace budget_slam::graph
