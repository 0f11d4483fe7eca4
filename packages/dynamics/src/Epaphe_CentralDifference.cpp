#include "Epaphe_CentralDifference.hpp"

#include "Epaphe_Parallel.hpp"

#include "Epaphe_Error.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace epaphe {
namespace {

/// The massless boundary's operators (ReducedModel::massless(), q = [u_b, eta]): the flexibility P
/// of the common form (dense n x n, column-major), Kmid (the modes' diagonal stiffness), and the
/// factors that predict() and dampingIncrement() apply A, B and D by (below).
struct MasslessOperators {
  std::vector<double> P, Kmid;
  std::vector<double> Ae1, Be1, Pe;  // 1 + A_e, 1 + B_e and P_e (per mode)
  std::vector<double> d, Ginv;       // the modes' damping D_e and G^{-1} (nb x nb)
};

// q = [u_b, eta] (Epaphe_ReducedModel.hpp). The boundary is static, u_b = Phi_b eta + r with the
// residual r = G f in equilibrium with the contact force: the correction of step n (force f_n,
// closing the gaps at t_{n+1}) leaves r_{n+1} = G f_n, so f_n is the force at t_{n+1} and
// f_{n-2} = G^{-1} r_{n-1} the one at t_{n-1}. The modes step by the central difference under
// their average, the force at t_n to second order:
//   eta_{n+1} = 2 eta_n - eta_{n-1} + A_e eta_n + B_e (eta_n - eta_{n-1}) + P_e Phi_b^T (f_n + f_{n-2}) / 2,
// A_e = -P_e Omega^2, B_e = -P_e D_e / h, P_e = (I/h^2 + D_e/2h)^{-1}, all diagonal. The f_{n-2} half
// is W q_{n-1}, W = P_e Phi_b^T G^{-1} L / 2 with L q = u_b - Phi_b eta = r: a term of the
// predictor, carried by A and B. With u_b* = Phi_b eta*, in the common form
//   A = [-I, Phi_b (I + A_e); 0, A_e] + C,  B = [-I, Phi_b (I + B_e); 0, B_e] - C,  C = [Phi_b W; W],
// and the correction q += F f moves eta by P_e Phi_b^T f / 2 and u_b by Phi_b times that plus G f:
//   F = [G + Phi_b P_e Phi_b^T / 2, Phi_b P_e / 2; P_e Phi_b^T / 2, P_e / 2].
// Energy: multiplying the modes' step by (eta_{n+1} - eta_{n-1}) / 2 and splitting
// Phi_b (eta_{n+1} - eta_{n-1}) = (u_{n+1} - u_{n-1}) - (r_{n+1} - r_{n-1}), the average force's work
// on the residual, (r_{n+1} + r_{n-1})^T G^{-1} (r_{n+1} - r_{n-1}) / 4, is exactly the change of the
// stored 1/4 (r_n^T G^{-1} r_n + r_{n+1}^T G^{-1} r_{n+1}): no dissipation, unlike a residual driven
// by f_n alone (which lost 1/4 (r_{n+1} - r_{n-1})^T G^{-1} (r_{n+1} - r_{n-1}) a step: 71 J of 3200 on
// V1). The contact work the run counts, f_n . (u_{n+1} - u_{n-1}) / 2, differs from the average's by
// (f_n - f_{n-2}) . (u_{n+1} - u_{n-1}) / 4 = dq^T L^T G^{-1} E_b dq / 4 (dq = q_{n+1} - q_{n-1},
// E_b q = u_b): an exchange, zero in lasting contact, that the balance counts with the damping as
// h S in D, S = sym(L^T G^{-1} E_b). In a lasting contact with a stiff boundary this is the
// trapezoidal rule on the contact spring over 2h: stable for any boundary stiffness.
// Applied by their factors: with C q_n - C (q_n - q_{n-1}) = C q_{n-1} and the boundary rows
// cancelling, 2 q_n - q_{n-1} + A q_n + B (q_n - q_{n-1}) is eta* = (I + A_e) eta_n + (I + B_e)
// (eta_n - eta_{n-1}) + P_e Phi_b^T z_{n-1} / 2, u_b* = Phi_b eta*, where z = G^{-1} r = G^{-1} L q is
// the residual's force; dq^T (D + h S) dq = sum_k d_k deta_k^2 + h du^T (z_{n+1} - z_{n-1}); and the
// residual's stored energy r^T G^{-1} r = r . z. A step has z once, for q_{n+1}: the contact's force
// f_n (plus the loads' boundary part at t_{n+1}), which r_{n+1} = G f_n makes it, when the loop gives it
// (setContactForce), else G^{-1} r (CentralDifference::residual). The exchange reads it at once, the
// energy record at this step and the next, the predictor two steps later.
MasslessOperators masslessOperators(const ReducedModel& model, double h, const DampingOptions& damping) {
  const int n = model.size;
  const int nb = model.boundarySize(), m = model.numModes;
  const std::vector<double> w2 = model.modalStiffness(), d = modalDamping(model, damping);
  const auto& Phi = model.boundaryModes;
  auto phi = [&](int c, int k) { return Phi[static_cast<std::size_t>(k) * nb + c]; };
  auto at = [n](std::vector<double>& X, int i, int j) -> double& { return X[static_cast<std::size_t>(j) * n + i]; };
  std::vector<double> Ginv =
      spdInverse(model.residualFlexibility, nb, "the residual flexibility of body '" + model.name + "'",
                 "keep fewer modes, or recompute the reduction");
  std::vector<double> P(static_cast<std::size_t>(n) * n, 0.0), Kmid(static_cast<std::size_t>(n), 0.0),
      Pe(static_cast<std::size_t>(m)), Ae1(Pe.size()), Be1(Pe.size());
  for (int k = 0; k < m; ++k) {
    Pe[k] = 1.0 / (1.0 / (h * h) + d[k] / (2 * h));
    Ae1[k] = 1.0 - Pe[k] * w2[k];     // I + A_e, A_e = -P_e Omega^2
    Be1[k] = 1.0 - Pe[k] * d[k] / h;  // I + B_e, B_e = -P_e D_e / h
    at(P, nb + k, nb + k) = 0.5 * Pe[k];
    Kmid[nb + k] = w2[k];
    for (int c = 0; c < nb; ++c) {
      at(P, c, nb + k) = at(P, nb + k, c) = 0.5 * phi(c, k) * Pe[k];
      for (int c2 = 0; c2 < nb; ++c2) at(P, c, c2) += 0.5 * phi(c, k) * Pe[k] * phi(c2, k);
    }
  }
  for (int c = 0; c < nb; ++c)
    for (int c2 = 0; c2 < nb; ++c2) at(P, c, c2) += model.residualFlexibility[static_cast<std::size_t>(c2) * nb + c];
  return {std::move(P), std::move(Kmid), std::move(Ae1), std::move(Be1), std::move(Pe), d, std::move(Ginv)};
}

}  // namespace

