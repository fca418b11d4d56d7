#pragma once
#include <cstddef>

namespace budget_slam::graph::detail {

/// G += Zᵀ Z on (at least) the lower triangle of G, r x r column-major; Z is m x r row-major.
/// The dense core of the information gain (SparseCholesky::inverseQuadraticForm):
/// register-blocked 4 x 8 tiles, built twice (AVX2 + FMA and baseline) and chosen at run time.
void gramLower(const double* Z, std::size_t m, std::size_t r, double* G);

/// Forward substitution L X = B in place on a dense row-major X (m x r), L given column by column
/// on local row numbers: column a has its diagonal at vals[start[a]] and its off-diagonal entries
/// at start[a] + 1 .. start[a + 1] - 1, rows rows[q] > a. Same dispatch as gramLower.
void forwardSubstitute(double* X, std::size_t m, std::size_t r, const int* start, const int* rows,
                       const double* vals);

}  // namespace budget_slam::graph::detail
