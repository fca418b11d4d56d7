#pragma once
// The held factor's information matrix H (IncrementalFactorization, docs/GRAPH.md "Held
// factor"): its upper triangle assembled in compressed columns in elimination order, with g, chi2
// and the estimate by row. No factorization here.
#include <Eigen/Core>
#include <vector>

#include "HeldRecords.h"
#include "budget_slam/graph/SparseCholesky.h"

namespace budget_slam::graph::held {

/// H = sum of the live factors' A^T A, g = sum A^T r, chi2 = sum |r|^2, every variable's rows
/// its positions in the elimination order (P = I).
/// Invariants: `owner[r]` is the variable of row r, -1 for a spare or dead row, whose row of H is
/// the identity (g and est zero there); every live factor's `hpos` indexes its entries in Hx;
/// rows from `next_row` on are spare.
struct HeldMatrix {
  /// Variable of each row of H, -1 for a spare or dead row (an identity row of H).
  std::vector<int> owner;
  int next_row = 0;     ///< first spare row
  int dying_count = 0;  ///< variables marked dying (while a journal is folded in)
  int dead_rows = 0;    ///< rows of removed variables since the last fresh ordering
  /// H's upper triangle in compressed columns, rows in elimination order (the factor is
  /// P H P^T with P = I): kept equal to the sum of the factors' A^T A.
  std::vector<int> Hp, Hi;
  std::vector<double> Hx;
  Eigen::VectorXd g;    ///< sum of A^T r, by row
  Eigen::VectorXd est;  ///< the estimate the graph holds, by row (a pose's yaw wrapped)
  double chi2 = 0;      ///< sum of |r|^2 at the linearization points

  int capacity() const { return static_cast<int>(owner.size()); }
  bool dyingRow(const HeldRecords& rec, int r) const {
    return owner[r] >= 0 && rec.vars[owner[r]].dying;
  }

  /// Every entry (r <= c) a factor puts into H's upper triangle, in a fixed order: fn(r, c,
  /// column of A for r, column of A for c).
  template <typename Fn>
  static void forEachEntry(const HeldRecords& rec, const Held& h, Fn fn) {
    const int nv = h.var[1] >= 0 ? 2 : 1;
    int off[2] = {0, 0};
    if (nv == 2) off[1] = rec.vars[h.var[0]].dim;
    for (int x = 0; x < nv; ++x)
      for (int y = 0; y < nv; ++y) {
        const Var &a = rec.vars[h.var[x]], &b = rec.vars[h.var[y]];
        for (int i = 0; i < a.dim; ++i)
          for (int j = 0; j < b.dim; ++j)
            if (a.row + i <= b.row + j) fn(a.row + i, b.row + j, off[x] + i, off[y] + j);
      }
  }

  /// Adds sign * A^T A of a factor to H (at its hpos), sign * A^T r to g, sign * |r|^2 to chi2.
  /// Entries on a dying row are set to zero instead (the row leaves H).
  void add(const HeldRecords& rec, const Held& h, double sign) {
    change(rec, h, h.lin, sign, nullptr);
  }
  /// H, g and chi2 from `old` to the factor's own linearization: one pass over its entries.
  void replace(const HeldRecords& rec, const Held& h, const LinearFactor& old) {
    change(rec, h, h.lin, 1.0, &old);
  }
  void change(const HeldRecords& rec, const Held& h, const LinearFactor& lf, double sign,
              const LinearFactor* old);
  /// Index into Hx of entry (r, c), r <= c, or -1 when H has none there.
  int find(int r, int c) const;
  /// H's pattern and values from every factor (after a fresh ordering, or when a factor ties
  /// two variables that had no entry yet): every diagonal entry, the factors' entries.
  void buildPattern(HeldRecords& rec);
  /// H, g and chi2 from every factor's linearization on the pattern as it stands.
  void assemble(const HeldRecords& rec);
  /// hpos of a factor from H's pattern; false when an entry is missing.
  bool locate(const HeldRecords& rec, Held* h) const;
  /// New columns from `first` on (rows of variables placed since the last change, and spares):
  /// the entries of the new factors there, and every diagonal. False when a new factor has an
  /// entry in an older column that H has no place for (buildPattern() then).
  bool extendPattern(HeldRecords& rec, int first, const std::vector<int>& added);
  /// H as CHOLMOD reads it. Rows of removed variables keep their entries in Hp/Hi (zeros: the
  /// factors' positions stay valid) until the next fresh ordering; a factorization or a pattern
  /// cut reads a copy without them, so they leave no fill behind. With `first`: only the columns
  /// from `first` on (the others empty), all a partial re-elimination from `first` reads.
  SparseCholesky::UpperTriangle upper(int first = 0);

 private:
  std::vector<int> Fp, Fi;  ///< upper()'s copy without the dead rows
  std::vector<double> Fx;
};

}  // namespace budget_slam::graph::held
