#include "Epaphe_SceneCheck.hpp"

#include "Epaphe_BodyModel.hpp"
#include "Epaphe_ContactEnforcement.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ImportedSpeedSource.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_Mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

/// Box edge lengths, casing meshes and degenerate planes.
void checkGeometry(const ParameterList& P, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& mp = bl.sublist(bl.name(it)).sublist("Mesh");
    if (deck::getEnum<MeshType>(mp, "Type") == MeshType::Casing) checkCasingMesh(bl.name(it), mp, origin);
    if (deck::getEnum<MeshType>(mp, "Type") != MeshType::Box) continue;
    const auto L = deck::getVec3(mp, "Lengths", origin);
    for (int d = 0; d < 3; ++d)
      EPAPHE_REQUIRE(L[d] > 0, origin << ": '" << deck::pathOf(mp, "Lengths") << "' = {" << L[0] << ", " << L[1] << ", "
                                      << L[2] << "}: the length along "
                                      << "xyz"[d] << " is " << L[d] << "; every edge length must be positive");
  }
  const ParameterList& surfs = P.sublist("Surfaces");
  for (auto it = surfs.begin(); it != surfs.end(); ++it) {
    const ParameterList& s = surfs.sublist(surfs.name(it));
    if (deck::getEnum<SurfaceType>(s, "Type") != SurfaceType::Plane) continue;
    const auto U = deck::getVec3(s, "U", origin), V = deck::getVec3(s, "V", origin);
    const std::array<double, 3> n = {U[1] * V[2] - U[2] * V[1], U[2] * V[0] - U[0] * V[2], U[0] * V[1] - U[1] * V[0]};
    const double nu = std::sqrt(U[0] * U[0] + U[1] * U[1] + U[2] * U[2]);
    const double nv = std::sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
    const double area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    EPAPHE_REQUIRE(area > 1e-12 * nu * nv && nu > 0 && nv > 0,
                   origin << ": surface '" << surfs.name(it) << "': 'U' = {" << U[0] << ", " << U[1] << ", " << U[2]
                          << "} and 'V' = {" << V[0] << ", " << V[1] << ", " << V[2]
                          << "} are parallel or zero; a plane needs two independent edge vectors");
  }
}

/// The bodies' Reduction lists against the rest of the deck: a massless boundary takes Lagrange
/// contact; a full model with lumped mass takes no retained set
/// and only damping that keeps M/h^2 + D/2h diagonal.
void checkReductions(const ParameterList& P, const DampingOptions& damping, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  const ParameterList& dp = P.sublist("Time").sublist("Damping");
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& bp = bl.sublist(bl.name(it));
    const ParameterList& rp = bp.sublist("Reduction");
    const auto method = deck::getEnum<ReductionMethod>(rp, "Method");
    const std::string ctx = origin + ": body '" + bl.name(it) + "', '" + deck::pathOf(rp, "Method") + "' = '" +
                            rp.get<std::string>("Method") + "'";
    if (method == ReductionMethod::MasslessBoundary) {
      const ParameterList& cp = P.sublist("Contact");
      EPAPHE_REQUIRE(deck::getEnum<ContactMethod>(cp, "Method") == ContactMethod::Lagrange,
                     ctx << " with '" << deck::pathOf(cp, "Method") << "' = '" << cp.get<std::string>("Method")
                         << "': a penalty force computed from the predicted gap would ignore the boundary's static "
                            "residual flexibility (its nodes have no mass to lag behind the force); use 'Lagrange', "
                            "or 'Craig-Bampton' for penalty contact");
    }
    if (method != ReductionMethod::FullLumped) continue;
    const std::string problem = fullModelDampingProblem(damping);
    EPAPHE_REQUIRE(problem.empty(), ctx << " with '" << deck::pathOf(dp, "Type") << "' = '"
                                        << dp.get<std::string>("Type") << "': " << problem);
    EPAPHE_REQUIRE(rp.get<std::string>("Retained node set").empty(),
                   ctx << " keeps every node, but '" << deck::pathOf(rp, "Retained node set") << "' = '"
                       << rp.get<std::string>("Retained node set") << "'; remove the key (or reduce the body)");
  }
}

