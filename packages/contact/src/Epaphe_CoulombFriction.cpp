#include "Epaphe_CoulombFriction.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_SmallDense.hpp"

#include <cmath>
#include <type_traits>

namespace epaphe {

CoulombFriction::CoulombFriction(double mu, bool penalty, double kp, double h, int nc,
                                 std::unique_ptr<ContactEnforcement> frictionless, bool warm)
    : mu_(mu), kp_(kp), h_(h), penalty_(penalty), warm_(warm), frictionless_(std::move(frictionless)) {
  EPAPHE_REQUIRE(std::isfinite(mu_) && mu_ > 0.0,
                 "contact: friction coefficient mu = " << mu_ << "; Coulomb friction needs a finite value > 0");
  basis_ = Kokkos::View<double* [3][3]>("epaphe::contact::basis", nc);
  disp_ = Kokkos::View<double* [3]>("epaphe::contact::motion", nc);
  local_ = Kokkos::View<double** [3][3]>("epaphe::contact::local_flexibility", nc, nc);
  column_ = Kokkos::View<double* [3]>("epaphe::contact::sliding_column", nc);
  force_ = Kokkos::View<double* [3]>("epaphe::contact::node_force", nc);
  state_ = Kokkos::View<int*>("epaphe::contact::state", nc);
  nextState_ = Kokkos::View<int*>("epaphe::contact::next_state", nc);
  returns_ = Kokkos::View<int*>("epaphe::contact::slide_to_stick", nc);
  bestState_ = Kokkos::View<int*>("epaphe::contact::best_state", nc);
  nextTangent_ = Kokkos::View<double* [3]>("epaphe::contact::next_tangent", nc);
  bestTangent_ = Kokkos::View<double* [3]>("epaphe::contact::best_tangent", nc);
  sys_.MCf = Kokkos::View<double**, Kokkos::LayoutLeft>("epaphe::contact::friction_matrix", 3 * nc, 3 * nc);
  sys_.sol = Kokkos::View<double*>("epaphe::contact::friction_solution", 3 * nc);
  sys_.rhs = Kokkos::View<double*>("epaphe::contact::friction_rhs", 3 * nc);
  sys_.unknownOffset = Kokkos::View<int*>("epaphe::contact::friction_unknowns", nc + 1);
  sys_.unknownOffsetH = Kokkos::create_mirror_view(sys_.unknownOffset);
  sys_.MCfH = Kokkos::create_mirror_view(sys_.MCf);
  sys_.solH = Kokkos::create_mirror_view(sys_.sol);
  sys_.rhsH = Kokkos::create_mirror_view(sys_.rhs);
  prev_ = Kokkos::View<int*>("epaphe::contact::previous_state", nc);
  prevTangent_ = Kokkos::View<double* [3]>("epaphe::contact::previous_tangent", nc);
  keep_.reserve(nc);
  sys_.ipiv.reserve(3 * static_cast<std::size_t>(nc));
}

Teuchos::RCP<const Teuchos::ParameterList> CoulombFriction::getValidParameters() {
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Coulomb friction"));
  deck::addDouble(*pl, "Friction coefficient", 0.0,
                  "Coulomb mu: the correction acts along n + mu t, t opposing the "
                  "sliding (eqs. 2.29, 2.31), capped so that a node sticks rather "
                  "than slides back",
                  0.0);
  deck::addBool(*pl, "Warm friction start", true,
                "A node in contact at the last step starts its stick/slip "
                "classification from that step's final state and sliding "
                "direction (usually one pass) instead of from its predicted "
                "motion; false: always from the predicted motion");
  return pl;
}

void CoulombFriction::enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
                              const DenseVector* qn) {
  if (qn == nullptr) {  // no motion over the step: no friction direction
    lock_ = SelfLocking{};
    frictionless_->enforce(v, active, q, qn);
    return;
  }
  prepare(v, active, q, *qn);
  solve(v, active);
}

namespace {
/// Node k's unknowns (lambda, s1, s2) act along columns c_j in its own basis (n, e1, e2): stuck,
/// the force lambda n + s1 e1 + s2 e2, c_j = the unit vectors; sliding, lambda (n + mu t) and no
/// tangential unknowns (their rows are s1 = s2 = 0): c_0 = (1 + mu t.n, mu t.e1, mu t.e2) (t is
/// tangential, t.n = 0 to round-off, kept so that c_0 is n + mu t exactly). Returns whether it slides.
template <class B, class T, class S>
KOKKOS_INLINE_FUNCTION bool slidingColumn(const B& basis, const T& tangent, const S& state, int k, double mu, int slide,
                                          double c0[3]) {
  if (state(k) != slide) return false;
  for (int i = 0; i < 3; ++i) {
    double s = 0.0;
    for (int e = 0; e < 3; ++e) s += tangent(k, e) * basis(k, i, e);
    c0[i] = (i == 0 ? 1.0 : 0.0) + mu * s;
  }
  return true;
}
}  // namespace

