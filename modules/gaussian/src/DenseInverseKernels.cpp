#include "DenseInverseKernels.h"

#include <algorithm>
#include <cmath>

namespace budget_slam::gaussian::detail {

namespace {

constexpr std::size_t kBlock = 32;  ///< panel width of the blocked algorithms

/// Four doubles, loaded and stored unaligned; the compiler maps it onto one AVX register in the
/// x86-64-v3 clone and two SSE2 registers in the baseline one.
typedef double V4 __attribute__((vector_size(32), aligned(8)));

#define LOAD4(v, p) __builtin_memcpy(&(v), (p), sizeof(V4))

// C (m x n) += alpha * A (m x k) * op(B), all column-major; op(B)(p, j) = B[p * bp + j * bj], so
// the same kernel serves A B (bp = 1, bj = ldb) and A B^T (bp = ldb, bj = 1). With `lower_only`
// (C square and on the diagonal) the tiles wholly above the diagonal are skipped. Register tiles
// of 8 rows x 4 columns (eight accumulators of four): the 8 rows of A are contiguous, B is
// broadcast. fp-contract lets the x86-64-v3 clone fuse the multiply-adds (-std=c++17 turns
// contraction off by default).
__attribute__((target_clones("arch=x86-64-v3", "default"), optimize("fp-contract=fast"))) void
gemmAccumulate(double* C, std::size_t ldc, const double* A, std::size_t lda, const double* B,
               std::size_t bp, std::size_t bj, std::size_t m, std::size_t n, std::size_t k,
               double alpha, bool lower_only) {
  for (std::size_t j0 = 0; j0 < n; j0 += 4) {
    const std::size_t nj = std::min<std::size_t>(4, n - j0);
    for (std::size_t i0 = lower_only ? j0 / 8 * 8 : 0; i0 < m; i0 += 8) {
      const std::size_t ni = std::min<std::size_t>(8, m - i0);
      if (ni == 8 && nj == 4) {
        V4 c00 = {}, c01 = {}, c10 = {}, c11 = {}, c20 = {}, c21 = {}, c30 = {}, c31 = {};
        const double* a = A + i0;
        const double* b = B + j0 * bj;
        for (std::size_t p = 0; p < k; ++p, a += lda, b += bp) {
          V4 a0, a1;
          LOAD4(a0, a);
          LOAD4(a1, a + 4);
          const V4 b0 = V4{} + b[0], b1 = V4{} + b[bj], b2 = V4{} + b[2 * bj],
                   b3 = V4{} + b[3 * bj];
          c00 += a0 * b0;
          c01 += a1 * b0;
          c10 += a0 * b1;
          c11 += a1 * b1;
          c20 += a0 * b2;
          c21 += a1 * b2;
          c30 += a0 * b3;
          c31 += a1 * b3;
        }
        const V4 acc[4][2] = {{c00, c01}, {c10, c11}, {c20, c21}, {c30, c31}};
        for (std::size_t j = 0; j < 4; ++j) {
          double* c = C + i0 + (j0 + j) * ldc;
          for (int h = 0; h < 2; ++h) {
            V4 v;
            LOAD4(v, c + 4 * h);
            v += alpha * acc[j][h];
            __builtin_memcpy(c + 4 * h, &v, sizeof v);
          }
        }
        continue;
      }
      double acc[4][8] = {};
      for (std::size_t p = 0; p < k; ++p) {
        const double* a = A + i0 + p * lda;
        for (std::size_t j = 0; j < nj; ++j) {
          const double b = B[p * bp + (j0 + j) * bj];
          for (std::size_t ii = 0; ii < ni; ++ii) acc[j][ii] += a[ii] * b;
        }
      }
      for (std::size_t j = 0; j < nj; ++j) {
        double* c = C + i0 + (j0 + j) * ldc;
        for (std::size_t ii = 0; ii < ni; ++ii) c[ii] += alpha * acc[j][ii];
      }
    }
  }
}

/// y[0..m) -= s * x[0..m): the column operations of the panels.
__attribute__((target_clones("arch=x86-64-v3", "default"), optimize("fp-contract=fast"))) void
axpyMinus(double* y, const double* x, double s, std::size_t m) {
  for (std::size_t i = 0; i < m; ++i) y[i] -= s * x[i];
}

}  // namespace

bool choleskyLowerInPlace(double* A, std::size_t n, std::size_t ld) {
  for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
    const std::size_t kb = std::min(kBlock, n - k0);
    // The block column k0 .. k0+kb, full height, left-looking inside the block (the earlier
    // blocks' contributions were subtracted by their trailing updates).
    for (std::size_t j = k0; j < k0 + kb; ++j) {
      double* cj = A + j + j * ld;  // column j from the diagonal down
      for (std::size_t p = k0; p < j; ++p) axpyMinus(cj, A + j + p * ld, A[j + p * ld], n - j);
      const double d = cj[0];
      if (!(d > 0) || !std::isfinite(d)) return false;
      const double s = std::sqrt(d);
      cj[0] = s;
      const double inv = 1.0 / s;
      for (std::size_t i = 1; i < n - j; ++i) cj[i] *= inv;
    }
    // Trailing update of the lower triangle: A22 -= P P^T, P the panel below the block.
    const std::size_t r = k0 + kb;
    if (r < n) {
      const double* P = A + r + k0 * ld;
      gemmAccumulate(A + r + r * ld, ld, P, ld, P, ld, 1, n - r, n - r, kb, -1.0, true);
    }
  }
  return true;
}