/// Grid (i along the arc, j along the axis) of a Cylinder arc surface: with e1 the reference
/// direction and e2 = axis x e1, S_u x S_v points away from the axis.
std::vector<double> cylinderArcGrid(const ParameterList& s, int na, int nz, const std::string& origin) {
  const auto c = deck::getVec3(s, "Center", origin);
  auto a = deck::getVec3(s, "Axis", origin), e1 = deck::getVec3(s, "Reference", origin);
  const double R = s.get<double>("Radius");
  const auto ang = deck::getDoubles(s, "Angles"), ax = deck::getDoubles(s, "Axial range");
  EPAPHE_REQUIRE(ang.size() == 2 && ax.size() == 2 && ang[1] > ang[0] && ax[1] > ax[0],
                 origin << ": '" << deck::pathOf(s, "Angles")
                        << "' and 'Axial range' must each be {first, last} with "
                           "last > first");
  auto norm = [](std::array<double, 3>& v) {
    const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (double& x : v) x /= l;
    return l;
  };
  EPAPHE_REQUIRE(norm(a) > 0, origin << ": '" << deck::pathOf(s, "Axis") << "' is the zero vector");
  const double along = e1[0] * a[0] + e1[1] * a[1] + e1[2] * a[2];
  for (int d = 0; d < 3; ++d) e1[d] -= along * a[d];
  EPAPHE_REQUIRE(norm(e1) > 1e-12, origin << ": '" << deck::pathOf(s, "Reference") << "' is parallel to the axis");
  const std::array<double, 3> e2 = {a[1] * e1[2] - a[2] * e1[1], a[2] * e1[0] - a[0] * e1[2],
                                    a[0] * e1[1] - a[1] * e1[0]};
  std::vector<double> grid;
  for (int i = 0; i < na; ++i) {
    const double t = (ang[0] + (ang[1] - ang[0]) * i / (na - 1)) * M_PI / 180.0;
    for (int j = 0; j < nz; ++j) {
      const double z = ax[0] + (ax[1] - ax[0]) * j / (nz - 1);
      for (int d = 0; d < 3; ++d) grid.push_back(c[d] + R * (std::cos(t) * e1[d] + std::sin(t) * e2[d]) + z * a[d]);
    }
  }
  return grid;
}

/// Grid of a Casing surface: around the z axis, the casing's radius(theta, z) (cone and clearance
/// law, CasingGeometry::radiusAt, the law the Casing mesh's inner face follows too); nt distinct
/// angles and the first repeated (a closed surface), nz axial positions over the Axial range.
std::vector<double> casingGrid(const ParameterList& s, int nt, int nz, const std::string& origin) {
  const CasingGeometry g = casingGeometry(s, "Radius", origin);
  std::vector<double> grid;
  for (int i = 0; i <= nt; ++i) {
    const double th = 2.0 * M_PI * (i % nt) / nt;
    for (int j = 0; j < nz; ++j) {
      const double z = g.axialStation(j, nz), r = g.radiusAt(th, z);
      grid.insert(grid.end(), {r * std::cos(th), r * std::sin(th), z});
    }
  }
  return grid;
}

/// Every rigid surface's grid can be built, and a Body face surface names a body of the deck.
void checkBodyFaceReferences(const ParameterList& P, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  const ParameterList& surfs = P.sublist("Surfaces");
  for (auto it = surfs.begin(); it != surfs.end(); ++it) {
    const std::string name = surfs.name(it);
    const ParameterList& s = surfs.sublist(name);
    if (deck::getEnum<SurfaceType>(s, "Type") != SurfaceType::BodyFace) {
      rigidSurfaceGrid(s, origin);
      continue;
    }
    const std::string bodyName = s.get<std::string>("Body");
    if (!bl.isSublist(bodyName)) {
      ErrorBuilder eb;
      eb << origin << ": '" << deck::pathOf(s, "Body") << "' = '" << bodyName << "' is not a body; the deck has:";
      for (auto b = bl.begin(); b != bl.end(); ++b) eb << " '" << bl.name(b) << "'";
      eb.raise();
    }
  }
}

