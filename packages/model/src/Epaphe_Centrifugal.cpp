#include "Epaphe_Centrifugal.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_SameGraph.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include <cmath>

namespace epaphe {

SpinAxis spinAxis(const std::array<double, 3>& point, const std::array<double, 3>& direction,
                  const std::string& context) {
  const double len = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2]);
  for (int d = 0; d < 3; ++d)
    EPAPHE_REQUIRE(std::isfinite(point[d]) && std::isfinite(direction[d]),
                   context << ": the rotation axis {" << direction[0] << ", " << direction[1] << ", " << direction[2]
                           << "} through {" << point[0] << ", " << point[1] << ", " << point[2]
                           << "} has a value that is not a finite number");
  EPAPHE_REQUIRE(len > 0, context << ": the rotation axis {" << direction[0] << ", " << direction[1] << ", "
                                  << direction[2] << "} has zero length; give its direction, e.g. {0, 0, 1}");
  SpinAxis a;
  a.point = point;
  for (int d = 0; d < 3; ++d) a.direction[d] = direction[d] / len;
  return a;
}

namespace {

void requireElements(const FullModel& model, const char* what) {
  EPAPHE_REQUIRE(model.material.has_value(),
                 "body '" << model.name << "': " << what << " needs the model's elements, and an imported model "
                          << "has none in Epaphe; import its matrices at speed from the FE code instead");
}

}  // namespace

namespace {

/// assembleCentrifugal, its matrices on model.K's graph (`onK`; false returned when that graph lacks an
/// entry) or on graphs of their own.
bool assembleCentrifugal(const FullModel& model, const SpinAxis& axis, bool onK, CentrifugalTerms& t) {
  const auto rows = model.K->getRowMap();
  const auto& a = axis.direction;
  double P[3][3], A[3][3];  // P = I - a a^T, A v = a x v
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) P[i][j] = (i == j ? 1.0 : 0.0) - a[i] * a[j];
  A[0][0] = 0;
  A[0][1] = -a[2];
  A[0][2] = a[1];
  A[1][0] = a[2];
  A[1][1] = 0;
  A[1][2] = -a[0];
  A[2][0] = -a[1];
  A[2][1] = a[0];
  A[2][2] = 0;

  t.perpendicularMass =
      onK ? Teuchos::rcp(new CrsMatrix(model.K->getCrsGraph())) : Teuchos::rcp(new CrsMatrix(rows, 81));
  t.coriolis = onK ? Teuchos::rcp(new CrsMatrix(model.K->getCrsGraph())) : Teuchos::rcp(new CrsMatrix(rows, 81));
  bool complete = true;
  t.load = Teuchos::rcp(new MultiVector(rows, 1));
  auto load = t.load->getDataNonConst(0);
  double Ke[24 * 24], Me[24 * 24], Mp[24 * 24], Gc[24 * 24];
  for (int i = 0; i < 24 * 24; ++i) Mp[i] = Gc[i] = 0;
  forEachOwnedHex(model, *rows, [&](const std::array<int, 8>& hex, const double(&x)[8][3]) {
    if (!complete) return;
    hex8StiffnessMass(x, *model.material, Ke, Me);
    // The consistent mass is m_ab I_3 per node pair: M_perp,ab = m_ab P, G_ab / 2 = m_ab [a]_x.
    for (int p = 0; p < 8; ++p)
      for (int q = 0; q < 8; ++q) {
        const double m = Me[(3 * p) * 24 + 3 * q];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            Mp[(3 * p + i) * 24 + 3 * q + j] = m * P[i][j];
            Gc[(3 * p + i) * 24 + 3 * q + j] = m * A[i][j];
          }
      }
    if (onK) {
      complete = sumIntoElementMatrix(model, hex, Mp, *t.perpendicularMass) &&
                 sumIntoElementMatrix(model, hex, Gc, *t.coriolis);
    } else {
      insertElementMatrix(model, hex, Mp, *t.perpendicularMass);
      insertElementMatrix(model, hex, Gc, *t.coriolis);
    }
    // f_c,a = sum_b M_perp,ab (x_b - x_0), the clamped nodes' x_b included
    for (int r = 0; r < 24; ++r) {
      const int row = model.eq[3 * hex[r / 3] + r % 3];
      if (row < 0 || !rows->isNodeGlobalElement(row)) continue;
      double f = 0;
      for (int q = 0; q < 8; ++q)
        for (int j = 0; j < 3; ++j) f += Mp[r * 24 + 3 * q + j] * (x[q][j] - axis.point[j]);
      load[rows->getLocalElement(row)] += f;
    }
  });
  if (!complete) return false;
  t.perpendicularMass->fillComplete(model.K->getDomainMap(), model.K->getRangeMap());
  t.coriolis->fillComplete(model.K->getDomainMap(), model.K->getRangeMap());
  return true;
}

}  // namespace