CentralDifference::CentralDifference(const ReducedModel& model, double h, const DampingOptions& damping) : h_(h) {
  const int n = model.size;
  EPAPHE_REQUIRE(h > 0 && std::isfinite(h), "time step = " << h << " s; it must be a finite value > 0");
  damped_ = damping.type != DampingType::None;
  dissipative_ = damped_;
  gyroscopic_ = !model.coriolis.empty() && model.speed != 0.0;
  if (gyroscopic_) {
    // dense reduced models only (SceneCheck refuses the others first)
    EPAPHE_REQUIRE(!model.sparse() && !model.massless() &&
                       model.coriolis.size() == static_cast<std::size_t>(n) * static_cast<std::size_t>(n),
                   "body '" << model.name << "': the Coriolis terms are kept on a dense reduced model only, not on a "
                            << model.method() << " model");
    damped_ = true;  // B = -P (D + Omega G_r) / h
  }
  if (model.sparse()) {
    // M = diag(m), D = alpha M, P = [M/h^2 + D/2h]^{-1} and B = -P D / h diagonal, K sparse
    const std::string problem = fullModelDampingProblem(damping);
    EPAPHE_REQUIRE(problem.empty(), "body '" << model.name << "' is a full model with lumped mass: " << problem);
    const double alpha = damping.type == DampingType::Rayleigh ? damping.alpha : 0.0;
    std::vector<double> D(static_cast<std::size_t>(n)), P(D.size()), B(D.size());
    for (int i = 0; i < n; ++i) {
      const double m = model.lumpedMass[i];
      D[i] = alpha * m;
      P[i] = 1.0 / (m / (h * h) + D[i] / (2 * h));  // P = [M/h^2 + D/2h]^{-1}
      B[i] = -P[i] * D[i] / h;                      // B = -P D / h
    }
    // A q_n = -P (K q_n): predict() applies K and keeps K q_n for energies() (no second matrix)
    K_ = BodyOperator::sparse(model.sparseK, "epaphe::dynamics::K");
    kqn_ = DenseVector("epaphe::dynamics::Kqn", n);
    M_ = BodyOperator::diagonal(model.lumpedMass, "epaphe::dynamics::M");
    D_ = BodyOperator::diagonal(D, "epaphe::dynamics::D");
    P_ = BodyOperator::diagonal(P, "epaphe::dynamics::P");
    if (damped_) B_ = BodyOperator::diagonal(B, "epaphe::dynamics::B");
  } else if (model.massless()) {
    // q = [u_b, eta]: the modes step by the central difference under the boundary's averaged force,
    // the boundary is static (masslessOperators, where it is derived)
    MasslessOperators o = masslessOperators(model, h, damping);
    damped_ = true;  // the exchange is counted with damping
    // A, B and D are applied by their factors (predict(), dampingIncrement())
    K_ = BodyOperator::dense(model.K, n, "epaphe::dynamics::K");  // = K_res + diag(Kmid)
    Kmid_ = BodyOperator::diagonal(o.Kmid, "epaphe::dynamics::Kmid");
    M_ = BodyOperator::denseOrDiagonal(model.M, n, "epaphe::dynamics::M");  // diag(0, I)
    P_ = BodyOperator::dense(o.P, n, "epaphe::dynamics::P");
    massless_.boundary = model.boundarySize();
    massless_.on = true;
    massless_.modes = model.numModes;
    massless_.phiB = model.boundaryModes;
    massless_.ae1 = std::move(o.Ae1);
    massless_.be1 = std::move(o.Be1);
    massless_.pe = std::move(o.Pe);
    massless_.damping = std::move(o.d);
    massless_.ginv = std::move(o.Ginv);
    for (Residual& r : massless_.cache) {  // sized once: residual() allocates nothing
      r.q.assign(static_cast<std::size_t>(n), 0.0);
      r.r.assign(static_cast<std::size_t>(massless_.boundary), 0.0);
      r.z.assign(static_cast<std::size_t>(massless_.boundary), 0.0);
    }
  } else {
    const std::vector<double> D = dampingMatrix(model, damping);
    // With the Coriolis terms, the velocity term is (D + Omega G_r) (q_{n+1} - q_{n-1}) / 2h: Omega G_r
    // takes the damping's place in P and B (the header), and M/h^2 + (D + Omega G_r)/2h is not symmetric
    std::vector<double> DG = D;
    if (gyroscopic_)
      for (std::size_t k = 0; k < DG.size(); ++k) DG[k] += model.speed * model.coriolis[k];
    // P = [M/h^2 + (D + Omega G_r)/2h]^{-1}
    std::vector<double> lhs(D.size());
    for (std::size_t k = 0; k < lhs.size(); ++k) lhs[k] = model.M[k] / (h * h) + DG[k] / (2 * h);
    const std::vector<double> P = gyroscopic_
                                      ? generalInverse(lhs, n, "M/h^2 + (D + Omega G)/2h of body '" + model.name + "'",
                                                       "check the mass matrix and the damping coefficients")
                                      : spdInverse(lhs, n, "M/h^2 + D/2h of body '" + model.name + "'",
                                                   "check the mass matrix and the damping coefficients");
    // A = -P K, B = -P (D + Omega G_r) / h
    std::vector<double> A(D.size()), B(D.size());
    Teuchos::BLAS<int, double> blas;
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, -1.0, P.data(), n, model.K.data(), n, 0.0, A.data(), n);
    A_ = BodyOperator::dense(A, n, "epaphe::dynamics::A");
    if (damped_) {
      blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, -1.0 / h, P.data(), n, DG.data(), n, 0.0, B.data(), n);
      B_ = BodyOperator::dense(B, n, "epaphe::dynamics::B");
    }
    K_ = BodyOperator::dense(model.K, n, "epaphe::dynamics::K");
    M_ = BodyOperator::dense(model.M, n, "epaphe::dynamics::M");
    D_ = BodyOperator::dense(D, n, "epaphe::dynamics::D");
    P_ = BodyOperator::dense(P, n, "epaphe::dynamics::P");
    pDense_ = P;
  }
  f_ = DenseVector("epaphe::dynamics::f", n);
  Pf_ = DenseVector("epaphe::dynamics::Pf", n);
  tmp_ = DenseVector("epaphe::dynamics::tmp", n);
  tmp2_ = DenseVector("epaphe::dynamics::tmp2", n);
  pair_ = DenseMatrix("epaphe::dynamics::pair", n, 2);
  image_ = DenseMatrix("epaphe::dynamics::image", n, 2);
}

