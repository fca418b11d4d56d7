#pragma once
// The held factor's bookkeeping (IncrementalFactorization, docs/GRAPH.md "Held factor"): which
// variables and factors it holds, each variable's rows and linearization point, each factor's
// current linearization. No arithmetic on H or L here.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "budget_slam/graph/FactorGraph.h"
#include "budget_slam/graph/GraphFactor.h"

namespace budget_slam::graph::held {

/// A variable of the held factor: its rows of H and its linearization point.
struct Var {
  VariableKey key;
  int row = -1;  ///< first row of H, its position in the elimination order; -1 until placed
  int dim = 0;
  Eigen::Vector3d lin = Eigen::Vector3d::Zero();
  std::vector<int> factors;  ///< indices into HeldRecords::factors
  bool alive = false;
  bool dying = false;  ///< removed by the changes being folded in
  /// The change count (IncrementalFactorization's) when a change last touched it: a fresh
  /// ordering puts the recently touched variables last.
  std::uint64_t touched = 0;
};

/// A factor folded into H, with the rows it put there and where its entries of H are.
struct Held {
  GraphFactor f;
  std::array<int, 2> var{{-1, -1}};
  LinearFactor lin;
  std::vector<int> hpos;           ///< index into Hx of each of its entries
  std::vector<std::uint8_t> hidx;  ///< ... and of the value in A^T A (column-major 6 x 6)
  bool alive = false;
  bool added = false;  ///< added since the last change was folded in (not in H yet)
};

/// Rows to add to or take from H: a factor's linearization on its variables' rows.
struct Piece {
  LinearFactor lin;
  int nvar = 0;
  std::array<int, 2> row{{-1, -1}};
  std::array<int, 2> dim{{0, 0}};
};

/// Variables by VariableIndex and factors by slot, mirroring one FactorGraph.
/// Invariants: a live factor's variables are alive and list it in `factors`; `factor_of` maps
/// exactly the live factors' ids; `factor_count` counts them.
struct HeldRecords {
  std::vector<Var> vars;  ///< by VariableIndex (FactorGraph::variableIndices)
  std::vector<Held> factors;
  std::vector<int> free_factors;
  std::unordered_map<FactorId, int> factor_of;
  std::size_t factor_count = 0;

  Var& var(VariableIndex v) {
    if (v >= vars.size() || !vars[v].alive)
      throw std::logic_error("IncrementalFactorization: unknown variable");
    return vars[v];
  }
  void clear() {
    vars.clear();
    factors.clear();
    free_factors.clear();
    factor_of.clear();
    factor_count = 0;
  }
  void addVar(VariableIndex v, const VariableKey& key) {
    if (v >= vars.size()) vars.resize(static_cast<std::size_t>(v) + 1);
    Var& r = vars[v];
    if (r.alive) throw std::logic_error("IncrementalFactorization: variable added twice");
    r = Var();
    r.key = key;
    r.dim = static_cast<int>(key.dim());
    r.alive = true;
  }
  void removeVar(VariableIndex v) {
    Var& r = var(v);
    if (!r.factors.empty())
      throw std::logic_error("IncrementalFactorization: variable removed with factors");
    r.alive = false;
    r.dying = false;
  }
  int addFactor(const GraphFactor& f) {
    int k;
    if (!free_factors.empty()) {
      k = free_factors.back();
      free_factors.pop_back();
    } else {
      k = static_cast<int>(factors.size());
      factors.emplace_back();
    }
    Held& h = factors[k];
    h.f = f;
    h.alive = true;
    h.added = true;
    h.hpos.clear();
    h.var = {{-1, -1}};
    for (int j = 0; j < f.variableCount(); ++j) {
      var(f.vars[j]).factors.push_back(k);
      h.var[j] = static_cast<int>(f.vars[j]);
    }
    factor_of[f.id] = k;
    ++factor_count;
    return k;
  }
  void removeFactor(int k) {
    Held& h = factors[k];
    for (int j = 0; j < 2 && h.var[j] >= 0; ++j) {
      std::vector<int>& fs = vars[h.var[j]].factors;
      fs.erase(std::find(fs.begin(), fs.end(), k));
    }
    factor_of.erase(h.f.id);
    h.alive = false;
    free_factors.push_back(k);
    --factor_count;
  }
  /// The factor linearized at its variables' linearization points.
  LinearFactor linearizeHeld(const Held& h) const {
    return linearize(h.f, vars[h.var[0]].lin,
                     h.var[1] >= 0 ? vars[h.var[1]].lin : Eigen::Vector3d::Zero());
  }
  /// The factor's current rows on its variables' rows of H.
  Piece pieceOf(const Held& h) const {
    Piece p;
    p.lin = h.lin;
    for (int j = 0; j < 2 && h.var[j] >= 0; ++j) {
      p.row[j] = vars[h.var[j]].row;
      p.dim[j] = vars[h.var[j]].dim;
      p.nvar = j + 1;
    }
    return p;
  }
  /// The first (smallest) row of H a factor touches.
  int firstRow(const Held& h) const {
    int first = vars[h.var[0]].row;
    if (h.var[1] >= 0) first = std::min(first, vars[h.var[1]].row);
    return first;
  }
  static Eigen::Vector3d valueIn(const FactorGraph& graph, const VariableKey& key) {
    if (key.kind == VariableKey::Kind::Pose) return graph.pose(static_cast<StepIndex>(key.id)).x;
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    v.head<2>() = graph.landmark(key.id).x;
    return v;
  }
  /// Every variable and factor of `graph` afresh, each factor linearized at its variables'
  /// values (no rows placed).
  void read(const FactorGraph& graph) {
    clear();
    for (const auto& [s, p] : graph.poses()) {
      addVar(p.index, VariableKey::pose(s));
      vars[p.index].lin = p.x;
    }
    for (const auto& [id, l] : graph.landmarks()) {
      addVar(l.index, VariableKey::landmark(id));
      vars[l.index].lin.head<2>() = l.x;
    }
    for (const GraphFactor& f : graph.factors()) addFactor(f);
    for (Held& h : factors) {
      h.lin = linearizeHeld(h);
      h.added = false;
    }
  }
};

}  // namespace budget_slam::graph::held