/// A Body face surface's body has no contact nodes of its own (checked after the body's mesh, whose
/// faults a deck shows first).
void checkBodyFacesNotOwnContact(const ParameterList& P, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  const ParameterList& surfs = P.sublist("Surfaces");
  for (auto it = surfs.begin(); it != surfs.end(); ++it) {
    const std::string name = surfs.name(it);
    const ParameterList& s = surfs.sublist(name);
    if (deck::getEnum<SurfaceType>(s, "Type") != SurfaceType::BodyFace) continue;
    const std::string bodyName = s.get<std::string>("Body");
    const ParameterList& bp = bl.sublist(bodyName);
    const std::string contactSet = bp.get<std::string>("Contact node set");
    EPAPHE_REQUIRE(contactSet.empty(),
                   origin << ": surface '" << name << "' is carried by body '" << bodyName << "' ('"
                          << deck::pathOf(s, "Body") << "'), whose own nodes are contact nodes ('"
                          << deck::pathOf(bp, "Contact node set") << "' = '" << contactSet
                          << "'): a node cannot touch a surface of its own body"
                          << (s.get<double>("Rotation speed") != 0.0 ? " (nor can a surface turn relative to its own "
                                                                       "body)"
                                                                     : "")
                          << "; carry the surface by another body, or remove that 'Contact node set'");
  }
}

