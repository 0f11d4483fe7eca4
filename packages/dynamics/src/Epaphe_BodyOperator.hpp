#pragma once
// A body's linear operators in its own coordinates, as the explicit step applies them: dense (a
// reduced body's K, M, D and the scheme's A, B, stored by rows so that a thread's block of rows is
// one piece of memory), sparse (a full body's K, KokkosKernels) or diagonal (a lumped mass, a
// mass-proportional damping). Used by the central difference (Epaphe_CentralDifference.hpp) and the
// stable-step estimate (Epaphe_StableStep.hpp).
#include "Epaphe_DenseTypes.hpp"
#include "Epaphe_ReducedModel.hpp"

#include <KokkosSparse_CrsMatrix.hpp>
#include <Kokkos_Core.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace epaphe {

/// One linear operator of a body in its coordinates: dense (a reduced body's K, M, D, A, B),
/// sparse (a full body's K, a KokkosKernels CrsMatrix) or diagonal (a lumped mass, a
/// mass-proportional damping). Its vectors live in host memory (the explicit step runs there).
class BodyOperator {
public:
  /// KokkosKernels' compressed-row matrix, the storage of a sparse operator.
  using Sparse = KokkosSparse::CrsMatrix<double, int, Kokkos::DefaultExecutionSpace, void, std::size_t>;
  BodyOperator() = default;
  /// n x n, column-major (stored by rows: see forRowBlocks).
  static BodyOperator dense(const std::vector<double>& a, int n, const std::string& label);
  /// A in compressed rows.
  static BodyOperator sparse(const SparseRows& a, const std::string& label);
  /// diag(d).
  static BodyOperator diagonal(const std::vector<double>& d, const std::string& label);
  /// dense(), or diagonal() when every entry off the diagonal is zero (a massless boundary's mass,
  /// diag(0, I)): the same products, without reading n^2 - n zeros.
  static BodyOperator denseOrDiagonal(const std::vector<double>& a, int n, const std::string& label);

  /// y = alpha A x + beta y (beta = 0: y is overwritten).
  void apply(double alpha, const DenseVector& x, double beta, const DenseVector& y) const;
  /// Y = A X for two vectors at once (n x 2, column-major): a dense operator is read once (one BLAS
  /// dgemm, about the cost of one dgemv: 0.63 against 1.15 us for two on 68 x 68, 23 against 39 us
  /// on 419 x 419, OpenBLAS 0.3.21 on this project's machine).
  void apply2(const DenseMatrix& x, const DenseMatrix& y) const;
  /// A dense operator's entries replaced by `a` (n x n, column-major) in place, nothing allocated.
  void assignDense(const std::vector<double>& a);
  /// The dense operator, column-major (a copy: it is stored by rows; empty when not dense).
  DenseMatrix denseMatrix() const;
  /// Bytes one apply() reads of the operator's own storage (values and indices).
  std::size_t bytes() const;
  /// A diagonal operator's entries (empty when not diagonal).
  const DenseVector& diagonalEntries() const { return diagonal_; }

private:
  DenseMatrix dense_;
  Sparse sparse_;
  DenseVector diagonal_;
  enum class Kind { None, Dense, Sparse, Diagonal } kind_ = Kind::None;
};

}  // namespace epaphe
