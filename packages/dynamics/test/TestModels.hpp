#pragma once
// Models small enough to solve by hand, shared by the dynamics and contact tests.
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_ReducedModel.hpp"

#include <utility>
#include <vector>

namespace epaphe::test {

/// One node of mass m on a spring k in each direction (3 DOFs, all retained), at the origin.
inline ReducedModel oscillator(double m, double k) {
  ReducedModel r;
  r.name = "oscillator";
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
  r.nodeSets["all"] = {0};
  r.retainedNodes = {0};
  return r;
}

/// A fixed pseudo-random vector in [-1, 1).
inline std::vector<double> noise(int n, unsigned seed) {
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& x : v) {
    seed = seed * 1103515245u + 12345u;
    x = static_cast<double>((seed >> 8) & 0xffff) / 32768.0 - 1.0;
  }
  return v;
}

/// One free node of mass m (K = 0).
inline ReducedModel pointMass(double m) {
  return oscillator(m, 0.0);
}

/// The terms of the discrete energy balance over `steps` free steps of `cd` from q_{-1} = qm,
/// q_0 = q: E_{-1/2}, the last E_{n+1/2} and the damping work (E + damping = E_{-1/2} exactly).
struct EnergyBalance {
  double start = 0, end = 0, damping = 0;
};
inline EnergyBalance freeSteps(const CentralDifference& cd, DenseVector qm, DenseVector q, int steps) {
  DenseVector qp("qp", q.extent(0));
  EnergyBalance b;
  b.start = cd.halfStepEnergy(qm, q);
  for (int n = 0; n < steps; ++n) {
    cd.predict(q, qm, qp);
    b.damping += cd.dampingIncrement(qp, qm);
    std::swap(qm, q);
    std::swap(q, qp);
  }
  b.end = cd.halfStepEnergy(qm, q);
  return b;
}

}  // namespace epaphe::test
