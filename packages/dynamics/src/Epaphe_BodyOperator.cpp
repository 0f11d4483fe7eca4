#include "Epaphe_BodyOperator.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace epaphe {
BodyOperator BodyOperator::dense(const std::vector<double>& a, int n, const std::string& label) {
  BodyOperator op;
  op.kind_ = Kind::Dense;
  op.dense_ = DenseMatrix(label, n, n);  // A's rows, each contiguous: column i holds row i
  auto h = Kokkos::create_mirror_view(op.dense_);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) h(j, i) = a[static_cast<std::size_t>(j) * n + i];
  Kokkos::deep_copy(op.dense_, h);
  return op;
}

void BodyOperator::assignDense(const std::vector<double>& a) {
  const int n = static_cast<int>(dense_.extent(0));
  EPAPHE_REQUIRE(kind_ == Kind::Dense && a.size() == static_cast<std::size_t>(n) * n,
                 "BodyOperator::assignDense: " << a.size() << " entries for a dense operator of size " << n);
  auto h = Kokkos::create_mirror_view(dense_);  // host memory: the view itself, nothing allocated
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) h(j, i) = a[static_cast<std::size_t>(j) * n + i];
  Kokkos::deep_copy(dense_, h);
}

DenseMatrix BodyOperator::denseMatrix() const {
  if (kind_ != Kind::Dense) return DenseMatrix();
  const int n = static_cast<int>(dense_.extent(0));
  DenseMatrix a(dense_.label(), n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) a(i, j) = dense_(j, i);
  return a;
}

BodyOperator BodyOperator::sparse(const SparseRows& a, const std::string& label) {
  BodyOperator op;
  op.kind_ = Kind::Sparse;
  const int n = a.rows();
  Sparse::row_map_type::non_const_type rows(label + "::rows", n + 1);
  Sparse::index_type::non_const_type cols(label + "::cols", a.cols.size());
  Sparse::values_type::non_const_type values(label + "::values", a.values.size());
  auto rh = Kokkos::create_mirror_view(rows);
  auto ch = Kokkos::create_mirror_view(cols);
  auto vh = Kokkos::create_mirror_view(values);
  for (int i = 0; i <= n; ++i) rh(i) = a.rowStart[i];
  for (std::size_t k = 0; k < a.values.size(); ++k) {
    ch(k) = a.cols[k];
    vh(k) = a.values[k];
  }
  Kokkos::deep_copy(rows, rh);
  Kokkos::deep_copy(cols, ch);
  Kokkos::deep_copy(values, vh);
  op.sparse_ = Sparse(label, n, n, a.values.size(), values, rows, cols);
  return op;
}

BodyOperator BodyOperator::diagonal(const std::vector<double>& d, const std::string& label) {
  BodyOperator op;
  op.kind_ = Kind::Diagonal;
  op.diagonal_ = DenseVector(label, d.size());
  auto h = Kokkos::create_mirror_view(op.diagonal_);
  for (std::size_t i = 0; i < d.size(); ++i) h(i) = d[i];
  Kokkos::deep_copy(op.diagonal_, h);
  return op;
}

BodyOperator BodyOperator::denseOrDiagonal(const std::vector<double>& a, int n, const std::string& label) {
  std::vector<double> d(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double v = a[static_cast<std::size_t>(j) * n + i];
      if (i == j)
        d[i] = v;
      else if (v != 0.0)
        return dense(a, n, label);
    }
  return diagonal(d, label);
}

std::size_t BodyOperator::bytes() const {
  switch (kind_) {
    case Kind::Dense:
      return dense_.span() * sizeof(double);
    case Kind::Sparse:
      return sparse_.nnz() * (sizeof(double) + sizeof(int)) + (sparse_.numRows() + 1) * sizeof(std::size_t);
    case Kind::Diagonal:
      return diagonal_.span() * sizeof(double);
    default:
      return 0;
  }
}

namespace {
/// forRowBlocks (Epaphe_Parallel.hpp) on an operator of `bytes`: about 50 bytes of the matrix per ns
/// on one core, measured (419 x 419 in 19.5 us; a 112 x 112 one stays on the calling thread). The
/// operator is stored by rows, so a block is one contiguous piece of memory and one BLAS call
/// (transposed) that each core streams from its own cache: 419 x 419 on 2 threads 2.2x faster than
/// on 1, where a block of rows of a column-major matrix (a piece of every column) was 1.3x
/// (adjacent-line prefetch fetched the other core's half too). Blocks start at multiples of 8 rows:
/// OpenBLAS's dgemv_t then gave every row the same bits on 1 and 2 threads (419 x 419; at other
/// boundaries it did not).
template <class F>
void operatorRowBlocks(const char* name, int n, std::size_t bytes, const F& f) {
  forRowBlocks(name, n, static_cast<long>(bytes / 50), 8, f);
}
}  // namespace

