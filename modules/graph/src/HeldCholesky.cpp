#include "HeldCholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <limits>

namespace budget_slam::graph::held {

HeldCholesky::HeldCholesky(const HeldCholesky& o)
    : chol(o.chol.copy()),
      fresh_fill(o.fresh_fill),
      fresh_flops(o.fresh_flops),
      fresh_depth(o.fresh_depth),
      refresh_flops(o.refresh_flops),
      stale_pattern(o.stale_pattern),
      path_cost(o.path_cost) {}

Tree HeldCholesky::tree() {
  const cholmod_factor& L = *chol.factor();
  return {static_cast<const int*>(L.p), static_cast<const int*>(L.nz), static_cast<const int*>(L.i),
          static_cast<int>(L.n)};
}

double HeldCholesky::nonZerosOfL() {
  const Tree t = tree();
  double s = 0;
  for (int k = 0; k < t.n; ++k) s += t.nz[k];
  return s;
}

void HeldCholesky::computePathCosts() {
  const Tree t = tree();
  path_cost.assign(static_cast<std::size_t>(t.n), 0.0);
  for (int k = t.n - 1; k >= 0; --k) {  // a parent comes after its children
    const int up = t.parent(k);
    path_cost[k] = t.nz[k] + (up >= 0 ? path_cost[up] : 0.0);
  }
}

double HeldCholesky::meanDepth(const std::vector<int>& owner) {
  const Tree t = tree();
  std::vector<int> depth(static_cast<std::size_t>(t.n), 1);
  double sum = 0, count = 0;
  for (int k = t.n - 1; k >= 0; --k) {
    const int up = t.parent(k);
    if (up >= 0) depth[k] = 1 + depth[up];
    if (owner[k] >= 0) sum += depth[k], ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

double HeldCholesky::refreshCap(std::size_t h_entries) const {
  return (kRefreshCostPerFlop * refresh_flops +
          kRefreshCostPerEntry * static_cast<double>(h_entries)) /
         kUpdateCostPerEntry;
}

double HeldCholesky::flopsFrom(int first) {
  return partialCap(first, 0, std::numeric_limits<double>::infinity()) * kUpdateCostPerEntry /
         kRefreshCostPerFlop;
}

double HeldCholesky::partialCap(int first, std::size_t h_entries, double stop) {
  const Tree t = tree();
  const double scale = kRefreshCostPerFlop / kUpdateCostPerEntry;
  double s = kRefreshCostPerEntry * static_cast<double>(h_entries) / kUpdateCostPerEntry;
  for (int j = std::max(first, 0); j < t.n; ++j) {
    const double nz = t.nz[j];
    s += scale * nz * nz;
  }
  // The leading columns' entries in the trailing rows: each is computed again, at the cost of
  // its column's length there (the row factorization's sparse triangular solve).
  for (int j = std::min(first, t.n) - 1; j >= 0 && s <= stop; --j) {
    const int nz = t.nz[j];
    const int* b = t.i + t.p[j];
    if (nz > 1 && b[nz - 1] >= first) {
      const double kept = static_cast<double>(std::lower_bound(b + 1, b + nz, first) - b);
      s += scale * (static_cast<double>(nz) * nz - kept * kept);
    }
  }
  return s;
}

double HeldCholesky::pathEntries(int k, double cap) {
  const Tree t = tree();
  double s = 0;
  for (; k >= 0 && s <= cap; k = t.parent(k)) s += t.nz[k];
  return s;
}

double HeldCholesky::columns(const std::vector<Piece>& pieces, const std::vector<char>& deleted,
                             std::vector<int>* cp, std::vector<int>* ci, std::vector<double>* cx,
                             double cap) {
  cp->assign(1, 0);
  ci->clear();
  cx->clear();
  double work = 0;
  for (const Piece& p : pieces) {
    // Variables by row, so each column's rows come out ascending.
    const bool swap = p.nvar == 2 && p.row[1] < p.row[0];
    const int first = swap ? 1 : 0;
    const int off[2] = {0, p.dim[0]};
    for (int i = 0; i < p.lin.rows; ++i) {
      const std::size_t begin = ci->size();
      for (int q = 0; q < p.nvar; ++q) {
        const int a = q == 0 ? first : 1 - first;
        for (int t = 0; t < p.dim[a]; ++t) {
          const int row = p.row[a] + t;
          const double x = p.lin.A(i, off[a] + t);
          if (x != 0 && !deleted[row]) {
            ci->push_back(row);
            cx->push_back(x);
          }
        }
      }
      if (ci->size() == begin) continue;
      if (work <= cap) work += pathEntries((*ci)[begin], cap - work);
      cp->push_back(static_cast<int>(ci->size()));
    }
  }
  return work;
}

bool HeldCholesky::degraded(double ratio, int used_rows, int dead_rows) {
  const double rows = used_rows - dead_rows;
  if (rows <= 0) return false;
  return (nonZerosOfL() - dead_rows) / rows > ratio * fresh_fill ||
         refresh_flops / rows > ratio * fresh_flops || dead_rows > 0.1 * used_rows;
}

}  // namespace budget_slam::graph::held
