#include "HeldSolution.h"

#include <cholmod.h>

#include <algorithm>
#include <cmath>

namespace budget_slam::graph::held {

void HeldSolution::solve(const cholmod_factor& L, const Eigen::VectorXd& g, double threshold) {
  const int n = static_cast<int>(L.n);
  const int* Lp = static_cast<const int*>(L.p);
  const int* Lnz = static_cast<const int*>(L.nz);
  const int* Li = static_cast<const int*>(L.i);
  const double* Lx = static_cast<const double*>(L.x);
  const bool ll = L.is_ll != 0;  // L L^T; otherwise unit L with D on the diagonal
  int k0 = std::clamp(from, 0, n);
  // Rows skipped under a larger threshold may lag by more than this one allows.
  if (threshold < lag_) k0 = 0;
  if (y.size() != n || dx.size() != n || seen.size() != n) {
    y.setZero(n);
    dx.setZero(n);
    seen.setZero(n);
    k0 = 0;
  }
  rows.clear();

  // Forward substitution L y = -g, rows k0 .. n-1 (the leading rows stay): first the leading
  // columns' entries in the trailing rows, then the trailing columns.
  for (int k = k0; k < n; ++k) y[k] = -g[k];
  for (int j = 0; j < k0; ++j) {
    const int* b = Li + Lp[j];
    const int nz = Lnz[j];
    if (nz < 2 || b[nz - 1] < k0 || y[j] == 0) continue;
    const double yj = y[j];
    for (int e = static_cast<int>(std::lower_bound(b + 1, b + nz, k0) - b); e < nz; ++e)
      y[b[e]] -= Lx[Lp[j] + e] * yj;
  }
  for (int j = k0; j < n; ++j) {
    const int p = Lp[j];
    if (ll) y[j] /= Lx[p];
    const double yj = y[j];
    if (yj == 0) continue;
    for (int e = 1; e < Lnz[j]; ++e) y[Li[p + e]] -= Lx[p + e] * yj;
  }

  // Back substitution (D and L^T), from the root down: a trailing row always, a leading row
  // when a row of its column propagated (visited only when its etree parent was solved again).
  recalc_.assign(static_cast<std::size_t>(n), 0);
  propagates_.assign(static_cast<std::size_t>(n), 0);
  for (int k = n - 1; k >= 0; --k) {
    const int p = Lp[k];
    const int nz = Lnz[k];
    if (k < k0) {
      if (nz < 2 || !recalc_[Li[p + 1]]) continue;
      bool moved = false;
      for (int e = 1; e < nz && !moved; ++e) moved = propagates_[Li[p + e]] != 0;
      if (!moved) continue;
    }
    double s = ll ? y[k] : y[k] / Lx[p];
    for (int e = 1; e < nz; ++e) s -= Lx[p + e] * dx[Li[p + e]];
    if (ll) s /= Lx[p];
    recalc_[k] = 1;
    rows.push_back(k);
    if (k0 == 0 || std::abs(s - seen[k]) > threshold) {
      propagates_[k] = 1;
      seen[k] = s;
    }
    dx[k] = s;
  }
  from = n;
  lag_ = k0 == 0 ? threshold : std::max(lag_, threshold);
}

}  // namespace budget_slam::graph::held