/// What the built-in mesh of a body shows without assembling it: the node sets the deck names exist,
/// the contact nodes and carried grids are retained and not clamped, the modes fit the condensed
/// DOFs, and gravity acts on a model whose rigid translation is a motion.
void checkBodyMesh(const ParameterList& P, const std::string& body, const Mesh& mesh, const std::string& origin) {
  const ParameterList& bp = P.sublist("Bodies").sublist(body);
  const ParameterList& rp = bp.sublist("Reduction");
  const std::string ctx = origin + ": body '" + body + "'";
  const auto method = deck::getEnum<ReductionMethod>(rp, "Method");
  const bool reduced = method == ReductionMethod::CraigBampton || method == ReductionMethod::Guyan ||
                       method == ReductionMethod::MasslessBoundary;

  const std::string clampedSet = bp.get<std::string>("Clamped node set"),
                    contactSet = bp.get<std::string>("Contact node set");
  std::set<int> clamped;
  if (!clampedSet.empty())
    for (int n : mesh.nodeSet(clampedSet, ctx + ", 'Clamped node set'")) clamped.insert(n);
  std::string retainedSet = rp.get<std::string>("Retained node set");
  if (retainedSet.empty()) retainedSet = contactSet;
  std::set<int> retained;
  if (reduced) {
    EPAPHE_REQUIRE(!retainedSet.empty(), ctx << ": reduction " << rp.get<std::string>("Method")
                                             << " needs a 'Retained node set' (or a 'Contact node set')");
    for (int n : mesh.nodeSet(retainedSet, ctx + ", 'Reduction->Retained node set'"))
      if (!clamped.count(n)) retained.insert(n);
  }
  for (const std::string& ws : deck::getStrings(bp, "Watched node sets"))
    mesh.nodeSet(ws, ctx + ", 'Watched node sets'");
  if (!contactSet.empty())
    for (int n : mesh.nodeSet(contactSet, ctx + ", 'Contact node set'")) {
      EPAPHE_REQUIRE(!clamped.count(n), ctx << ": contact node " << mesh.nodeId(n) << " of '" << contactSet
                                            << "' is clamped by 'Clamped node set' = '" << clampedSet
                                            << "'; a contact node must be free to move: do not clamp contact nodes");
      EPAPHE_REQUIRE(!reduced || retained.count(n),
                     ctx << ": contact node " << mesh.nodeId(n) << " (of '" << contactSet
                         << "') is not a retained DOF: it is not in 'Reduction->Retained "
                            "node set' = '"
                         << retainedSet << "'; add the contact node set to the retained node set");
    }

  const int freeDofs = 3 * (mesh.numNodes() - static_cast<int>(clamped.size()));
  const int retainedDofs = 3 * static_cast<int>(retained.size()), modes = rp.get<int>("Fixed-interface modes");
  if (method == ReductionMethod::CraigBampton)
    EPAPHE_REQUIRE(modes <= freeDofs - retainedDofs,
                   ctx << ": " << modes << " fixed-interface modes asked but only " << freeDofs - retainedDofs
                       << " condensed DOFs exist (" << freeDofs << " free, " << retainedDofs << " retained); set '"
                       << deck::pathOf(rp, "Fixed-interface modes") << "' <= " << freeDofs - retainedDofs);
  if (method == ReductionMethod::MasslessBoundary) {
    const int rigid = clamped.empty() ? 6 : 0;  // a free body keeps its rigid-body modes too
    EPAPHE_REQUIRE(retainedDofs + modes + rigid <= freeDofs,
                   ctx << ": " << retainedDofs << " retained DOFs and " << modes << " modes"
                       << (rigid ? " (and the free body's 6 rigid-body modes)" : "") << " exceed the model's "
                       << freeDofs << " free DOFs; keep fewer modes");
  }
  if (const int candidates = rp.get<int>("Candidate modes"); candidates > 0) {
    EPAPHE_REQUIRE(
        method == ReductionMethod::MasslessBoundary,
        ctx << ": '" << deck::pathOf(rp, "Candidate modes") << "' = " << candidates
            << " selects modes for a Massless boundary only; remove it, or set 'Method' to Massless boundary");
    EPAPHE_REQUIRE(candidates >= modes, ctx << ": '" << deck::pathOf(rp, "Candidate modes") << "' = " << candidates
                                            << " is fewer than the " << modes << " 'Fixed-interface modes' kept");
    const int rigid = clamped.empty() ? 6 : 0;
    EPAPHE_REQUIRE(retainedDofs + candidates + rigid <= freeDofs,
                   ctx << ": " << candidates << " candidate modes and " << retainedDofs << " retained DOFs exceed the "
                       << "model's " << freeDofs << " free DOFs; ask fewer 'Candidate modes'");
    const auto d = deck::getVec3(rp, "Load direction", origin);
    EPAPHE_REQUIRE(d[0] != 0.0 || d[1] != 0.0 || d[2] != 0.0,
                   ctx << ": '" << deck::pathOf(rp, "Candidate modes") << "' = " << candidates
                       << " needs the direction "
                       << "of the contact's load: set '" << deck::pathOf(rp, "Load direction") << "', e.g. {1, 0, 0}");
  }
  const auto g = deck::getVec3(bp, "Gravity", origin);
  if (!clamped.empty() && (method == ReductionMethod::CraigBampton || method == ReductionMethod::Guyan))
    for (int d = 0; d < 3; ++d)
      EPAPHE_REQUIRE(g[d] == 0,
                     ctx << ", 'Gravity' = {" << g[0] << ", " << g[1] << ", " << g[2] << "}: a rigid translation along "
                         << "xyz"[d] << " is not a motion of its " << rp.get<std::string>("Method")
                         << " model (its rigid translations are held): "
                         << "the body is held by 'Clamped node set' = '" << clampedSet
                         << "', so M t is not its weight T^T M e; use 'Full, lumped mass' (weight exact with "
                            "clamps), or remove the key");

  const ParameterList& surfs = P.sublist("Surfaces");
  for (auto it = surfs.begin(); it != surfs.end(); ++it) {
    const std::string name = surfs.name(it);
    const ParameterList& s = surfs.sublist(name);
    if (deck::getEnum<SurfaceType>(s, "Type") != SurfaceType::BodyFace || s.get<std::string>("Body") != body) continue;
    const std::string gridName = s.get<std::string>("Node grid");
    const auto git = mesh.nodeGrids.find(gridName);
    if (git == mesh.nodeGrids.end()) {
      ErrorBuilder eb;
      eb << origin << ": '" << deck::pathOf(s, "Node grid") << "' = '" << gridName << "' is not a node grid of body '"
         << body << "'; it has:";
      for (const auto& [gn, grid] : mesh.nodeGrids) eb << " '" << gn << "' (" << grid.nu << " x " << grid.nv << ")";
      eb.raise();
    }
    const NodeGrid& grid = git->second;
    EPAPHE_REQUIRE(grid.nu >= 4 && grid.nv >= 4, origin << ": surface '" << name << "': node grid '" << gridName
                                                        << "' of body '" << body << "' is " << grid.nu << " x "
                                                        << grid.nv
                                                        << " nodes; a bicubic surface needs at least 4 in each "
                                                           "direction: refine the mesh");
    int free = 0;
    for (int node : grid.nodes) {
      if (clamped.count(node)) continue;
      ++free;
      EPAPHE_REQUIRE(!reduced || retained.count(node),
                     origin << ": surface '" << name << "': node " << mesh.nodeId(node) << " of grid '" << gridName
                            << "' is not a retained node of body '" << body << "'; add the grid's node set to its "
                            << "'Reduction->Retained node set'");
    }
    EPAPHE_REQUIRE(free > 0, origin << ": surface '" << name << "': every node of grid '" << gridName
                                    << "' is clamped; use a rigid surface");
  }
}

}  // namespace

