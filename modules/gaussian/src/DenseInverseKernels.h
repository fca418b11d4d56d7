#pragma once
#include <cstddef>

namespace budget_slam::gaussian::detail {

// Dense kernels of BlockMutualInformation: the Cholesky factor of a covariance and the inverse of
// that factor, whose column norms are the diagonal of the information matrix. Column-major
// storage with leading dimension ld; only the lower triangle is read and written (the strict
// upper triangle is scratch). Each is built twice (AVX2 + FMA and baseline x86-64) and chosen at
// run time, like the graph's Gram kernels: Eigen's own kernels are fixed to SSE2 here.

/// A = L L^T in place (lower triangle), blocked right-looking: about n^3/6 multiply-adds.
/// Returns false when a pivot is not positive (A not positive definite); A is then garbage.
bool choleskyLowerInPlace(double* A, std::size_t n, std::size_t ld);

/// L <- L^-1 for a lower triangular L with a positive diagonal, in place, blocked: about n^3/6
/// multiply-adds. The strict upper triangle is set to zero. `scratch` holds at least n * 64
/// doubles.
void invertLowerInPlace(double* L, std::size_t n, std::size_t ld, double* scratch);

}  // namespace budget_slam::gaussian::detail
