// Uses three installed Epaphe packages: deck validation (simulation/core), a B-spline surface and
// a closest-point projection (surface).
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ClosestPoint.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Runtime.hpp"

#include <cmath>
#include <iostream>

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  rt.initializeKokkos(1);
  bool ok = true;
  {
    const auto deck = epaphe::readDeckFromString(
        "<ParameterList name=\"Epaphe\"><ParameterList name=\"Time\">"
        "<Parameter name=\"Time step\" type=\"double\" value=\"2e-7\"/></ParameterList></ParameterList>",
        "inline deck");
    ok = ok && deck.params->sublist("Time").get<double>("Time step") == 2e-7 &&
         deck.params->sublist("Contact").get<std::string>("Method") == "Lagrange";
    std::vector<double> grid;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j) grid.insert(grid.end(), {double(i), double(j), 1.0});
    epaphe::BSplineSurface plane("plane", 5, 5, grid);
    const double x[3] = {1.3, 2.7, 1.5};  // 0.5 above the plane z = 1 (S_u x S_v = +z)
    const auto p = epaphe::closestPoint(plane.hostView(), x, 2.0, 2.0, 1e-12, 20);
    ok = ok && std::abs(p.gap - 0.5) < 1e-12 && std::abs(p.point[0] - 1.3) < 1e-12;
    std::cout << "gap " << p.gap << " at (" << p.point[0] << ", " << p.point[1] << ", " << p.point[2] << ")\n";
  }
  std::cout << (ok ? "consumer OK" : "consumer FAILED") << "\n";
  return ok ? 0 : 1;
}