DampingOptions dampingOptions(const ParameterList& tp, const std::string& origin) {
  const ParameterList& dp = tp.sublist("Damping");
  DampingOptions damping;
  damping.type = deck::getEnum<DampingType>(dp, "Type");
  damping.alpha = dp.get<double>("Alpha");
  damping.beta = dp.get<double>("Beta");
  damping.ratio = dp.get<double>("Ratio");
  if (const auto f = deck::getDoubles(dp, "Rayleigh frequencies"); !f.empty()) {
    const auto xi = deck::getDoubles(dp, "Rayleigh ratios");
    EPAPHE_REQUIRE(f.size() == 2 && xi.size() == 2, origin << ": 'Time->Damping->Rayleigh frequencies' and "
                                                              "'Rayleigh ratios' must both have 2 values");
    rayleighFromRatios(f[0], xi[0], f[1], xi[1], damping.alpha, damping.beta);
  }
  return damping;
}

RigidGrid rigidSurfaceGrid(const ParameterList& s, const std::string& origin) {
  const auto pts = deck::getInts(s, "Points");
  EPAPHE_REQUIRE(pts.size() == 2, origin << ": '" << deck::pathOf(s, "Points") << "' has " << pts.size()
                                         << " values; give the grid size as {nu, nv}");
  EPAPHE_REQUIRE(pts[0] >= 4 && pts[1] >= 4, origin << ": '" << deck::pathOf(s, "Points") << "' = {" << pts[0] << ", "
                                                    << pts[1]
                                                    << "}; a bicubic surface needs at least 4 points in each "
                                                       "direction");
  RigidGrid g;
  g.nu = pts[0];
  g.nv = pts[1];
  const auto type = deck::getEnum<SurfaceType>(s, "Type");
  if (type == SurfaceType::Plane) {
    const auto o = deck::getVec3(s, "Origin", origin), U = deck::getVec3(s, "U", origin),
               V = deck::getVec3(s, "V", origin);
    for (int i = 0; i < g.nu; ++i)
      for (int j = 0; j < g.nv; ++j)
        for (int d = 0; d < 3; ++d) g.points.push_back(o[d] + U[d] * i / (g.nu - 1) + V[d] * j / (g.nv - 1));
  } else if (type == SurfaceType::Casing) {
    g.points = casingGrid(s, g.nu, g.nv, origin);
    g.nu += 1;  // the first row repeated: closed
    g.towardsAxis = true;
  } else {
    g.points = cylinderArcGrid(s, g.nu, g.nv, origin);
  }
  return g;
}