void CoulombFriction::prepare(const ContactStepViews& v, const std::vector<int>& activeH, const DenseVector& q,
                              const DenseVector& qn) {
  // Per node: d_a = u_a(q*) - u_a(q_n), the tangent-plane basis (e1, e2) of n_a, and the initial
  // state: sliding against the predicted tangential motion (t = -d_t / |d_t|) when there is one,
  // stuck otherwise.
  const auto normal = v.normal;
  const auto basis = unmanaged(basis_);
  const auto disp = unmanaged(disp_);
  const auto tangent = v.tangent;
  const auto state = unmanaged(state_);
  const auto returns = unmanaged(returns_);
  const auto x = v.x;
  const RelativeMotion D = v.D;
  const Difference<DenseVector> dq{unmanaged(q), unmanaged(qn)};
  const auto surfOf = v.surf;
  const auto turn = v.turn;
  const auto footX = v.footX;
  const double h = h_;
  const bool warm = warm_;
  const auto prev = unmanaged(prev_);
  const auto prevTangent = unmanaged(prevTangent_);
  const auto active = v.upload(activeH);
  forEach(
      "epaphe::contact::friction_prepare", static_cast<int>(activeH.size()), 60, KOKKOS_LAMBDA(const int a) {
        const int k = active(a);  // the active nodes only: nothing reads the others' state
        double n[3], dsp[3], dn = 0.0, dd = 0.0, xx = 0.0;
        for (int e = 0; e < 3; ++e) n[e] = normal(k, e);
        D.apply(k, dq, dsp);  // relative motion d_a = D_a (q* - q_n)
        if (surfOf(k) >= 0 && turn(surfOf(k), 0) != 0.0) {
          // less the turning surface's own motion over the step, h omega a x (S - c)
          const int s = surfOf(k);
          const double w = h * turn(s, 0);
          const double r[3] = {footX(k, 0) - turn(s, 4), footX(k, 1) - turn(s, 5), footX(k, 2) - turn(s, 6)};
          const double a[3] = {turn(s, 1), turn(s, 2), turn(s, 3)};
          dsp[0] -= w * (a[1] * r[2] - a[2] * r[1]);
          dsp[1] -= w * (a[2] * r[0] - a[0] * r[2]);
          dsp[2] -= w * (a[0] * r[1] - a[1] * r[0]);
        }
        for (int e = 0; e < 3; ++e) {
          disp(k, e) = dsp[e];
          dn += dsp[e] * n[e];
          dd += dsp[e] * dsp[e];
          xx += x(k, e) * x(k, e);
        }
        // e1: the coordinate axis least aligned with n, made orthogonal to n; e2 = n x e1
        const int ax =
            ::fabs(n[0]) <= ::fabs(n[1]) && ::fabs(n[0]) <= ::fabs(n[2]) ? 0 : (::fabs(n[1]) <= ::fabs(n[2]) ? 1 : 2);
        double e1[3] = {0.0, 0.0, 0.0};
        e1[ax] = 1.0;
        double an = n[ax], l1 = 0.0;
        for (int e = 0; e < 3; ++e) {
          e1[e] -= an * n[e];
          l1 += e1[e] * e1[e];
        }
        l1 = ::sqrt(l1);
        for (int e = 0; e < 3; ++e) e1[e] /= l1;
        const double e2[3] = {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
        for (int e = 0; e < 3; ++e) {
          basis(k, 0, e) = n[e];
          basis(k, 1, e) = e1[e];
          basis(k, 2, e) = e2[e];
        }
        double dt[3], tt = 0.0;
        for (int e = 0; e < 3; ++e) {
          dt[e] = dsp[e] - dn * n[e];
          tt += dt[e] * dt[e];
        }
        const double len = ::sqrt(tt);
        const bool moving = len > 1e-14 * (::sqrt(xx) + ::sqrt(dd));
        for (int e = 0; e < 3; ++e) tangent(k, e) = moving ? -dt[e] / len : 0.0;
        state(k) = moving ? kSlide : kStick;
        returns(k) = 0;
        if (warm && prev(k) == kStick) {
          state(k) = kStick;
        } else if (warm && prev(k) == kSlide) {
          // last step's sliding direction, in this step's tangent plane
          double t[3], tn = 0.0, tl = 0.0;
          for (int e = 0; e < 3; ++e) tn += prevTangent(k, e) * n[e];
          for (int e = 0; e < 3; ++e) {
            t[e] = prevTangent(k, e) - tn * n[e];
            tl += t[e] * t[e];
          }
          tl = ::sqrt(tl);
          if (tl > 0.5) {
            state(k) = kSlide;
            for (int e = 0; e < 3; ++e) tangent(k, e) = t[e] / tl;
          }
        }
      });
  fence();
}

void CoulombFriction::solve(const ContactStepViews& v, std::vector<int>& activeH) {
  // Joint solve over the active set, 3 unknowns per active node a (lambda_a, s1_a, s2_a):
  //   normal row:     g*_a + n_a^T sum_b F_ab f_b = 0, f_b the force on node b (the gap closes;
  //                   penalty: lambda_a = k_p (-g*_a) instead);
  //   stuck, rows i:  e_i,a^T (d_a + sum_b F_ab f_b) = 0  (no tangential motion over the step);
  //   sliding:        s1_a = s2_a = 0, the node's force being lambda_a (n_a + mu t_a).
  // Then classify: stuck -> sliding when |s_a| > mu lambda_a (t_a = s_a / |s_a|); sliding -> stuck
  // when the corrected tangential motion w_a does not oppose t_a (w_a . t_a > 0), else t_a follows
  // -w_a / |w_a|. Repeat while anything changes (at most kMaxFrictionPasses; then the pass with the
  // fewest changes is solved again and kept). Lagrange nodes with lambda_a < 0 are released.
  const bool penalty = penalty_;
  const int nc = static_cast<int>(v.force.extent(0));
  const int ld = 3 * nc;
  int bestChanges = -1, passes = 0, releases = 0;
  bool restored = false;
  int nA = static_cast<int>(activeH.size());
  localFlexibility(v, v.upload(activeH), nA);  // releases only remove nodes: it covers every pass
  for (;;) {
    const auto active = v.upload(activeH);
    countUnknowns(v, activeH, nA);
    assembleSystem(v, active, nA);
    solveSystem(v, activeH, nA, ld);
    if (!penalty && releasePulled(activeH, nA, releases, nc)) {  // release the nodes the surface would pull
      if (nA == 0) break;
      continue;
    }
    if (restored) break;
    const int changes = classify(v, active, nA);
    if (changes == 0) break;
    if (bestChanges < 0 || changes < bestChanges) {
      bestChanges = changes;
      copy(bestState_, state_);
      copy(bestTangent_, v.tangent);
    }
    if (++passes == kMaxFrictionPasses) {  // not settled: solve again with the best pass's states
      copy(state_, bestState_);
      copy(v.tangent, bestTangent_);
      restored = true;
      continue;
    }
    commitClassification(v, active, nA);
  }
  lastPasses_ = passes + 1;
  checkSelfLocking(v, activeH, nA);
  storeForces(v, activeH, nA);
}

void CoulombFriction::setStaticCompliance(const std::vector<double>& blocks) {
  const std::size_t nc = prev_.extent(0);
  EPAPHE_REQUIRE(blocks.empty() || blocks.size() == 9 * nc,
                 "contact: " << blocks.size() << " static compliance entries for " << nc << " nodes (9 each)");
  static_ = blocks;
}

void CoulombFriction::checkSelfLocking(const ContactStepViews& v, const std::vector<int>& activeH, int nA) {
  // Per sliding node a (lambda_a > 0), c_a = n_a + mu t_a:
  //   (48) correction:    m_a = n^T C_aa c_a / n^T C_aa n = (T_aa c_0)_0 / T_aa,00  (c_0: c_a in a's basis)
  //   (50) quasi-static:  m_a = (n^T S_a c_a + kappa) / (n^T S_a n + kappa),  kappa = 1/k_p (penalty) or 0
  // the node is locked when m_a <= 0 (docs/theory/divergence.md). Host loop over the active nodes:
  // the views live in host-accessible memory (the classification's host loops read them too).
  lock_ = SelfLocking{};
  const double kappa = penalty_ ? 1.0 / kp_ : 0.0;
  for (int a = 0; a < nA; ++a) {
    const int k = activeH[a];
    if (state_(k) != kSlide || !(sys_.solH(3 * a) > 0.0)) continue;
    ++lock_.sliding;
    double cn = 0.0;
    for (int j = 0; j < 3; ++j) cn += local_(k, k, 0, j) * column_(k, j);
    const double stepMargin = cn / local_(k, k, 0, 0);
    if (lock_.stepNode < 0 || stepMargin < lock_.stepMargin) {
      lock_.stepMargin = stepMargin;
      lock_.stepNode = k;
    }
    if (static_.empty() || std::isnan(static_[9 * static_cast<std::size_t>(k)])) continue;
    const double* S = &static_[9 * static_cast<std::size_t>(k)];
    double n[3], c[3];
    for (int e = 0; e < 3; ++e) {
      n[e] = basis_(k, 0, e);
      c[e] = n[e] + mu_ * v.tangent(k, e);
    }
    double snn = kappa, snc = kappa;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        snn += n[i] * S[3 * i + j] * n[j];
        snc += n[i] * S[3 * i + j] * c[j];
      }
    const double margin = snc / snn;
    if (lock_.node < 0 || margin < lock_.margin) {
      lock_.margin = margin;
      lock_.node = k;
    }
  }
}