Flexibility CentralDifference::flexibility() const {
  const DenseMatrix F = P_.denseMatrix();
  return F.extent(0) > 0 ? Flexibility(F) : Flexibility::diagonal(P_.diagonalEntries());
}

void CentralDifference::setConstantForce(const std::vector<double>& f) {
  EPAPHE_REQUIRE(f.size() == f_.extent(0), "external force has " << f.size() << " entries, the model " << f_.extent(0));
  auto fh = Kokkos::create_mirror_view(f_);
  forced_ = false;
  for (std::size_t i = 0; i < f.size(); ++i) {
    fh(i) = f[i];
    forced_ = forced_ || f[i] != 0.0;
  }
  Kokkos::deep_copy(f_, fh);
  P_.apply(1.0, f_, 0.0, Pf_);
  if (massless_.on) {
    // Massless boundary: a body force (the weight, T^T M e_d = [0, Phi^T M e_d]) acts on the modes
    // alone and in full at t_n, P_e f_eta, the boundary following; P holds half of that for the
    // boundary's averaged force (constructor), hence the factor 2.
    for (int c = 0; c < massless_.boundary; ++c)
      EPAPHE_REQUIRE(f[c] == 0.0, "a constant force on the massless boundary's DOF "
                                      << c << " (" << f[c] << "): only the modes carry mass and take body forces");
    epaphe::axpby(0.0, Pf_, 2.0, Pf_);
  }
}