void invertLowerInPlace(double* L, std::size_t n, std::size_t ld, double* scratch) {
  for (std::size_t j = 1; j < n; ++j) std::fill(L + j * ld, L + j * ld + j, 0.0);
  // Column blocks from the last to the first: with W = L^-1 known on the trailing rows and
  // columns B, the block column J is W_JJ = L_JJ^-1 and W_BJ = -W_BB L_BJ W_JJ.
  const std::size_t nblocks = (n + kBlock - 1) / kBlock;
  for (std::size_t blk = nblocks; blk-- > 0;) {
    const std::size_t j0 = blk * kBlock, jb = std::min(kBlock, n - j0), b0 = j0 + jb, mb = n - b0;
    // S = L_BJ (original values), before the diagonal block is touched.
    for (std::size_t c = 0; c < jb; ++c)
      std::copy(L + b0 + (j0 + c) * ld, L + n + (j0 + c) * ld, scratch + c * mb);
    // W_JJ: columns right to left; column c of the inverse needs the inverse's columns to its
    // right and the original column c: W(i, c) = -(sum_{c<q<=i} W(i, q) L(q, c)) / L(c, c).
    for (std::size_t c = jb; c-- > 0;) {
      double* col = L + j0 + (j0 + c) * ld;  // rows j0 .. j0+jb-1 of column j0+c
      const double inv = 1.0 / col[c];
      double tmp[kBlock];
      for (std::size_t i = c + 1; i < jb; ++i) {
        double s = 0;
        for (std::size_t q = c + 1; q <= i; ++q) s += L[j0 + i + (j0 + q) * ld] * col[q];
        tmp[i] = -s * inv;
      }
      col[c] = inv;
      for (std::size_t i = c + 1; i < jb; ++i) col[i] = tmp[i];
    }
    if (mb == 0) continue;
    // X = W_BB S (W_BB lower triangular with a zero upper part): block rows of W_BB against the
    // rows of S they can reach. X goes to scratch + jb * mb.
    double* X = scratch + jb * mb;
    std::fill(X, X + mb * jb, 0.0);
    for (std::size_t i0 = 0; i0 < mb; i0 += kBlock) {
      const std::size_t ib = std::min(kBlock, mb - i0), kk = i0 + ib;
      gemmAccumulate(X + i0, mb, L + b0 + i0 + b0 * ld, ld, scratch, 1, mb, ib, jb, kk, 1.0, false);
    }
    // W_BJ = -X W_JJ.
    for (std::size_t c = 0; c < jb; ++c)
      std::fill(L + b0 + (j0 + c) * ld, L + n + (j0 + c) * ld, 0.0);
    gemmAccumulate(L + b0 + j0 * ld, ld, X, mb, L + j0 + j0 * ld, 1, ld, mb, jb, jb, -1.0, false);
  }
}

}  // namespace budget_slam::gaussian::detail