CentrifugalTerms assembleCentrifugal(const FullModel& model, const SpinAxis& axis) {
  requireElements(model, "the centrifugal load");
  // on K's graph, so that K - Omega^2 M_perp is a loop over values (sumOnGraph); on their own if it lacks an entry
  CentrifugalTerms t;
  if (!assembleCentrifugal(model, axis, true, t)) {
    t = CentrifugalTerms();
    assembleCentrifugal(model, axis, false, t);
  }
  return t;
}

Teuchos::RCP<CrsMatrix> assembleGeometricStiffness(const FullModel& model, const std::vector<double>& u) {
  requireElements(model, "the geometric stiffness");
  EPAPHE_REQUIRE(u.size() == 3 * static_cast<std::size_t>(model.numNodes()),
                 "body '" << model.name << "': " << u.size() << " nodal displacements for " << model.numNodes()
                          << " nodes (3 per node expected)");
  const auto rows = model.K->getRowMap();
  auto Ks = Teuchos::rcp(new CrsMatrix(rows, 81));
  double ue[24], Kg[24 * 24];
  forEachOwnedHex(model, *rows, [&](const std::array<int, 8>& hex, const double(&x)[8][3]) {
    for (int p = 0; p < 8; ++p)
      for (int d = 0; d < 3; ++d) ue[3 * p + d] = u[3 * static_cast<std::size_t>(hex[p]) + d];
    hex8GeometricStiffness(x, *model.material, ue, Kg);
    insertElementMatrix(model, hex, Kg, *Ks);
  });
  Ks->fillComplete();
  return Ks;
}

Teuchos::RCP<CrsMatrix> assembleGeometricStiffness(const FullModel& model, const std::vector<double>& u,
                                                   const CrsMatrix& pattern) {
  requireElements(model, "the geometric stiffness");
  EPAPHE_REQUIRE(u.size() == 3 * static_cast<std::size_t>(model.numNodes()),
                 "body '" << model.name << "': " << u.size() << " nodal displacements for " << model.numNodes()
                          << " nodes (3 per node expected)");
  const auto rows = pattern.getRowMap();
  auto Ks = Teuchos::rcp(new CrsMatrix(pattern.getCrsGraph()));
  double ue[24], Kg[24 * 24];
  bool complete = true;
  forEachOwnedHex(model, *rows, [&](const std::array<int, 8>& hex, const double(&x)[8][3]) {
    if (!complete) return;
    for (int p = 0; p < 8; ++p)
      for (int d = 0; d < 3; ++d) ue[3 * p + d] = u[3 * static_cast<std::size_t>(hex[p]) + d];
    hex8GeometricStiffness(x, *model.material, ue, Kg);
    complete = sumIntoElementMatrix(model, hex, Kg, *Ks);
  });
  if (!complete) return assembleGeometricStiffness(model, u);
  Ks->fillComplete(pattern.getDomainMap(), pattern.getRangeMap());
  return Ks;
}

Teuchos::RCP<CrsMatrix> sumOnGraph(double a, const CrsMatrix& A, double b, const CrsMatrix& B) {
  if (A.getCrsGraph().get() != B.getCrsGraph().get()) return Tpetra::MatrixMatrix::add(a, false, A, b, false, B);
  auto C = Teuchos::rcp(new CrsMatrix(A.getCrsGraph()));
  typename CrsMatrix::local_inds_host_view_type ia, ib;
  typename CrsMatrix::values_host_view_type va, vb;
  std::vector<double> vc;
  for (LO r = 0; r < static_cast<LO>(A.getNodeNumRows()); ++r) {
    A.getLocalRowView(r, ia, va);
    B.getLocalRowView(r, ib, vb);  // the same graph: the same columns in the same order
    vc.resize(ia.extent(0));
    for (std::size_t k = 0; k < vc.size(); ++k) vc[k] = a * va(k) + b * vb(k);
    C->replaceLocalValues(r, static_cast<LO>(vc.size()), vc.data(), ia.data());
  }
  C->fillComplete(A.getDomainMap(), A.getRangeMap());
  return C;
}

std::vector<double> nodalValues(const FullModel& model, const MultiVector& x) {
  const auto rows = x.getMap();
  const auto data = x.getData(0);
  std::vector<double> owned(static_cast<std::size_t>(model.numFree), 0.0), all(owned.size(), 0.0);
  for (LO i = 0; i < static_cast<LO>(rows->getNodeNumElements()); ++i) owned[rows->getGlobalElement(i)] = data[i];
  Teuchos::reduceAll(*rows->getComm(), Teuchos::REDUCE_SUM, model.numFree, owned.data(), all.data());
  std::vector<double> u(3 * static_cast<std::size_t>(model.numNodes()), 0.0);
  for (std::size_t k = 0; k < u.size(); ++k)
    if (model.eq[k] >= 0) u[k] = all[model.eq[k]];
  return u;
}

}  // namespace epaphe