void CoulombFriction::localFlexibility(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA) {
  static_assert(std::is_same<decltype(local_)::array_layout, Kokkos::LayoutRight>::value &&
                    std::is_same<decltype(basis_)::array_layout, Kokkos::LayoutRight>::value &&
                    std::is_same<decltype(v.C)::array_layout, Kokkos::LayoutRight>::value,
                "the friction kernels read 3 x 3 blocks of T, C and the bases as contiguous runs");
  const auto C = v.C;
  const auto basis = unmanaged(basis_);
  const auto T = unmanaged(local_);
  // F is symmetric, so C_ba = C_ab^T and T_ba = T_ab^T: node a makes the blocks b >= a and their
  // transposes (each pair by one thread: no two threads write one block)
  forEach(
      "epaphe::contact::friction_local", nA, 30L * nA, KOKKOS_LAMBDA(const int a) {
        const int ka = active(a);
        const double* Ba = &basis(ka, 0, 0);  // 3 x 3 blocks, contiguous
        for (int bb = a; bb < nA; ++bb) {
          const int kb = active(bb);
          const double* Cab = &C(ka, kb, 0, 0);
          const double* Bb = &basis(kb, 0, 0);
          double* Tab = &T(ka, kb, 0, 0);
          double* Tba = &T(kb, ka, 0, 0);
          double G[3][3];  // G[d][j] = (C_ab e_j,b)_d
          for (int d = 0; d < 3; ++d)
            for (int j = 0; j < 3; ++j) {
              double s = 0.0;
              for (int e = 0; e < 3; ++e) s += Cab[3 * d + e] * Bb[3 * j + e];
              G[d][j] = s;
            }
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
              double s = 0.0;
              for (int d = 0; d < 3; ++d) s += Ba[3 * i + d] * G[d][j];
              Tab[3 * i + j] = s;
              Tba[3 * j + i] = s;  // (on the diagonal block, its own transpose: made symmetric)
            }
        }
      });
  fence();
}