void BodyOperator::apply(double alpha, const DenseVector& x, double beta, const DenseVector& y) const {
  // The per-step work of a small dense model is a few microseconds: an OpenMP kernel launch per
  // vector operation would cost more than the work (measured: 2 threads 4.5x slower than 1 on a
  // 112-DOF model). The vectors live in host memory (OpenMP), so dense and diagonal operators run as
  // plain loops and one BLAS dgemv per thread's block of rows; the sparse product the same way
  // (below).
  static_assert(Kokkos::SpaceAccessibility<Kokkos::HostSpace, DenseVector::memory_space>::accessible,
                "the explicit step runs on host memory");
  const int n = static_cast<int>(y.extent(0));
  switch (kind_) {
    case Kind::Dense: {
      const double* A = dense_.data();
      const double* xv = x.data();
      double* yv = y.data();
      operatorRowBlocks(
          "epaphe::dynamics::gemv", n, bytes(), [=](int r0, int r1) {  // rows r0..r1: columns of the storage
            Teuchos::BLAS<int, double>().GEMV(Teuchos::TRANS, n, r1 - r0, alpha, A + static_cast<std::size_t>(r0) * n,
                                              n, xv, 1, beta, yv + r0, 1);
          });
      break;
    }
    case Kind::Sparse: {
      // CSR rows summed in four interleaved partial sums. KokkosKernels 13.2's spmv on the OpenMP
      // space sums each row in one dependent chain of additions (its 4-way unrolled loop is for the
      // Serial space only): latency-bound at about 1 ns per entry (the lumped bar, 1212 rows of up
      // to 36 entries: 30-49 us a product); four chains take the adds' throughput instead.
      const auto rows = sparse_.graph.row_map.data();
      const int* cols = sparse_.graph.entries.data();
      const double* vals = sparse_.values.data();
      const double* xv = x.data();
      double* yv = y.data();
      operatorRowBlocks("epaphe::dynamics::spmv", n, bytes(), [=](int r0, int r1) {
        for (int i = r0; i < r1; ++i) {
          double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
          std::size_t k = rows[i];
          const std::size_t end = rows[i + 1];
          for (; k + 4 <= end; k += 4) {
            s0 += vals[k] * xv[cols[k]];
            s1 += vals[k + 1] * xv[cols[k + 1]];
            s2 += vals[k + 2] * xv[cols[k + 2]];
            s3 += vals[k + 3] * xv[cols[k + 3]];
          }
          for (; k < end; ++k) s0 += vals[k] * xv[cols[k]];
          const double s = alpha * ((s0 + s1) + (s2 + s3));
          yv[i] = beta == 0.0 ? s : s + beta * yv[i];
        }
      });
      break;
    }
    case Kind::Diagonal: {
      const double* d = diagonal_.data();
      const double* xv = x.data();
      double* yv = y.data();
      if (beta == 0.0)
        for (int i = 0; i < n; ++i) yv[i] = alpha * d[i] * xv[i];
      else
        for (int i = 0; i < n; ++i) yv[i] = alpha * d[i] * xv[i] + beta * yv[i];
      break;
    }
    case Kind::None:
      throw Error("BodyOperator: applying an empty operator");
  }
}

void BodyOperator::apply2(const DenseMatrix& x, const DenseMatrix& y) const {
  const int n = static_cast<int>(y.extent(0));
  switch (kind_) {
    case Kind::Dense: {
      const double* A = dense_.data();
      const double* xv = x.data();
      double* yv = y.data();
      const int ldx = static_cast<int>(x.stride(1)), ldy = static_cast<int>(y.stride(1));
      operatorRowBlocks("epaphe::dynamics::gemm2", n, bytes(), [=](int r0, int r1) {
        Teuchos::BLAS<int, double>().GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, r1 - r0, 2, n, 1.0,
                                          A + static_cast<std::size_t>(r0) * n, n, xv, ldx, 0.0, yv + r0, ldy);
      });
      break;
    }
    case Kind::Sparse:
    case Kind::Diagonal:
    case Kind::None:
      for (int c = 0; c < 2; ++c)
        apply(1.0, Kokkos::subview(x, Kokkos::ALL, c), 0.0, Kokkos::subview(y, Kokkos::ALL, c));
      break;
  }
}

}  // namespace epaphe