void CentralDifference::addLoad(const std::vector<double>& f0, const LoadTimeFunction& g) {
  const std::size_t n = f_.extent(0);
  EPAPHE_REQUIRE(f0.size() == n, "a load has " << f0.size() << " reduced entries, the model " << n);
  Load load{g, std::vector<double>(n, 0.0), std::vector<double>(n, 0.0), {}, {}};
  // eq. 67: a massless boundary's boundary part acts at t_{n+1} through P (as the contact force), its modal
  // part at t_n through 2 P on the modes (as the constant force); any other model takes f0 at t_n through P
  const std::size_t nb = massless_.on ? static_cast<std::size_t>(massless_.boundary) : 0;
  for (std::size_t i = 0; i < n; ++i)
    (i < nb ? load.next : load.now)[i] = (massless_.on && i >= nb ? 2.0 : 1.0) * f0[i];
  auto times = [&](const std::vector<double>& x) {
    DenseVector in("epaphe::dynamics::load", n), out("epaphe::dynamics::Pload", n);
    auto h = Kokkos::create_mirror_view(in);
    for (std::size_t i = 0; i < n; ++i) h(i) = x[i];
    Kokkos::deep_copy(in, h);
    P_.apply(1.0, in, 0.0, out);
    fence();
    auto o = Kokkos::create_mirror_view(out);
    Kokkos::deep_copy(o, out);
    std::vector<double> r(n);
    for (std::size_t i = 0; i < n; ++i) r[i] = o(i);
    return r;
  };
  load.Pnow = times(load.now);
  load.Pnext = times(load.next);
  // the work counts the force itself: the modal part's factor 2 belongs to P only
  if (massless_.on)
    for (std::size_t i = nb; i < n; ++i) load.now[i] = f0[i];
  loads_.push_back(std::move(load));
  fLoad_.assign(n, 0.0);
  PfLoad_.assign(n, 0.0);
}