void CoulombFriction::assembleSystem(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA) {
  // Only the unknowns that are not known beforehand: lambda_a unless the normal law is penalty
  // (lambda_a = k_p (-g*_a), eq. 2.34), s1_a and s2_a only while node a sticks (a sliding node's
  // force is lambda_a (n_a + mu t_a), its tangential unknowns are zero). The known forces move to
  // the right-hand side. Node a's first unknown is sys_.unknownOffset(a): a step whose active nodes
  // all slide solves nA (Lagrange) or no unknowns instead of 3 nA. Row i of node a, column j of
  // node b: e_i,a^T C_ab c_j,b = (T_ab c_j,b)_i, c_j,b in b's basis (slidingColumn).
  const bool penalty = penalty_;
  const double kp = kp_;
  constexpr int slide = kSlide;
  const auto off = unmanaged(sys_.unknownOffset);
  const auto T = unmanaged(local_);
  const auto basis = unmanaged(basis_);
  const auto state = unmanaged(state_);
  const auto disp = unmanaged(disp_);
  const auto gap = v.gap;
  const auto A = unmanaged(sys_.MCf);
  const auto rhs = unmanaged(sys_.rhs);
  const auto column = unmanaged(column_);
  const bool rows = v.rows;  // a normal law's own rows (v.row): alpha, beta, gamma; penalty: {0, 1, force}
  const auto row = v.row;
  // Raw pointers into T (T_ab's 3 x 3 entries contiguous, row i at 3 i) and A (column-major,
  // leading dimension 3 nc): the views' multi-index arithmetic was most of this loop's instructions.
  const long ld = static_cast<long>(A.extent(0));  // 3 nc, as solveSystem() reads it
  forEach(
      "epaphe::contact::friction_matrix", nA, 20L * nA, KOKKOS_LAMBDA(const int a) {
        const int ka = active(a);
        const bool sl = state(ka) == slide;
        const int i0 = penalty ? 1 : 0, i1 = sl ? 1 : 3;  // node a's rows: i in [i0, i1)
        double b[3] = {0.0, 0.0, 0.0};                    // right-hand side of rows i
        b[0] = rows ? row(ka, 2) : -gap(ka);
        for (int i = 1; i < 3; ++i)
          for (int d = 0; d < 3; ++d) b[i] -= basis(ka, i, d) * disp(ka, d);
        const double ra0 = rows ? row(ka, 0) : 1.0, ra1 = rows ? row(ka, 1) : 0.0;
        const double* Ta = &T(ka, 0, 0, 0);
        double* Ar = A.data() + off(a) - i0;  // Ar[i + col ld]: row i of node a
        for (int bb = 0; bb < nA; ++bb) {
          const int kb = active(bb);
          const double* Tab = Ta + 9L * kb;
          const int c = off(bb);     // node b's first column
          if (state(kb) == slide) {  // one column, T_ab c_0 (under penalty known: to the right-hand side)
            const double c0 = column(kb, 0), c1 = column(kb, 1), c2 = column(kb, 2);
            const double fb = penalty ? (rows ? row(kb, 2) : kp * (-gap(kb))) : 0.0;
            for (int i = i0; i < i1; ++i) {  // a's rows only: a sliding a has one
              const double y = Tab[3 * i] * c0 + Tab[3 * i + 1] * c1 + Tab[3 * i + 2] * c2;
              if (penalty)
                b[i] -= y * fb;
              else
                Ar[i + c * ld] = i == 0 && rows ? ra0 * y + (bb == a ? ra1 : 0.0) : y;
            }
            continue;
          }
          if (penalty) {  // stuck: its normal column known, its tangential ones solved
            const double fb = rows ? row(kb, 2) : kp * (-gap(kb));
            for (int i = i0; i < i1; ++i) {
              b[i] -= Tab[3 * i] * fb;
              Ar[i + c * ld] = Tab[3 * i + 1];
              Ar[i + (c + 1) * ld] = Tab[3 * i + 2];
            }
            continue;
          }
          for (int i = i0; i < i1; ++i)  // stuck, Lagrange: three columns
            for (int j = 0; j < 3; ++j)
              Ar[i + (c + j) * ld] = i == 0 && rows ? ra0 * Tab[j] + (bb == a && j == 0 ? ra1 : 0.0) : Tab[3 * i + j];
        }
        for (int i = i0; i < i1; ++i) rhs(off(a) + i - i0) = b[i];
      });
  fence();
}

