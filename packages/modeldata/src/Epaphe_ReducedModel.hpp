#pragma once
// The reduced model: plain data (dense matrices and recovery rows), produced by the reduction
// package and consumed by the online loop, which never sees Tpetra (package modeldata: no Tpetra).
//
// Reduced coordinates q (size n): for Craig-Bampton, the physical DOFs of the retained nodes
// (3 per node) followed by the amplitudes of the fixed-interface modes (thesis eq. 2.12); for the
// unreduced model, every free DOF. Physical displacements are u = R q (eq. 2.5).
//
// A full model with lumped mass (method "Full, lumped mass") is not reduced at all and stays
// sparse: q = u over the free DOFs (R = I: a node's DOF is q[nodeDof], 0 when clamped), K in
// compressed rows, M diagonal; the dense K, M and recovery are then empty (sparse() is true).
//
// Massless boundary (method "Massless boundary", MacNeal 1971; Monjaraz-Tec, Gross & Krack 2022):
// q = [u_b, eta], u_b the retained DOFs, eta the amplitudes of the body's own lowest normal modes
// Phi (retained nodes free, the body held by its boundary conditions; Phi^T M Phi = I,
// Phi^T K Phi = Omega^2). The retained DOFs carry no mass: u_b = Phi_b eta + G f_b, with
// G = (K^{-1})_bb - Phi_b Omega^{-2} Phi_b^T the residual flexibility and f_b the force on them. In q,
//   K = [ G^{-1}             -G^{-1} Phi_b                  ]     M = [ 0  0 ]
//       [ -Phi_b^T G^{-1}     Omega^2 + Phi_b^T G^{-1} Phi_b ]         [ 0  I ]
// (static response exact: K^{-1} restricted to u_b is (K_full^{-1})_bb), and every node's
// displacement is u = R q, R = [Res G^{-1}, Phi - Res G^{-1} Phi_b], Res = K^{-1} E_b - Phi Omega^{-2} Phi_b^T.
// The stable step is set by Omega's largest entry alone (dynamics/Epaphe_CentralDifference.hpp).
#include "Epaphe_Mesh.hpp"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace epaphe {

/// A sparse matrix in compressed rows (0-based column indices, sorted in each row).
struct SparseRows {
  std::vector<std::size_t> rowStart;  ///< rows + 1 entries
  std::vector<int> cols;              ///< column index of each entry
  std::vector<double> values;         ///< value of each entry
  /// The number of rows.
  int rows() const { return rowStart.empty() ? 0 : static_cast<int>(rowStart.size()) - 1; }
};

/// How a body's model was made from its full model: the deck's 'Reduction->Method', the same values.
enum class ReductionKind { CraigBampton = 0, Guyan = 1, None = 2, FullLumped = 3, MasslessBoundary = 4 };

/// The deck's name of a kind: "Craig-Bampton", "Guyan", "None", "Full, lumped mass", "Massless boundary".
const char* reductionName(ReductionKind kind);

/// The kind of a deck name (reductionName's inverse); an Error names the valid ones otherwise.
ReductionKind reductionKindNamed(const std::string& name);

/// A body's model as the explicit loop uses it: reduced (Craig-Bampton, Guyan, massless boundary) or full
/// with lumped mass, with what recovers the nodes' displacements, the mesh and the node sets.
struct ReducedModel {
  std::string name;                          ///< the body's name
  ReductionKind kind = ReductionKind::None;  ///< what it is; method(), sparse() and massless() follow

  int size = 0;      ///< the number of coordinates q
  int numModes = 0;  ///< fixed-interface modes kept
  ///@{
  std::vector<double> K, M;  ///< size x size, column-major, symmetric
  ///@}
  std::vector<int> nodeDof;                   ///< 3 * node + d -> index in q equal to that DOF, or -1
  std::vector<double> recovery;               ///< (3 * numNodes) x size, row-major: u = R q
  std::vector<std::array<double, 3>> coords;  ///< node coordinates (m), at rest (plus staticDisplacement at speed)
  std::vector<std::array<int, 8>> hexes;      ///< the mesh, for field output (ParaView)
  std::map<std::string, std::vector<int>> nodeSets;  ///< node sets, sorted node indices
  std::map<std::string, NodeGrid> nodeGrids;         ///< ordered faces (surfaces carried by the body)
  std::vector<int> retainedNodes;                    ///< the nodes whose DOFs are kept as coordinates (the interface)
  std::vector<double> modeFrequencies;               ///< fixed-interface modes (Hz)
  std::vector<double> fullFrequencies;      ///< lowest frequencies of the full model it came from (Hz), if computed
  SparseRows sparseK;                       ///< full model with lumped mass: K (size x size)
  std::vector<double> lumpedMass;           ///< full model with lumped mass: diag(M) (size)
  std::vector<double> boundaryModes;        ///< massless boundary: Phi_b, (size - numModes) x numModes, column-major
  std::vector<double> residualFlexibility;  ///< massless boundary: G, square on the retained DOFs, column-major
  std::vector<double> modalTranslation;     ///< massless boundary: Phi^T M e_d, numModes x 3, column-major
  std::array<double, 3> translationMass = {0, 0, 0};  ///< massless boundary: e_d^T M e_d over the free DOFs
  double speed = 0;                                   ///< a body at speed: Omega (rad/s) of its model, 0 at rest
  std::vector<double> staticDisplacement;  ///< a body at speed: u_s, 3 per node (coords are x + u_s); empty at rest
  /// A body at speed that keeps its Coriolis terms ('Rotation->Coriolis'): G_r = V^T G V per unit speed
  /// (size x size, column-major, skew), V the reduction's basis (the recovery) and G = 2 int rho N^T [a]_x N,
  /// so that speed * G_r is the gyroscopic matrix in M q'' + speed G_r q' + K q = f. Empty: not kept.
  std::vector<double> coriolis;