std::vector<double> CentralDifference::forceAt(double t) const {
  auto fh = Kokkos::create_mirror_view(f_);
  Kokkos::deep_copy(fh, f_);
  std::vector<double> f(f_.extent(0));
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = fh(i);
  for (const Load& load : loads_) {
    const double g = load.g(t);
    for (std::size_t i = 0; i < f.size(); ++i) f[i] += g * (load.now[i] + load.next[i]);
  }
  return f;
}

double CentralDifference::loadEnergyScale() const {
  double scale = 0;
  for (const Load& load : loads_) {
    double fPf = 0;  // f^T P f, the modal part's factor 2 of a massless boundary kept (a scale)
    for (std::size_t i = 0; i < load.now.size(); ++i) fPf += load.now[i] * load.Pnow[i] + load.next[i] * load.Pnext[i];
    scale += load.g.largest() * load.g.largest() * std::abs(fPf) / 4;
  }
  return scale;
}

void CentralDifference::predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar,
                                double t) const {
  predict(qn, qnm1, qstar);
  if (loads_.empty()) return;
  // f_n = sum_k g_k(t_n) f_k (eqs. 65-67; a massless boundary's boundary part at t_{n+1}), q* += P f_n
  std::fill(fLoad_.begin(), fLoad_.end(), 0.0);
  std::fill(PfLoad_.begin(), PfLoad_.end(), 0.0);
  const std::size_t n = fLoad_.size();
  for (const Load& load : loads_) {
    const double gNow = load.g(t), gNext = massless_.on ? load.g(t + h_) : 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      fLoad_[i] += gNow * load.now[i] + gNext * load.next[i];
      PfLoad_[i] += gNow * load.Pnow[i] + gNext * load.Pnext[i];
    }
  }
  double* qs = qstar.data();
  for (std::size_t i = 0; i < n; ++i) qs[i] += PfLoad_[i];
}