void CoulombFriction::countUnknowns(const ContactStepViews& v, const std::vector<int>& activeH, int nA) {
  int m = 0;
  double c0[3];
  for (int a = 0; a < nA; ++a) {
    sys_.unknownOffsetH(a) = m;
    m += (penalty_ ? 0 : 1) + (state_(activeH[a]) == kSlide ? 0 : 2);
    // this pass's sliding columns, read by every row of the system and by classify()
    if (slidingColumn(basis_, v.tangent, state_, activeH[a], mu_, kSlide, c0))
      for (int i = 0; i < 3; ++i) column_(activeH[a], i) = c0[i];
  }
  sys_.unknownOffsetH(nA) = m;
  copy(sys_.unknownOffset, sys_.unknownOffsetH);
}

void CoulombFriction::solveSystem(const ContactStepViews& v, const std::vector<int>& active, int nA, int ld) {
  const int m = sys_.unknownOffsetH(nA);
  if (m > 0) {
    copy(sys_.MCfH, sys_.MCf);
    copy(sys_.rhsH, sys_.rhs);
    const int info = solveDense(m, sys_.MCfH.data(), ld, sys_.rhsH.data(), sys_.ipiv);
    EPAPHE_REQUIRE(info == 0, "contact: the friction contact system of "
                                  << nA << " active nodes (" << m << " unknowns) is singular (zero pivot at unknown "
                                  << info << ")");
  }
  // (lambda, s1, s2) of every active node: the solved unknowns and the known ones; and its force in
  // its basis, lambda c_0 sliding, (lambda, s1, s2) stuck (classify() reads it for every pair)
  for (int a = 0; a < nA; ++a) {
    const int ka = active[a], o = sys_.unknownOffsetH(a);
    const bool sl = state_(ka) == kSlide;
    const double lambda = penalty_ ? (v.rows ? v.row(ka, 2) : kp_ * (-v.gap(ka))) : sys_.rhsH(o);
    sys_.solH(3 * a) = lambda;
    const int t = penalty_ ? o : o + 1;
    sys_.solH(3 * a + 1) = sl ? 0.0 : sys_.rhsH(t);
    sys_.solH(3 * a + 2) = sl ? 0.0 : sys_.rhsH(t + 1);
    for (int j = 0; j < 3; ++j) force_(a, j) = sl ? column_(ka, j) * lambda : sys_.solH(3 * a + j);
  }
  copy(sys_.sol, sys_.solH);
}