  /// The deck's name of its kind ("Craig-Bampton", ...), for messages and files.
  std::string method() const { return reductionName(kind); }
  /// True for a full model with lumped mass (sparse K, diagonal M).
  bool sparse() const { return kind == ReductionKind::FullLumped; }
  /// True for a massless boundary.
  bool massless() const { return kind == ReductionKind::MasslessBoundary; }
  /// The retained (boundary) DOFs: the first size - numModes coordinates.
  int boundarySize() const { return size - numModes; }
  /// Massless boundary: Omega_j^2 = (2 pi f_j)^2 of the kept modes, the one definition that the
  /// reduction's K and the integrator use.
  std::vector<double> modalStiffness() const;
  /// Massless boundary: K_res = L^T G^{-1} L (size x size, column-major, symmetric), L = [I, -Phi_b],
  /// the stiffness of the static residual r = u_b - Phi_b eta; K = K_res + diag(0, Omega^2).
  std::vector<double> residualStiffness() const;
  /// The number of nodes.
  int numNodes() const { return static_cast<int>(coords.size()); }
  /// K(i, j).
  double k(int i, int j) const { return K[static_cast<std::size_t>(j) * size + i]; }
  /// M(i, j).
  double m(int i, int j) const { return M[static_cast<std::size_t>(j) * size + i]; }
  /// The row of the recovery R for DOF `d` (0..2) of `node`: `size` values, u = R q.
  const double* recoveryRow(int node, int d) const {
    return recovery.data() + (3 * static_cast<std::size_t>(node) + d) * size;
  }
  /// A named node set or a union "a, b" of them (see Mesh::nodeSet).
  std::vector<int> nodeSet(const std::string& spec, const std::string& context) const;
  /// The reduced coordinates of a rigid translation along `direction`. Craig-Bampton and Guyan: unit
  /// displacement of every retained DOF along it, zero modal amplitudes (exact: their constraint
  /// modes reproduce rigid-body motion). Massless boundary: the translation projected onto the modes
  /// in the mass inner product, eta = Phi^T M e_d, and the boundary following them, u_b = Phi_b eta
  /// (exact for a free body, whose rigid-body modes are among its modes; a held body keeps only
  /// the part of it its modes carry).
  std::vector<double> rigidTranslation(int direction) const;
  /// M x, M dense or lumped.
  std::vector<double> massTimes(const std::vector<double>& x) const;
  /// For a full model (R = I, no recovery rows): per row 3 k + d of `nodes`, the index in q of node
  /// k's DOF d (-1: clamped, u = 0).
  std::vector<int> recoveryIndex(const std::vector<int>& nodes) const;
};

/// K x = lambda M x for dense symmetric K and positive definite M (n x n, column-major) by LAPACK
/// dsygvd: ascending eigenvalues; with `vectors`, the M-orthonormal eigenvectors (column-major).
std::vector<double> denseEigenpairs(const std::vector<double>& K, const std::vector<double>& M, int n,
                                    std::vector<double>* vectors = nullptr);

/// Inverse of a symmetric positive definite n x n matrix (column-major) by Cholesky; an Error names
/// `what`, the failing column and `fix` when it is not positive definite.
std::vector<double> spdInverse(std::vector<double> A, int n, const std::string& what, const std::string& fix);

/// Inverse of a general nonsingular n x n matrix (column-major) by LU with partial pivoting (LAPACK
/// dgetrf, dgetri); an Error names `what` and `fix` when it is singular.
std::vector<double> generalInverse(std::vector<double> A, int n, const std::string& what, const std::string& fix);

/// Natural frequencies (Hz, ascending) of a dense model. Negative round-off eigenvalues give 0.
std::vector<double> denseFrequencies(const std::vector<double>& K, const std::vector<double>& M, int n);

/// Natural frequencies (Hz, ascending) of a dense reduced model: denseFrequencies(K, M), or for a
/// massless boundary (M singular) the kept modes' (the retained DOFs respond statically).
std::vector<double> reducedFrequencies(const ReducedModel& model);

}  // namespace epaphe
