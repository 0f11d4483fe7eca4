#include "Epaphe_ThermalParameters.hpp"

#include "Epaphe_Deck.hpp"

namespace epaphe {

using Teuchos::ParameterList;
using namespace deck;

void addThermalParameters(ParameterList& body) {
  auto& th =
      body.sublist("Thermal", false,
                   "Heat from rubbing (docs/user/heat.md): the body's reduced thermal model, heated by the "
                   "friction at its contact nodes; no 'Conductivity': none. Built-in meshes and CalculiX imports; "
                   "the density is the Material's (a CalculiX import: its *DENSITY when it has one)");
  addDouble(th, "Conductivity", 0.0, "k (W/(m K)); > 0 gives the body a thermal model", 0.0);
  addDouble(th, "Specific heat", 0.0, "c (J/(kg K)), > 0 with a thermal model", 0.0);
  addDouble(th, "Reference temperature", 20.0,
            "T_ref: the body's initial, uniform, temperature and that of its fixed-temperature nodes");
  addString(th, "Fixed temperature node set", "", "Nodes held at the reference temperature (empty: none)");
  addString(th, "Convection node set", "",
            "Convection -k dT/dn = h (T - T_inf) on the faces whose four corners are in this set (empty: none)");
  addDouble(th, "Convection coefficient", 0.0, "h (W/(m^2 K))", 0.0);
  addDouble(th, "Ambient temperature", 20.0, "T_inf, of the convection");
  addInt(th, "Modes", 10,
         "Lowest thermal modes kept, besides the static responses to unit heat inputs at the contact nodes and "
         "their Krylov corrections K^-1 C K^-1 e (docs/theory/heat.md eq. 58)",
         0);
  addInt(th, "Sub-steps", 100, "Mechanical steps per thermal step (sub-cycling, docs/theory/heat.md eq. 60)", 1);
  addDouble(th, "Heat partition", -1.0,
            "p: the share of the frictional heat the body receives (the counterface the rest); -1: from the "
            "effusivities, e_b / (e_b + e_c)",
            -1.0, 1.0);
  addDouble(th, "Expansion coefficient", 0.0,
            "alpha (1/K): the thermal growth of the contact nodes, the static displacement of the thermal strain "
            "alpha (T - T_ref), moves their positions at every thermal step (the clearance closes as the tip heats; "
            "docs/theory/heat.md eq. 61); 0: the temperature does not act on the mechanics (a CalculiX import: its "
            "*EXPANSION, when it has one, gives alpha)",
            0.0);
  addDouble(th, "Young's modulus", 0.0,
            "E (Pa) of the thermal growth of a model imported from CalculiX whose input has no *ELASTIC; 0: "
            "none given (built-in meshes take the Material's)",
            0.0);
  addDouble(th, "Poisson's ratio", -1.0,
            "nu of the thermal growth of a model imported from CalculiX whose input has no *ELASTIC; -1: none "
            "given (built-in meshes take the Material's)",
            -1.0, 0.499999);
  addDouble(th, "Counterface effusivity", 0.0,
            "e_c = sqrt(k rho c) of the surface rubbed (J/(m^2 K s^0.5)), for the default partition; 0: the body "
            "takes all the heat",
            0.0);
}

bool hasThermalModel(const ParameterList& bp) {
  return bp.isSublist("Thermal") && bp.sublist("Thermal").get<double>("Conductivity") > 0.0;
}

}  // namespace epaphe
