#include "Epaphe_SceneBody.hpp"

#include <Teuchos_BLAS.hpp>

#include <algorithm>

namespace epaphe {

NodeRecovery::NodeRecovery(const ReducedModel& rom, const std::vector<int>& nodes, const std::string& label) {
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

void NodeRecovery::apply(const DenseVector& q, const DenseVector& v, const DenseVector& u, const DenseVector& w) const {
  if (!index_.empty()) {
    apply(q, u);
    apply(v, w);
    return;
  }
  const int m = static_cast<int>(R_.extent(0)), n = static_cast<int>(R_.extent(1));
  X_.resize(2 * static_cast<std::size_t>(n));
  Y_.resize(2 * static_cast<std::size_t>(m));
  std::copy(q.data(), q.data() + n, X_.begin());
  std::copy(v.data(), v.data() + n, X_.begin() + n);
  Teuchos::BLAS<int, double>().GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, m, 2, n, 1.0, R_.data(), m, X_.data(), n,
                                    0.0, Y_.data(), m);
  std::copy(Y_.begin(), Y_.begin() + m, u.data());
  std::copy(Y_.begin() + m, Y_.end(), w.data());
}

}  // namespace epaphe
