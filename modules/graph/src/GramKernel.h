#pragma once
#include <cstddef>

namespace budget_slam::graph::detail {

// Each kernel is built twice (x86-64-v3: AVX2 + FMA, and baseline) and chosen at run time by the
// CPU's features ("arch=haswell" would dispatch on the CPU model and miss AMD processors).

/// Forward substitution L X = B in place on a dense row-major X (m x r), L given column by column
/// on local row numbers: column a has its diagonal at vals[start[a]] and its off-diagonal entries
/// at start[a] + 1 .. start[a + 1] - 1, rows rows[q] > a.
void forwardSubstitute(double* X, std::size_t m, std::size_t r, const int* start, const int* rows,
                       const double* vals);

/// G[lo + b, lo + a] += sum_i rows[i][a] rows[i][b] for a >= b in [0, w): the lower triangle of
/// the Gram matrix of m rows of width w given by pointers (rows of one range, see
/// SparseCholesky::inverseGram); G column-major with leading dimension ldg. Register-blocked
/// 4 x 8 tiles.
void gramLowerRows(const double* const* rows, std::size_t m, std::size_t w, double* G,
                   std::size_t ldg, std::size_t lo);

/// Forward substitution on the etree path `nodes` (ascending, m of them) of a simplicial factor
/// in CSC form (column k: Lp[k] .. Lp[k] + Lnz[k] - 1, diagonal first), in place on the
/// row-major X (row a = node nodes[a], leading dimension ld); local[] maps a node to its row.
/// The factor is L L^T, or with `ldl` a unit L D L^T whose diagonal entries hold D: the rows of
/// X then come out as those of the L L^T factor L D^1/2 would give. Row a is non-zero only in
/// columns [lo[a], hi[a]), and an ancestor's range holds its descendants' (inverseGram).
void forwardSubstitutePath(double* X, std::size_t ld, const int* nodes, std::size_t m,
                           const int* Lp, const int* Lnz, const int* Li, const double* Lx, bool ldl,
                           const int* local, const int* lo, const int* hi);

}  // namespace budget_slam::graph::detail
