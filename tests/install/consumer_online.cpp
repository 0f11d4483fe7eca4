// The online loop from an installed Epaphe with no Tpetra: it links Epaphe::dynamics (and through
// it contact, surface, modeldata, core) only. A mass on springs, built by hand as a reduced model,
// is stepped by the central difference for one period; its displacement returns to the start
// (phase error (omega h)^2 / 24 per radian: 1.6e-6 of a period here) and the discrete energy
// E_{n+1/2} stays constant (the central difference conserves it exactly, to round-off).
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>

#include <cmath>
#include <iostream>

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  rt.initializeKokkos(1);
  bool ok = true;
  {
    const double m = 2.0, k = 800.0, omega = std::sqrt(k / m), period = 2 * M_PI / omega;
    const int steps = 1000;
    const double h = period / steps, x0 = 1e-3;
    epaphe::ReducedModel r;  // one node, mass m and stiffness k in each direction
    r.name = "oscillator";
    r.kind = epaphe::ReductionKind::None;
    r.size = 3;
    r.K.assign(9, 0.0);
    r.M.assign(9, 0.0);
    for (int i = 0; i < 3; ++i) {
      r.K[4 * i] = k;
      r.M[4 * i] = m;
    }
    r.nodeDof = {0, 1, 2};
    r.recovery = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    r.coords = {{0, 0, 0}};
    r.retainedNodes = {0};
    const epaphe::CentralDifference cd(r, h, epaphe::DampingOptions{});
    Kokkos::View<double*> q[3] = {Kokkos::View<double*>("q0", 3), Kokkos::View<double*>("q1", 3),
                                  Kokkos::View<double*>("q2", 3)};
    auto init = Kokkos::create_mirror_view(q[0]);
    init(0) = x0;
    Kokkos::deep_copy(q[1], init);                  // q_0
    init(0) = x0 * (1 - 0.5 * h * h * omega * omega);  // q_{-1} = q_0 + h^2/2 a_0 (v_0 = 0)
    Kokkos::deep_copy(q[0], init);
    int prev = 0, cur = 1, next = 2;
    cd.predict(q[cur], q[prev], q[next]);
    const double e0 = cd.halfStepEnergy(q[cur], q[next]);
    double drift = 0;
    for (int n = 0; n < steps; ++n) {
      if (n > 0) cd.predict(q[cur], q[prev], q[next]);
      drift = std::max(drift, std::abs(cd.halfStepEnergy(q[cur], q[next]) - e0) / e0);
      const int old = prev;
      prev = cur;
      cur = next;
      next = old;
    }
    auto qh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), q[cur]);
    const double back = qh(0) / x0;
    std::cout << "after one period u/u0 = " << back << ", energy drift " << drift << "\n";
    ok = std::abs(back - 1) < 1e-4 && drift < 1e-12;
  }
  std::cout << (ok ? "online consumer OK" : "online consumer FAILED") << "\n";
  return ok ? 0 : 1;
}
