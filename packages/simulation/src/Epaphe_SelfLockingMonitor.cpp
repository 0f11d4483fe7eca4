#include "Epaphe_SelfLockingMonitor.hpp"

#include "Epaphe_SurfaceContact.hpp"

#include <Teuchos_LAPACK.hpp>

#include <cmath>
#include <limits>

namespace epaphe {

std::vector<double> staticContactCompliance(const ReducedModel& rom, const std::vector<int>& nodes) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> S(9 * nodes.size(), nan);
  if (nodes.empty() || rom.sparse()) return S;
  std::vector<int> dof;  // the nodes' DOFs in q
  for (int node : nodes)
    for (int d = 0; d < 3; ++d) dof.push_back(rom.nodeDof[3 * node + d]);
  for (int i : dof)
    if (i < 0) return S;
  const int m = static_cast<int>(dof.size());
  std::vector<double> X;  // (K^{-1})[:, dof] restricted to dof rows: m x m, column-major
  if (rom.massless()) {
    // eq. (13): (K^{-1})_bb = G + Phi_b Omega^{-2} Phi_b^T (a free body's Omega = 0: none)
    const int nb = rom.boundarySize();
    const std::vector<double> w2 = rom.modalStiffness();
    for (double w : w2)
      if (!(w > 0.0)) return S;
    X.assign(static_cast<std::size_t>(m) * m, 0.0);
    for (int c = 0; c < m; ++c)
      for (int r = 0; r < m; ++r) {
        double s = rom.residualFlexibility[static_cast<std::size_t>(dof[c]) * nb + dof[r]];
        for (int k = 0; k < rom.numModes; ++k)
          s += rom.boundaryModes[static_cast<std::size_t>(k) * nb + dof[r]] *
               rom.boundaryModes[static_cast<std::size_t>(k) * nb + dof[c]] / w2[k];
        X[static_cast<std::size_t>(c) * m + r] = s;
      }
  } else {
    // a dense K: one LU, solved for the unit columns at the nodes' DOFs
    const int n = rom.size;
    std::vector<double> K = rom.K, B(static_cast<std::size_t>(n) * m, 0.0);
    for (int c = 0; c < m; ++c) B[static_cast<std::size_t>(c) * n + dof[c]] = 1.0;
    std::vector<int> ipiv(n);
    int info = 0;
    Teuchos::LAPACK<int, double> lapack;
    lapack.GETRF(n, n, K.data(), n, ipiv.data(), &info);
    if (info != 0) return S;  // singular: a free body
    lapack.GETRS('N', n, m, K.data(), n, ipiv.data(), B.data(), n, &info);
    if (info != 0) return S;
    X.assign(static_cast<std::size_t>(m) * m, 0.0);
    for (int c = 0; c < m; ++c)
      for (int r = 0; r < m; ++r) X[static_cast<std::size_t>(c) * m + r] = B[static_cast<std::size_t>(c) * n + dof[r]];
  }
  for (std::size_t a = 0; a < nodes.size(); ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) S[9 * a + 3 * i + j] = X[(3 * a + j) * static_cast<std::size_t>(m) + 3 * a + i];
  return S;
}

namespace {
void keep(LockRecord& least, LockRecord& first, double margin, int node, double t) {
  if (node < 0) return;
  if (least.node < 0 || margin < least.margin) least = {margin, node, t};
  if (first.node < 0 && margin <= 0.0) first = {margin, node, t};
}
}  // namespace

void SelfLockingMonitor::afterCorrect(ExplicitLoop& loop) {
  const SurfaceContact* contact = contact_;
  if (contact == nullptr) return;
  const SelfLocking* lock = contact->enforcement().selfLocking();
  if (lock == nullptr || lock->sliding == 0) return;
  checks_ += lock->sliding;
  const double t = loop.time() + h_;
  keep(least_, first_, lock->margin, lock->node, t);
  keep(leastStep_, firstStep_, lock->stepMargin, lock->stepNode, t);
}

}  // namespace epaphe
