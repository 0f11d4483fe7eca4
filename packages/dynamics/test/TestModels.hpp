#pragma once
// Models small enough to solve by hand, shared by the dynamics and contact tests.
#include "Epaphe_ReducedModel.hpp"

namespace epaphe::test {

/// One node of mass m on a spring k in each direction (3 DOFs, all retained), at the origin.
inline ReducedModel oscillator(double m, double k) {
  ReducedModel r;
  r.name = "oscillator";
  r.method = "None";
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

/// One free node of mass m (K = 0).
inline ReducedModel pointMass(double m) { return oscillator(m, 0.0); }

}  // namespace epaphe::test
