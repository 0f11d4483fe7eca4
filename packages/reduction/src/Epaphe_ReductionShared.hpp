#pragma once
// What the reductions of this package share (Epaphe_CraigBampton.cpp, Epaphe_MasslessBoundary.cpp,
// Epaphe_FullModelFrequencies.cpp): products and gathers of distributed multivectors, the retained DOFs'
// numbering, and the scale of a model's largest eigenvalue. Not installed.
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_TpetraTypes.hpp"

#include <vector>

namespace epaphe {

/// A^T B as a dense column-major (colsA x colsB) array on every rank.
std::vector<double> transposeProduct(const MultiVector& A, const MultiVector& B);

/// A basis given by its rows over every node's DOFs (`recovery`, (3 numNodes) x n, row-major, a reduced
/// model's u = R q) as a multivector over the free DOFs of `full` on `map` (rows at clamped DOFs dropped).
MultiVector basisOnFreeDofs(const FullModel& full, const std::vector<double>& recovery, int n,
                            const Teuchos::RCP<const Map>& map);

/// A dense nR x k array (column-major, replicated) as a multivector on a locally replicated map.
MultiVector replicated(const std::vector<double>& a, int rows, int cols,
                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// The rows of a distributed multivector X (rows numbered by the global free DOF g) that
/// `rowIndex[g] >= 0` selects, as a dense (numRows x cols, column-major) array on every rank.
std::vector<double> gatherRows(const MultiVector& X, const std::vector<int>& rowIndex, int numRows);

/// The reduced model's mesh data and its retained DOFs, numbered in the order (retained node,
/// direction) as q's first entries: `rIndex[g]` is free DOF g's index among them (-1: not retained),
/// `nR` their count.
ReducedModel retainedShell(const FullModel& full, const std::vector<int>& retained, ReductionKind kind,
                           std::vector<int>& rIndex, int& nR);

/// max_i K_ii / M_ii over every rank: the scale of a model's largest eigenvalue.
double largestDiagonalRatio(const CrsMatrix& K, const CrsMatrix& M);

}  // namespace epaphe