double fastestRotation(const ParameterList& P) {
  double omega = 0;
  for (const auto& s : P.sublist("Surfaces"))
    omega = std::max(omega, std::abs(P.sublist("Surfaces").sublist(s.first).get<double>("Rotation speed")));
  return omega;
}

SpeedLaw speedLawOf(const ParameterList& rotation) {
  SpeedLaw law;
  const ParameterList& l = rotation.sublist("Speed law");
  law.start = law.end = rotation.get<double>("Speed");
  if (l.get<std::string>("Type") != "Ramp") return law;
  law.ramp = true;
  law.start = l.get<double>("Start speed");
  law.end = l.get<double>("End speed");
  law.t0 = l.get<double>("Start time");
  law.t1 = l.get<double>("End time");
  return law;
}

SpeedLaw runUpOf(const ParameterList& P) {
  const ParameterList& bl = P.sublist("Bodies");
  for (auto it = bl.begin(); it != bl.end(); ++it)
    if (const SpeedLaw law = speedLawOf(bl.sublist(bl.name(it)).sublist("Rotation")); law.ramp) return law;
  return SpeedLaw{};
}

namespace {

/// A run-up (a 'Speed law' of Type Ramp): on a body with a speed range that holds it, starting at the
/// body's 'Speed' (> 0), one driven body, and every turning surface at the start speed (it then turns
/// with the law, its sense kept: the law is the one source of the speed).
void checkRunUp(const ParameterList& P, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  int driven = 0;
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& rot = bl.sublist(bl.name(it)).sublist("Rotation");
    const SpeedLaw law = speedLawOf(rot);
    if (!law.ramp) continue;
    const std::string ctx = origin + ": body '" + bl.name(it) + "', Rotation->Speed law (Type Ramp)";
    const auto range = deck::getDoubles(rot, "Speed range");
    EPAPHE_REQUIRE(!range.empty(), ctx << ": a run-up needs a rotating body with a 'Speed range' (its model at "
                                          "each speed comes from the parametric model over the range); give "
                                          "'Rotation->Speed range' = {min, max} holding the start and end speeds, "
                                          "and 'Rotation->Speed' = 'Start speed'");
    EPAPHE_REQUIRE(law.start > 0 && law.start >= range[0] && law.start <= range[1] && law.end >= range[0] &&
                       law.end <= range[1] && law.t1 > law.t0 && rot.get<double>("Speed") == law.start,
                   ctx << ": Start speed " << law.start << ", End speed " << law.end << " rad/s, Start time " << law.t0
                       << ", End time " << law.t1 << " s, Speed " << rot.get<double>("Speed")
                       << " rad/s: a ramp needs 0 < Start speed = Speed, both speeds inside 'Speed range' {" << range[0]
                       << ", " << range[1] << "} and End time > Start time");
    ++driven;
    for (const auto& s : P.sublist("Surfaces")) {
      const double w = P.sublist("Surfaces").sublist(s.first).get<double>("Rotation speed");
      EPAPHE_REQUIRE(w == 0.0 || std::abs(w) == law.start,
                     origin << ": surface '" << s.first << "' turns at " << w << " rad/s but the run-up of body '"
                            << bl.name(it) << "' starts at " << law.start << " rad/s; a turning surface follows "
                            << "the run-up's law, so give it 'Rotation speed' = +/- the 'Start speed'");
    }
  }
  EPAPHE_REQUIRE(driven <= 1, origin << ": " << driven
                                     << " bodies have a 'Speed law' of Type Ramp; the turning "
                                        "surfaces follow one law, so give one body the ramp");
}