bool CoulombFriction::releasePulled(std::vector<int>& activeH, int& nA, int& releases, int nc) {
  keep_.clear();
  for (int a = 0; a < nA; ++a)
    if (sys_.solH(3 * a) >= 0.0) keep_.push_back(activeH[a]);
  if (static_cast<int>(keep_.size()) < nA && releases < nc) {
    ++releases;
    activeH.swap(keep_);
    nA = static_cast<int>(activeH.size());
    return true;
  }
  return false;
}

int CoulombFriction::classify(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA) {
  // classify: proposed next state and direction per active node
  const double mu = mu_;
  const auto T = unmanaged(local_);
  const auto basis = unmanaged(basis_);
  const auto tangent = v.tangent;
  const auto state = unmanaged(state_);
  const auto disp = unmanaged(disp_);
  const auto sol = unmanaged(sys_.sol);
  constexpr int slide = kSlide;
  const auto nextState = unmanaged(nextState_);
  const auto nextTangent = unmanaged(nextTangent_);
  const auto returns = unmanaged(returns_);
  const auto force = unmanaged(force_);
  // The nodes in blocks of kClassifyLanes: each node's classification up to its return's Newton
  // iterations, then the block's Newton iterations interleaved (a sliding node's iteration is a
  // chain of dependent divisions and square roots: one node's at a time leaves the core waiting on
  // it), then each node's result. Each node's arithmetic is its own and in the same order: the same
  // bits on any number of threads and for any block.
  constexpr int W = kClassifyLanes;
  const int blocks = (nA + W - 1) / W;
  int changes = 0;
  reduce(
      "epaphe::contact::friction_classify", blocks, 15L * W,
      KOKKOS_LAMBDA(const int blk, int& count) {
        const int a0 = blk * W, a1 = a0 + W < nA ? a0 + W : nA;
        double t[W][3], K[W][2][2], Ks[W][2], ml[W], alpha[W], tv[W][2], u[W][2];
        int next[W];
        bool iterate[W], returned[W];
        for (int a = a0; a < a1; ++a) {
          const int l = a - a0, ka = active(a);
          const double lambda = sol(3 * a);
          for (int e = 0; e < 3; ++e) t[l][e] = tangent(ka, e);
          next[l] = state(ka);
          iterate[l] = returned[l] = false;
          if (state(ka) != slide) {
            double s[3], ss = 0.0;
            for (int e = 0; e < 3; ++e) {
              s[e] = sol(3 * a + 1) * basis(ka, 1, e) + sol(3 * a + 2) * basis(ka, 2, e);
              ss += s[e] * s[e];
            }
            ss = ::sqrt(ss);
            if (ss > mu * lambda) {  // outside the cone: slide, friction along the sticking force
              next[l] = slide;
              for (int e = 0; e < 3; ++e) t[l][e] = s[e] / ss;
            }
            continue;
          }
          // the tangential part of w = d_a + sum_b F_ab f_b in a's basis, w_i = e_i,a^T d_a +
          // sum_b (T_ab f_b)_i, f_b in b's basis: (lambda, s1, s2) stuck, lambda c_0 sliding
          double w1 = 0.0, w2 = 0.0;
          for (int e = 0; e < 3; ++e) {
            w1 += disp(ka, e) * basis(ka, 1, e);
            w2 += disp(ka, e) * basis(ka, 2, e);
          }
          const double* Ta = &T(ka, 0, 0, 0);  // T_ab: 3 x 3, contiguous
          for (int b = 0; b < nA; ++b) {
            const double* Tab = Ta + 9L * active(b);
            for (int j = 0; j < 3; ++j) {
              w1 += Tab[3 + j] * force(b, j);
              w2 += Tab[6 + j] * force(b, j);
            }
          }
          // The return (docs/theory/contact.md, eq. (74)): the others' forces fixed, the node's
          // tangential motion is w = w_0 + K s, K_ij = e_i^T F_aa e_j its 2 x 2 tangential
          // flexibility and w_0 its motion without its own friction force s. The force that would
          // stop it is s_trial = s - K^{-1} w = -K^{-1} w_0: inside the cone |s_trial| <= mu lambda it
          // sticks. Outside it slides, and Coulomb's law puts its force against its slip, s = mu lambda t
          // with w = -alpha t, alpha >= 0: then (alpha I + mu lambda K) t = K s_trial, so
          //   t = (alpha I + mu lambda K)^{-1} K s_trial,  |t| = 1,
          // alpha the root of |t(alpha)| = 1 (|t(0)| = |s_trial| / (mu lambda) > 1, |t| -> 0 as alpha
          // grows). An isotropic K gives t along s_trial (the radial return); along s_trial when K is
          // not isotropic, the force would leave the slip at an angle and dissipate less than mu lambda |w|.
          double(&Kl)[2][2] = K[l];  // K_ij = T_aa(i, j), i, j in (e1, e2)
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) Kl[i][j] = T(ka, ka, 1 + i, 1 + j);
          const double det = Kl[0][0] * Kl[1][1] - Kl[0][1] * Kl[1][0];
          const double d1 = -(Kl[1][1] * w1 - Kl[0][1] * w2) / det, d2 = -(-Kl[1][0] * w1 + Kl[0][0] * w2) / det;
          double sT[2] = {d1, d2};  // s_trial in (e1, e2): mu lambda t + d
          for (int e = 0; e < 3; ++e) {
            sT[0] += mu * lambda * t[l][e] * basis(ka, 1, e);
            sT[1] += mu * lambda * t[l][e] * basis(ka, 2, e);
          }
          const double ss = ::sqrt(sT[0] * sT[0] + sT[1] * sT[1]);
          ml[l] = mu * lambda;
          if (!(ss > ml[l]) && returns(ka) < kMaxReturns) {
            next[l] = kStick;
            continue;
          }
          if (!(ss > 0.0)) continue;
          returned[l] = true;
          u[l][0] = sT[0] / ss;  // the radial return (mu lambda = 0, or no root)
          u[l][1] = sT[1] / ss;
          Ks[l][0] = Kl[0][0] * sT[0] + Kl[0][1] * sT[1];
          Ks[l][1] = Kl[1][0] * sT[0] + Kl[1][1] * sT[1];
          if (ml[l] > 0.0) {
            // t(alpha) = A^{-1} K s_trial, A = alpha I + ml K; f(alpha) = 1 / |t| - 1 rises from
            // f(0) < 0 and is about linear in alpha: Newton on f, f' = t.A^{-1}t / |t|^3, kept at
            // alpha >= 0, to |f| <= 1e-13 (the direction then within 1e-13), at most 10 steps. It
            // starts from the root to first order in ml K / alpha (eq. (74a)), g = K s_trial:
            //   A^{-1} = (I - ml K / alpha) / alpha + O(ml^2), so |t| = 1 at
            //   alpha = |g| - ml g.K g / |g|^2,
            // exact for an isotropic K = k I (k (|s_trial| - ml)). When friction is a small part of
            // the slip (ml K << alpha: rotor37-massless, |s_trial| / ml = 30-1000), one Newton step
            // or two, where the mean of K's diagonal times |s_trial| - ml took two or three
            const double gg = Ks[l][0] * Ks[l][0] + Ks[l][1] * Ks[l][1];
            const double gKg = Ks[l][0] * (Kl[0][0] * Ks[l][0] + Kl[0][1] * Ks[l][1]) +
                               Ks[l][1] * (Kl[1][0] * Ks[l][0] + Kl[1][1] * Ks[l][1]);
            alpha[l] = gg > 0.0 ? ::sqrt(gg) - ml[l] * gKg / gg : 0.0;
            tv[l][0] = u[l][0];
            tv[l][1] = u[l][1];
            if (!(alpha[l] > 0.0)) alpha[l] = 0.0;
            iterate[l] = true;
          }
        }
        // the Newton iterations of the block's returns, interleaved
        for (int it = 0; it < 10; ++it) {
          bool any = false;
          for (int l = 0; l < a1 - a0; ++l) {
            if (!iterate[l]) continue;
            const double m = ml[l], al = alpha[l];
            const double a00 = al + m * K[l][0][0], a01 = m * K[l][0][1], a10 = m * K[l][1][0],
                         a11 = al + m * K[l][1][1];
            const double r = 1.0 / (a00 * a11 - a01 * a10);
            tv[l][0] = (a11 * Ks[l][0] - a01 * Ks[l][1]) * r;
            tv[l][1] = (-a10 * Ks[l][0] + a00 * Ks[l][1]) * r;
            const double y0 = (a11 * tv[l][0] - a01 * tv[l][1]) * r, y1 = (-a10 * tv[l][0] + a00 * tv[l][1]) * r;
            const double in = 1.0 / ::sqrt(tv[l][0] * tv[l][0] + tv[l][1] * tv[l][1]), f = in - 1.0;
            const double fp = (tv[l][0] * y0 + tv[l][1] * y1) * in * in * in;
            if (!(fp > 0.0) || ::fabs(f) <= 1e-13) {
              iterate[l] = false;
              continue;
            }
            const double na = al - f / fp;
            const double stepped = na > 0.0 ? na : 0.5 * al;
            if (::fabs(stepped - al) <= 1e-13 * al) {
              iterate[l] = false;
              continue;
            }
            alpha[l] = stepped;
            any = true;
          }
          if (!any) break;
        }
        for (int a = a0; a < a1; ++a) {
          const int l = a - a0, ka = active(a);
          if (returned[l]) {
            if (ml[l] > 0.0) {
              const double n = ::sqrt(tv[l][0] * tv[l][0] + tv[l][1] * tv[l][1]);
              if (n > 0.0 && n == n) {
                u[l][0] = tv[l][0] / n;
                u[l][1] = tv[l][1] / n;
              }
            }
            for (int e = 0; e < 3; ++e) t[l][e] = u[l][0] * basis(ka, 1, e) + u[l][1] * basis(ka, 2, e);
          }
          double dt = 0.0;
          for (int e = 0; e < 3; ++e) {
            dt += (t[l][e] - tangent(ka, e)) * (t[l][e] - tangent(ka, e));
            nextTangent(ka, e) = t[l][e];
          }
          nextState(ka) = next[l];
          if (next[l] != state(ka) || (next[l] == slide && dt > 1e-12)) ++count;  // |t change| > 1e-6
        }
      },
      Kokkos::Sum<int>(changes));
  return changes;
}

