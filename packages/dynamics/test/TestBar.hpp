#pragma once
// The steel bar of the full-model tests (lumped mass, massless boundary).
#include "Epaphe_FullModel.hpp"

#include <Teuchos_DefaultComm.hpp>

#include <vector>

namespace epaphe::test {

inline const Material steel{7800, 2.1e11, 0.3};

/// A steel bar 0.2 x 0.02 x 0.02 m of nx x 2 x 2 hexahedra, clamped at x = 0 or free.
inline FullModel bar(int nx, bool clamped) {
  Mesh mesh = makeBoxMesh({0, 0, 0}, {0.2, 0.02, 0.02}, {nx, 2, 2});
  const std::vector<int> fixed = clamped ? mesh.nodeSet("x-", "test") : std::vector<int>();
  return assembleHexModel("bar", mesh, steel, fixed, Teuchos::DefaultComm<int>::getComm());
}

}  // namespace epaphe::test
