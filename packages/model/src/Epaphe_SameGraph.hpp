#pragma once
// Matrices of a body at speed on one graph, its stiffness's (Epaphe_ModelAtSpeed.cpp): the geometric
// stiffness of each fixed-point pass is summed into K's pattern instead of building a graph, and the
// sums K - Omega^2 M_perp + K_sigma are loops over values instead of Tpetra's sparse sums.
#include "Epaphe_FullModel.hpp"

#include <array>
#include <vector>

namespace epaphe {

/// assembleGeometricStiffness (Epaphe_Centrifugal.hpp) on the graph of `pattern` (model.K: a matrix of
/// the same elements, whose pattern holds every element's entries): no graph is built and the result
/// shares it. Falls back to a graph of its own when the pattern lacks an entry.
Teuchos::RCP<CrsMatrix> assembleGeometricStiffness(const FullModel& model, const std::vector<double>& u,
                                                   const CrsMatrix& pattern);

/// a A + b B: a loop over the values when A and B share one graph (the same Tpetra graph object, e.g.
/// both assembled on model.K's), Tpetra's sparse sum otherwise.
Teuchos::RCP<CrsMatrix> sumOnGraph(double a, const CrsMatrix& A, double b, const CrsMatrix& B);

/// insertElementMatrix (Epaphe_FullModel.hpp) summed into A, whose (static) graph must hold the
/// element's entries: false if one is missing.
bool sumIntoElementMatrix(const FullModel& model, const std::array<int, 8>& hex, const double* Ae, CrsMatrix& A);

}  // namespace epaphe