void CentralDifference::predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar) const {
  const int n = static_cast<int>(qn.extent(0));
  double* qs = qstar.data();
  const double* q0 = qn.data();
  const double* q1 = qnm1.data();
  if (massless_.on) {
    // The massless boundary's A and B by their factors (masslessOperators): with C q_n - C (q_n -
    // q_{n-1}) = C q_{n-1} and the boundary's rows cancelling, the same predictor is
    //   eta* = (1 + A_e) eta_n + (1 + B_e) (eta_n - eta_{n-1}) + P_e Phi_b^T z_{n-1} / 2,  u_b* = Phi_b eta*
    // (the boundary follows the modes), z_{n-1} = G^{-1} r_{n-1} made at step n-2 for the exchange:
    // 2 nb m products instead of 2 n^2 (1.9k against 9.2k on rotor 37's 68 DOFs), equal to the dense
    // form to round-off.
    const int nb = massless_.boundary, m = massless_.modes;
    double* eta = qs + nb;
    const Residual& prev = residual(q1);
    Teuchos::BLAS<int, double> blas;
    blas.GEMV(Teuchos::TRANS, nb, m, 1.0, massless_.phiB.data(), nb, prev.z.data(), 1, 0.0, eta, 1);  // Phi_b^T z_{n-1}
    for (int k = 0; k < m; ++k)
      eta[k] =
          0.5 * massless_.pe[k] * eta[k] + massless_.ae1[k] * q0[nb + k] + massless_.be1[k] * (q0[nb + k] - q1[nb + k]);
    blas.GEMV(Teuchos::NO_TRANS, nb, m, 1.0, massless_.phiB.data(), nb, eta, 1, 0.0, qs, 1);  // Phi_b eta*
    if (forced_) {
      const double* pf = Pf_.data();
      for (int i = 0; i < n; ++i) qs[i] += pf[i];
    }
    return;
  }
  for (int i = 0; i < n; ++i) qs[i] = 2.0 * q0[i] - q1[i];  // 2 q_n - q_{n-1}
  if (kqn_.extent(0) > 0) {                                 // + A q_n = -P (K q_n), K q_n kept
    K_.apply(1.0, qn, 0.0, kqn_);
    fence();
    const double* kq = kqn_.data();
    const double* p = P_.diagonalEntries().data();
    for (int i = 0; i < n; ++i) qs[i] -= p[i] * kq[i];
    kqnOf_ = q0;
  } else {
    A_.apply(1.0, qn, 1.0, qstar);
  }
  if (damped_) {  // + B (q_n - q_{n-1})
    double* d = tmp_.data();
    for (int i = 0; i < n; ++i) d[i] = q0[i] - q1[i];
    B_.apply(1.0, tmp_, 1.0, qstar);
  }
  if (forced_) {  // + P f
    const double* pf = Pf_.data();
    for (int i = 0; i < n; ++i) qs[i] += pf[i];
  }
}

CentralDifference::Residual& CentralDifference::entry(const double* q, bool& made) const {
  const std::size_t n = static_cast<std::size_t>(massless_.boundary + massless_.modes);
  ++massless_.uses;
  made = false;
  for (Residual& s : massless_.cache)  // the same values give the same z: a pure function of q
    if (s.used > 0 && std::memcmp(s.q.data(), q, n * sizeof(double)) == 0) {
      s.used = massless_.uses;
      return s;
    }
  // a new q replaces the least recently used entry: never the one the previous call returned
  Residual& s = *std::min_element(massless_.cache.begin(), massless_.cache.end(),
                                  [](const Residual& x, const Residual& y) { return x.used < y.used; });
  s.used = massless_.uses;
  made = true;
  const int nb = massless_.boundary, m = massless_.modes;
  std::copy(q, q + n, s.q.data());
  std::copy(q, q + nb, s.r.data());
  Teuchos::BLAS<int, double> blas;
  blas.GEMV(Teuchos::NO_TRANS, nb, m, -1.0, massless_.phiB.data(), nb, q + nb, 1, 1.0, s.r.data(),
            1);  // r = u_b - Phi_b eta
  return s;
}

const CentralDifference::Residual& CentralDifference::residual(const double* q) const {
  bool made = false;
  Residual& s = entry(q, made);
  if (!made) return s;
  // z = G^{-1} r, one block of rows per thread of the team when it pays (forRowBlocks: G^{-1} is
  // symmetric, so rows r0..r1 are columns r0..r1 of its storage, one contiguous piece each thread
  // streams; blocks at multiples of 8 rows, the same bits on 1 and 2 threads as BodyOperator's)
  const int nb = massless_.boundary;
  const double* ginv = massless_.ginv.data();
  const double* r = s.r.data();
  double* z = s.z.data();
  forRowBlocks("epaphe::dynamics::residual_force", nb, static_cast<long>(nb) * nb * sizeof(double) / 50, 8,
               [=](int r0, int r1) {
                 Teuchos::BLAS<int, double>().GEMV(Teuchos::TRANS, nb, r1 - r0, 1.0,
                                                   ginv + static_cast<std::size_t>(r0) * nb, nb, r, 1, 0.0, z + r0, 1);
               });
  fence();
  return s;
}

