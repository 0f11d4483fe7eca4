#pragma once
// Surfaces small enough to check contact by hand, shared by the contact and dynamics tests.
#include "Epaphe_BSplineSurface.hpp"

#include <vector>

namespace epaphe::test {

/// The plane z = 0 over [-2, 2]^2 as a 4 x 4 grid: S_u along x, S_v along y, normal +z.
inline BSplineSurface floorPlane() {
  std::vector<double> g;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) g.insert(g.end(), {-2.0 + 4.0 * i / 3.0, -2.0 + 4.0 * j / 3.0, 0.0});
  SurfaceOptions o;
  o.closureU = o.closureV = Closure::Open;
  return BSplineSurface("floor", 4, 4, g, o);
}

}  // namespace epaphe::test
