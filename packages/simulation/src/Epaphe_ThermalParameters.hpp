#pragma once
// The deck's 'Bodies-><name>->Thermal' list (heat from rubbing, docs/user/heat.md): plain
// parameters, no Tpetra, so that the deck schema compiles without it (tests/fuzz).
#include <Teuchos_ParameterList.hpp>

namespace epaphe {

/// The 'Thermal' list of a body (its keys, documentation and validators).
void addThermalParameters(Teuchos::ParameterList& body);

/// True when the body's 'Thermal->Conductivity' is set (> 0): it has a thermal model.
bool hasThermalModel(const Teuchos::ParameterList& bodyParams);

}  // namespace epaphe
