#pragma once
// The dense types of the explicit step: a system or body vector of coordinates and a dense matrix
// stored by columns (Kokkos views on the default memory space). Every package from core up uses
// them: the integrator's operators and state (dynamics), the flexibility (modeldata), the contact's
// correction (contact).
#include <Kokkos_Core.hpp>

namespace epaphe {

/// A dense matrix, column-major (LAPACK's layout), in the default memory space.
using DenseMatrix = Kokkos::View<double**, Kokkos::LayoutLeft>;
/// A dense vector in the default memory space.
using DenseVector = Kokkos::View<double*>;

}  // namespace epaphe