/// A body that keeps its Coriolis terms ('Rotation->Coriolis'): a dense reduced model (their skew
/// matrix enters the step's velocity term: Epaphe_CentralDifference.hpp), Epaphe's own elements (G is
/// assembled from them), a fixed speed (P = [M/h^2 + (D + Omega G)/2h]^-1, the contact's flexibility,
/// would change along a ramp) and frictionless contact (friction reads a symmetric flexibility).
void checkCoriolis(const ParameterList& P, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& bp = bl.sublist(bl.name(it));
    const ParameterList& rot = bp.sublist("Rotation");
    if (!rot.get<bool>("Coriolis")) continue;
    const std::string ctx = origin + ": body '" + bl.name(it) + "', Rotation->Coriolis = true";
    const auto method = deck::getEnum<ReductionMethod>(bp.sublist("Reduction"), "Method");
    EPAPHE_REQUIRE(
        method == ReductionMethod::CraigBampton || method == ReductionMethod::Guyan || method == ReductionMethod::None,
        ctx << ": the Coriolis terms are kept on a dense reduced model (Craig-Bampton, Guyan or None), "
            << "not with 'Reduction->Method' = '" << bp.sublist("Reduction").get<std::string>("Method")
            << "'; set the method to Craig-Bampton, or 'Coriolis' to false (their size is then reported)");
    EPAPHE_REQUIRE(hasBuiltInMesh(bp),
                   ctx << ": the Coriolis matrix is assembled from the elements of Epaphe's built-in meshes, and this "
                       << "body's model is imported; set 'Coriolis' to false");
    EPAPHE_REQUIRE(!speedLawOf(rot).ramp,
                   ctx << ": a run-up ('Speed law' Type Ramp) keeps no Coriolis terms (the step's flexibility would "
                       << "change with the speed); set 'Coriolis' to false, or run at a fixed speed");
    const double mu = P.sublist("Contact").get<double>("Friction coefficient");
    EPAPHE_REQUIRE(mu == 0.0, ctx << ": 'Contact->Friction coefficient' = " << mu
                                  << "; the Coriolis terms make the contact flexibility non-symmetric, which the "
                                  << "friction solve does not take; set the coefficient to 0 or 'Coriolis' to false");
  }
}

}  // namespace

long long numberOfSteps(const ParameterList& P, const std::string& origin) {
  const ParameterList& tp = P.sublist("Time");
  const double h = tp.get<double>("Time step");
  double endTime = tp.get<double>("End time");
  if (const double revs = tp.get<double>("End revolutions"); revs > 0) {
    const double omega = fastestRotation(P);
    EPAPHE_REQUIRE(omega > 0, origin << ": 'Time->End revolutions' = " << revs
                                     << " but no surface turns; give a 'Rotation speed' or use 'End time'");
    endTime = revs * 2 * M_PI / omega;
  }
  return std::max(1LL, static_cast<long long>(std::ceil(endTime / h - 1e-9)));
}

