#pragma once
// The one set of Tpetra types Epaphe uses: double, int local and global ordinals (Tpetra_INST_INT_INT),
// the default node (Kokkos OpenMP).
#include <Tpetra_CrsMatrix_decl.hpp>
#include <Tpetra_Map_decl.hpp>
#include <Tpetra_MultiVector_decl.hpp>
#include <Tpetra_Operator.hpp>

namespace epaphe {
/// Matrix and vector entries.
using Scalar = double;
/// Local ordinals.
using LO = int;
/// Global ordinals.
using GO = int;
/// A Tpetra map of the DOFs over the ranks.
using Map = Tpetra::Map<LO, GO>;
/// A distributed sparse matrix.
using CrsMatrix = Tpetra::CrsMatrix<Scalar, LO, GO>;
/// A distributed block of vectors.
using MultiVector = Tpetra::MultiVector<Scalar, LO, GO>;
/// An operator on MultiVector (Anasazi, Belos).
using Operator = Tpetra::Operator<Scalar, LO, GO>;
}  // namespace epaphe
