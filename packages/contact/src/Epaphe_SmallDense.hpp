#pragma once
// Dense solves of the contact laws' small systems (MC lambda = -g*, the friction system): a few to a
// few dozen unknowns, solved several times a step. LAPACK's dgesv spends about 50,000 instructions
// on a 12 x 12 system (callgrind, OpenBLAS 0.3.21: dispatch, threading checks, blocking), 30 times
// the arithmetic, and was a fifth of a blade run. Below kSmallDense unknowns the same algorithm
// (Gaussian elimination with partial pivoting, LAPACK's dgetf2 order: largest pivot in the column,
// row swaps) runs here; above, LAPACK.
#include <Teuchos_LAPACK.hpp>

#include <cmath>
#include <vector>

namespace epaphe {

/// Systems of fewer unknowns are solved here, larger ones by LAPACK.
constexpr int kSmallDense = 64;

/// Solves A x = b in place: A (n x n, column-major, leading dimension lda) is overwritten by its LU
/// factors and b by x. Returns 0, or k + 1 when the k-th pivot is exactly zero (LAPACK's info).
inline int solveDense(int n, double* A, int lda, double* b, std::vector<int>& ipiv) {
  ipiv.assign(static_cast<std::size_t>(n), 0);
  if (n > kSmallDense) {
    int info = 0;
    Teuchos::LAPACK<int, double>().GESV(n, 1, A, lda, ipiv.data(), b, n, &info);
    return info;
  }
  auto a = [&](int i, int j) -> double& { return A[static_cast<std::size_t>(j) * lda + i]; };
  double inv[kSmallDense];  // 1 / u_kk, for the back substitution too
  for (int k = 0; k < n; ++k) {
    int p = k;
    for (int i = k + 1; i < n; ++i)
      if (std::fabs(a(i, k)) > std::fabs(a(p, k))) p = i;
    if (a(p, k) == 0.0) return k + 1;
    if (p != k) {
      for (int j = 0; j < n; ++j) std::swap(a(k, j), a(p, j));
      std::swap(b[k], b[p]);
    }
    inv[k] = 1.0 / a(k, k);
    for (int i = k + 1; i < n; ++i) a(i, k) *= inv[k];  // multipliers l_ik
    for (int j = k + 1; j < n; ++j) {                   // trailing update, column by column
      const double akj = a(k, j);
      if (akj != 0.0)
        for (int i = k + 1; i < n; ++i) a(i, j) -= a(i, k) * akj;
    }
    for (int i = k + 1; i < n; ++i) b[i] -= a(i, k) * b[k];
  }
  // U x = y column by column, as LAPACK's dgetrs (dtrsm): x_k = y_k (1 / u_kk), then y_i -= u_ik x_k
  // for i < k, independent updates down a contiguous column; the reciprocals were made by the
  // factorisation, so that no division (nor, by rows, a chain of dependent subtractions) lies on the
  // substitution's path from one x_k to the next.
  for (int k = n - 1; k >= 0; --k) {
    b[k] *= inv[k];
    const double xk = b[k];
    for (int i = 0; i < k; ++i) b[i] -= a(i, k) * xk;
  }
  return 0;
}

}  // namespace epaphe
