#include "Epaphe_SceneBody.hpp"

#include "Epaphe_Parallel.hpp"

#include <Teuchos_BLAS.hpp>

#include <algorithm>

namespace epaphe {

NodeRecovery::NodeRecovery(const ReducedModel& rom, const std::vector<int>& nodes, const std::string& label)
    : size_(rom.size) {
  if (rom.sparse()) {
    index_ = rom.recoveryIndex(nodes);
    return;
  }
  R_ = DenseMatrix(label, 3 * nodes.size(), rom.size);
  auto Rh = Kokkos::create_mirror_view(R_);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int d = 0; d < 3; ++d)
      for (int j = 0; j < rom.size; ++j) Rh(3 * k + d, j) = rom.recoveryRow(nodes[k], d)[j];
  Kokkos::deep_copy(R_, Rh);
}

void NodeRecovery::apply(const DenseVector& q, const DenseVector& u) const {
  if (index_.empty()) {  // u = R q: one BLAS dgemv on the host (no kernel launch for a few rows)
    const int m = static_cast<int>(R_.extent(0)), n = static_cast<int>(R_.extent(1));
    Teuchos::BLAS<int, double>().GEMV(Teuchos::NO_TRANS, m, n, 1.0, R_.data(), m, q.data(), 1, 0.0, u.data(), 1);
    return;
  }
  auto uh = Kokkos::create_mirror_view(u);
  auto qh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), q);
  for (std::size_t i = 0; i < index_.size(); ++i) uh(i) = index_[i] >= 0 ? qh(index_[i]) : 0.0;
  Kokkos::deep_copy(u, uh);
}

// Called with a fixed column count (HistoryOutput pads its chunks), so that a column's result, each
// entry a sum over k in the kernel's order, does not depend on which columns share the call: a
// restart regroups the records.
void NodeRecovery::applyColumns(const double* X, int cols, double* Y) const {
  const std::size_t m = rows(), n = static_cast<std::size_t>(size_);
  if (!index_.empty()) {
    for (int j = 0; j < cols; ++j)
      for (std::size_t i = 0; i < m; ++i) Y[j * m + i] = index_[i] >= 0 ? X[j * n + index_[i]] : 0.0;
    return;
  }
  // One dgemm per thread on its block of R's rows (the watched DOFs), as one parallel region when
  // the product pays for it (about 10 multiply-adds a ns on one core: cube-rings' 1176 x 419 x 64,
  // 31.5 million, took 2.6 us of its 1-thread step and ran on one thread of two). Blocks at multiples
  // of 16 rows, the dgemm kernel's row tile; each entry's sum over k came out the same on 1 and 2
  // threads (cube-rings' histories; simulation.node-recovery asserts it).
  const double* R = R_.data();
  const int mi = static_cast<int>(m), ni = static_cast<int>(n);
  forRowBlocks("epaphe::output::recover", mi, static_cast<long>(m * n * static_cast<std::size_t>(cols) / 10), 16,
               [=](int r0, int r1) {
                 Teuchos::BLAS<int, double>().GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, r1 - r0, cols, ni, 1.0, R + r0,
                                                   mi, X, ni, 0.0, Y + r0, mi);
               });
  fence();
}

}  // namespace epaphe