void checkScene(const Deck& scene, const std::string& outputPath, bool restart) {
  const ParameterList& P = *scene.params;
  const std::string& origin = scene.origin;
  const ParameterList& bl = P.sublist("Bodies");
  EPAPHE_REQUIRE(bl.numParams() > 0, origin << ": 'Epaphe->Bodies' is empty; add a <ParameterList name=\"MyBody\">");
  checkGeometry(P, origin);
  numberOfSteps(P, origin);
  const ParameterList& tp = P.sublist("Time");
  const DampingOptions damping = dampingOptions(tp, origin);
  contactOptions(P.sublist("Contact"), tp.get<double>("Time step"));
  checkReductions(P, damping, origin);
  checkBodyFaceReferences(P, origin);
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& bp = bl.sublist(bl.name(it));
    bodyModelFiles(bl.name(it), bp, origin);  // the files an imported model reads exist
    if (hasBuiltInMesh(bp)) checkBodyMesh(P, bl.name(it), buildBodyMesh(bl.name(it), bp, origin), origin);
    // a rotating body: a finite speed, an axis, and elements Epaphe knows (its built-in meshes)
    const std::string ctx = origin + ": body '" + bl.name(it) + "', Rotation";
    const RotationOptions rotation = rotationOptions(bp.sublist("Rotation"), ctx);
    const auto range = deck::getDoubles(bp.sublist("Rotation"), "Speed range");
    const bool importedAtSpeed = !importedSpeeds(bl.name(it), bp, origin).empty();
    EPAPHE_REQUIRE((rotation.speed == 0 && range.empty()) || hasBuiltInMesh(bp) || importedAtSpeed,
                   ctx << "->Speed = " << rotation.speed << " rad/s: the model is imported, and Epaphe builds the "
                       << "centrifugal terms from the elements of its built-in meshes only; remove the key (the body "
                          "at rest), or import CalculiX matrices at speed ('Rotation->Imported speeds' and 'Imported "
                          "jobs' with a 'Speed range')");
    if (!range.empty()) {
      EPAPHE_REQUIRE(
          range.size() == 2 && range[0] >= 0 && range[1] > range[0] && std::isfinite(range[1]),
          ctx << "->Speed range has " << range.size() << " value(s)"
              << (range.size() == 2 ? " {" + std::to_string(range[0]) + ", " + std::to_string(range[1]) + "}" : "")
              << "; give {minimum, maximum} in rad/s with 0 <= minimum < maximum");
      EPAPHE_REQUIRE(std::abs(rotation.speed) >= range[0] && std::abs(rotation.speed) <= range[1],
                     ctx << "->Speed = " << rotation.speed << " rad/s is outside 'Speed range' {" << range[0] << ", "
                         << range[1]
                         << "}: the parametric model covers only its range; widen the range or change the speed");
      const auto method = deck::getEnum<ReductionMethod>(bp.sublist("Reduction"), "Method");
      EPAPHE_REQUIRE(method == ReductionMethod::CraigBampton || method == ReductionMethod::Guyan ||
                         method == ReductionMethod::MasslessBoundary,
                     ctx << "->Speed range: the parametric model over a speed range is built by Craig-Bampton, "
                         << "Guyan or the massless boundary, not by '"
                         << bp.sublist("Reduction").get<std::string>("Method")
                         << "'; set 'Reduction->Method' to Craig-Bampton, or remove 'Speed range' (the model is then "
                            "reduced at 'Speed' directly)");
      if (method == ReductionMethod::MasslessBoundary) {
        const auto& rp = bp.sublist("Reduction");
        EPAPHE_REQUIRE(
            !bp.get<std::string>("Clamped node set").empty(),
            ctx << "->Speed range: a massless-boundary model over a speed range needs a held body; name a "
                << "'Clamped node set' (a free body has rigid-body modes the parametric model does not keep)");
        EPAPHE_REQUIRE(rp.get<int>("Candidate modes") <= rp.get<int>("Fixed-interface modes"),
                       ctx << "->Speed range: a massless-boundary model over a speed range keeps the lowest modes; "
                           << "remove 'Reduction->Candidate modes' (" << rp.get<int>("Candidate modes") << ")");
      }
    }
  }
  checkBodyFacesNotOwnContact(P, origin);
  checkRunUp(P, origin);
  checkCoriolis(P, origin);
  // The files the run creates: the history, and each reduced-model cache.
  if (!restart) io::Hdf5File::checkCreatable(outputPath);
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& rp = bl.sublist(bl.name(it)).sublist("Reduction");
    if (rp.get<bool>("Cache") && deck::getEnum<ReductionMethod>(rp, "Method") != ReductionMethod::FullLumped)
      io::Hdf5File::checkCreatable(cacheFileOf(rp, outputPath, bl.name(it)));
  }
}

}  // namespace epaphe
