#pragma once
// The one set of Tpetra types Epaphe uses: double, int local and global ordinals (Tpetra_INST_INT_INT),
// the default node (Kokkos OpenMP).
#include <Tpetra_CrsMatrix_decl.hpp>
#include <Tpetra_Map_decl.hpp>
#include <Tpetra_MultiVector_decl.hpp>
#include <Tpetra_Operator.hpp>

namespace epaphe {
using Scalar = double;
using LO = int;
using GO = int;
using Map = Tpetra::Map<LO, GO>;
using CrsMatrix = Tpetra::CrsMatrix<Scalar, LO, GO>;
using MultiVector = Tpetra::MultiVector<Scalar, LO, GO>;
using Operator = Tpetra::Operator<Scalar, LO, GO>;
}  // namespace epaphe