void CentralDifference::setContactForce(const DenseVector& qNext, const DenseVector& g) const {
  if (!massless_.on) return;
  fence();
  bool made = false;
  Residual& s = entry(qNext.data(), made);
  // z = g_b + f_b(t_{n+1}): the loads' boundary part of this step's predict(..., t) (fLoad_'s first
  // nb entries hold g_k(t_{n+1}) times it, addLoad())
  const double* gb = g.data();
  for (int c = 0; c < massless_.boundary; ++c) s.z[c] = gb[c] + (loads_.empty() ? 0.0 : fLoad_[c]);
}

std::vector<double> CentralDifference::residualForces(const double* qn, const double* qnm1) const {
  if (!massless_.on) return {};
  std::vector<double> z(residual(qnm1).z);
  const std::vector<double>& zn = residual(qn).z;
  z.insert(z.end(), zn.begin(), zn.end());
  return z;
}

void CentralDifference::restoreResidualForces(const double* qn, const double* qnm1, const double* z) const {
  if (!massless_.on) return;
  const int nb = massless_.boundary;
  bool made = false;
  std::copy(z, z + nb, entry(qnm1, made).z.begin());
  std::copy(z + nb, z + 2 * nb, entry(qn, made).z.begin());
}

void CentralDifference::setStiffness(const std::vector<double>& K) {
  const int n = static_cast<int>(f_.extent(0));
  EPAPHE_REQUIRE(!gyroscopic_, "CentralDifference::setStiffness: a run-up keeps no Coriolis terms");
  EPAPHE_REQUIRE(!pDense_.empty() && K.size() == pDense_.size(),
                 "CentralDifference::setStiffness: a dense reduced model of size " << n << " only (" << K.size()
                                                                                   << " entries given)");
  aDense_.resize(K.size());
  // A = -P K
  Teuchos::BLAS<int, double> blas;
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, -1.0, pDense_.data(), n, K.data(), n, 0.0, aDense_.data(),
            n);
  A_.assignDense(aDense_);
  K_.assignDense(K);
}

double CentralDifference::halfStepEnergy(const DenseVector& qn, const DenseVector& qnp1) const {
  return energies(qn, qnp1, qnp1).total;  // (any third vector: only E_{n+1/2} is read)
}

double CentralDifference::dampingIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const {
  if (!damped_) return 0.0;
  if (!dissipative_ && !massless_.on) return 0.0;  // Coriolis alone: dq^T (Omega G_r) dq = 0, G_r skew
  if (massless_.on) {
    // dq^T (D + h S) dq by its factors (masslessOperators): sum_k d_k deta_k^2 + h du^T (z_{n+1} -
    // z_{n-1}), z = G^{-1} r the residual's force (z_{n+1} made here, z_{n-1} two steps ago)
    const int nb = massless_.boundary, m = massless_.modes;
    const double* a = qnp1.data();
    const double* b = qnm1.data();
    const Residual& za = residual(a);
    const Residual& zb = residual(b);  // (za stays valid: the least recently used entry is replaced)
    double modal = 0.0;
    for (int k = 0; k < m; ++k) modal += massless_.damping[k] * (a[nb + k] - b[nb + k]) * (a[nb + k] - b[nb + k]);
    double exchange = 0.0;
    for (int c = 0; c < nb; ++c) exchange += (a[c] - b[c]) * (za.z[c] - zb.z[c]);
    return (modal + h_ * exchange) / (4 * h_);
  }
  copy(tmp2_, qnp1);
  epaphe::axpby(-1.0, qnm1, 1.0, tmp2_);
  D_.apply(1.0, tmp2_, 0.0, tmp_);
  return epaphe::dot(tmp2_, tmp_) / (4 * h_);
}

