#include "GramKernel.h"

#include <algorithm>
#include <cmath>

namespace budget_slam::graph::detail {

// Plain loops on fixed-size tiles, so that the compiler vectorizes them for each clone; no
// Eigen here (its kernels are chosen at compile time and must not differ between translation
// units).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void forwardSubstitute(
    double* X, std::size_t m, std::size_t r, const int* start, const int* rows,
    const double* vals) {
  for (std::size_t a = 0; a < m; ++a) {
    double* xa = X + a * r;
    const double inv = 1.0 / vals[start[a]];
    bool nonzero = false;
    for (std::size_t j = 0; j < r; ++j) {
      xa[j] *= inv;
      nonzero |= xa[j] != 0.0;
    }
    if (!nonzero) continue;  // below every start node of this path: nothing to push up
    for (int q = start[a] + 1; q < start[a + 1]; ++q) {
      double* xi = X + static_cast<std::size_t>(rows[q]) * r;
      const double c = vals[q];
      for (std::size_t j = 0; j < r; ++j) xi[j] -= c * xa[j];
    }
  }
}

__attribute__((target_clones("arch=x86-64-v3", "default"))) void gramLowerRows(
    const double* const* rows, std::size_t m, std::size_t w, double* G, std::size_t ldg,
    std::size_t lo) {
  double* g = G + lo * ldg + lo;
  const std::size_t w8 = w / 8 * 8;
  for (std::size_t a0 = 0; a0 < w; a0 += 4) {
    const std::size_t na = std::min<std::size_t>(4, w - a0);
    for (std::size_t b0 = 0; b0 <= a0 && b0 < w8; b0 += 8) {  // full 4 x 8 tiles
      double acc[4][8] = {};
      for (std::size_t i = 0; i < m; ++i) {
        const double* z = rows[i];
        double za[4];
        for (std::size_t a = 0; a < 4; ++a) za[a] = a < na ? z[a0 + a] : 0.0;
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 8; ++b) acc[a][b] += za[a] * z[b0 + b];
      }
      for (std::size_t a = 0; a < na; ++a)
        for (std::size_t b = 0; b < 8; ++b) g[(b0 + b) * ldg + (a0 + a)] += acc[a][b];
    }
    for (std::size_t b = w8; b <= a0 + na - 1 && b < w; ++b)  // the columns past the last tile
      for (std::size_t a = 0; a < na; ++a) {
        if (b > a0 + a) continue;
        double acc = 0;
        for (std::size_t i = 0; i < m; ++i) acc += rows[i][a0 + a] * rows[i][b];
        g[b * ldg + (a0 + a)] += acc;
      }
  }
}

__attribute__((target_clones("arch=x86-64-v3", "default"))) void forwardSubstitutePath(
    double* X, std::size_t ld, const int* nodes, std::size_t m, const int* Lp, const int* Lnz,
    const int* Li, const double* Lx, bool ldl, const int* local, const int* lo, const int* hi) {
  for (std::size_t a = 0; a < m; ++a) {
    const int k = nodes[a];
    double* xa = X + a * ld;
    const std::size_t l = static_cast<std::size_t>(lo[a]), h = static_cast<std::size_t>(hi[a]);
    if (!ldl) {
      const double inv = 1.0 / Lx[Lp[k]];
      for (std::size_t j = l; j < h; ++j) xa[j] *= inv;
    }
    for (int q = Lp[k] + 1; q < Lp[k] + Lnz[k]; ++q) {
      double* xi = X + static_cast<std::size_t>(local[Li[q]]) * ld;
      const double c = Lx[q];
      for (std::size_t j = l; j < h; ++j) xi[j] -= c * xa[j];
    }
    if (ldl) {  // unit L pushed the row up unscaled; the LL^T row is it over sqrt(D_k)
      const double inv = 1.0 / std::sqrt(Lx[Lp[k]]);
      for (std::size_t j = l; j < h; ++j) xa[j] *= inv;
    }
  }
}

}  // namespace budget_slam::graph::detail