void CoulombFriction::commitClassification(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA) {
  const auto state = unmanaged(state_);
  const auto tangent = v.tangent;
  const auto nextState = unmanaged(nextState_);
  const auto nextTangent = unmanaged(nextTangent_);
  constexpr int slide = kSlide;
  const auto returns2 = unmanaged(returns_);
  forEach(
      "epaphe::contact::friction_commit", nA, 5, KOKKOS_LAMBDA(const int a) {
        const int ka = active(a);
        if (state(ka) == slide && nextState(ka) != slide) ++returns2(ka);
        state(ka) = nextState(ka);
        for (int e = 0; e < 3; ++e) tangent(ka, e) = nextTangent(ka, e);
      });
  fence();
}

void CoulombFriction::storeForces(const ContactStepViews& v, const std::vector<int>& activeH, int nA) {
  const double mu = mu_;
  const int nc = static_cast<int>(v.force.extent(0));
  // forces: lambda_a, and the direction c_a = n_a + mu_a t_a with mu_a t_a = s_a / lambda_a
  for (int k = 0; k < nc; ++k) v.force(k) = 0.0;
  for (int a = 0; a < nA; ++a) v.force(activeH[a]) = sys_.solH(3 * a);
  const auto active = v.upload(activeH);
  const auto normal = v.normal;
  const auto basis = unmanaged(basis_);
  const auto tangent = v.tangent;
  const auto state = unmanaged(state_);
  const auto dir = v.dir;
  const auto muA = v.mu;
  const auto sol = unmanaged(sys_.sol);
  const auto force = v.force;
  forEach(
      "epaphe::contact::friction_reset", nc, 5, KOKKOS_LAMBDA(const int k) {
        for (int e = 0; e < 3; ++e) {
          dir(k, e) = normal(k, e);
          if (force(k) == 0.0) tangent(k, e) = 0.0;
        }
        muA(k) = 0.0;
      });
  fence();
  forEach(
      "epaphe::contact::friction_force", nA, 15, KOKKOS_LAMBDA(const int a) {
        const int ka = active(a);
        const double l = sol(3 * a);
        if (state(ka) == kSlide) {
          muA(ka) = l > 0.0 ? mu : 0.0;
          for (int e = 0; e < 3; ++e) dir(ka, e) = normal(ka, e) + mu * tangent(ka, e);
          return;
        }
        double s[3], ss = 0.0;
        for (int e = 0; e < 3; ++e) {
          s[e] = sol(3 * a + 1) * basis(ka, 1, e) + sol(3 * a + 2) * basis(ka, 2, e);
          ss += s[e] * s[e];
        }
        ss = ::sqrt(ss);
        if (!(l > 0.0) || !(ss > 0.0)) {
          for (int e = 0; e < 3; ++e) tangent(ka, e) = 0.0;
          return;
        }
        muA(ka) = ss / l;
        for (int e = 0; e < 3; ++e) {
          tangent(ka, e) = s[e] / ss;
          dir(ka, e) = normal(ka, e) + s[e] / l;
        }
      });
  fence();
  for (int k = 0; k < nc; ++k) {  // the warm start of the next step's classification
    prev_(k) = v.force(k) > 0.0 ? state_(k) : 0;
    for (int e = 0; e < 3; ++e) prevTangent_(k, e) = v.tangent(k, e);
  }
}

void CoulombFriction::reset() {
  Kokkos::deep_copy(prev_, 0);
}

}  // namespace epaphe