double CentralDifference::externalWorkIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const {
  if (!forced_ && loads_.empty()) return 0.0;
  copy(tmp2_, qnp1);
  epaphe::axpby(-1.0, qnm1, 1.0, tmp2_);
  double work = forced_ ? 0.5 * epaphe::dot(f_, tmp2_) : 0.0;
  if (!loads_.empty()) {  // f_n . (q_{n+1} - q_{n-1}) / 2 with the loads' f_n of the step's predict
    fence();
    const double* dq = tmp2_.data();
    double s = 0.0;
    for (std::size_t i = 0; i < fLoad_.size(); ++i) s += fLoad_[i] * dq[i];
    work += 0.5 * s;
  }
  return work;
}

double CentralDifference::strain(const DenseVector& q) const {
  K_.apply(1.0, q, 0.0, tmp_);
  return 0.5 * epaphe::dot(q, tmp_);
}

CentralDifference::EnergyTerms CentralDifference::energies(const DenseVector& qn, const DenseVector& qnp1,
                                                           const DenseVector& v) const {
  const int n = static_cast<int>(qn.extent(0));
  double* X = pair_.data();
  const double* Y = image_.data();
  const double* a = qn.data();
  const double* b = qnp1.data();
  const double* w = v.data();
  auto dotColumn = [n](const double* x, const double* y) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += x[i] * y[i];
    return s;
  };
  EnergyTerms e;
  // M [(q_{n+1} - q_n) / h, v]
  for (int i = 0; i < n; ++i) {
    X[i] = (b[i] - a[i]) / h_;
    X[n + i] = w[i];
  }
  M_.apply2(pair_, image_);
  const double kinHalf = 0.5 * dotColumn(X, Y);
  e.kinetic = 0.5 * dotColumn(X + n, Y + n);
  if (!massless_.on) {
    // One product K q_n serves both terms, K being symmetric: q_n^T K q_{n+1} = q_{n+1}^T (K q_n);
    // a lumped model takes it from the predictor, without a product.
    const bool kept = kqnOf_ == a;  // the step's own q_n: predict() made K q_n
    if (!kept) K_.apply(1.0, qn, 0.0, tmp_);
    const double* Kqn = kept ? kqn_.data() : tmp_.data();
    e.total = kinHalf + 0.5 * dotColumn(b, Kqn);
    e.strain = 0.5 * dotColumn(a, Kqn);
    return e;
  }
  // massless boundary: K = K_res + diag(Kmid), q^T K_res q = r^T G^{-1} r = r . z (the residual's
  // force z, made for the exchange); E_{n+1/2} as in halfStepEnergy()
  const Residual& rn = residual(a);
  const Residual& rn1 = residual(b);  // (rn stays valid: the least recently used entry is replaced)
  const double* km = Kmid_.diagonalEntries().data();
  double mid = 0.0, own = 0.0;
  for (int i = 0; i < n; ++i) {
    mid += a[i] * km[i] * b[i];
    own += a[i] * km[i] * a[i];
  }
  double resN = 0.0, resN1 = 0.0;
  for (int c = 0; c < massless_.boundary; ++c) {
    resN += rn.r[c] * rn.z[c];
    resN1 += rn1.r[c] * rn1.z[c];
  }
  e.total = kinHalf + 0.5 * mid + 0.25 * (resN + resN1);
  e.strain = 0.5 * (resN + own);
  return e;
}

double CentralDifference::kinetic(const DenseVector& v) const {
  M_.apply(1.0, v, 0.0, tmp_);
  return 0.5 * epaphe::dot(v, tmp_);
}

}  // namespace epaphe
