#include "Epaphe_SceneCheck.hpp"

#include "Epaphe_BodyHeat.hpp"
#include "Epaphe_BodyModel.hpp"
#include "Epaphe_ContactEnforcement.hpp"
#include "Epaphe_ContactLaw.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ImportedSpeedSource.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_SteadyState.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <map>
#include <set>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

/// Each body's importer's refusals (Box edge lengths, casing meshes) and degenerate planes.
void checkGeometry(const ParameterList& P, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  for (auto it = bl.begin(); it != bl.end(); ++it) checkBodyImport(bl.name(it), bl.sublist(bl.name(it)), origin);
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

/// The contact law 'Method' names: friction and coatings only on a law that takes them, then the
/// law's own refusals (ContactLaw::check).
void checkContactLaw(const ParameterList& P, const std::string& origin) {
  const ParameterList& cp = P.sublist("Contact");
  const ContactLaw& law = contactLaw(cp.get<std::string>("Method"));
  const std::string ctx = origin + ": '" + deck::pathOf(cp, "Method") + "' = '" + law.name() + "'";
  EPAPHE_REQUIRE(law.supportsFriction() || cp.get<double>("Friction coefficient") == 0.0,
                 ctx << " has no Coulomb friction, but '" << deck::pathOf(cp, "Friction coefficient") << "' = "
                     << cp.get<double>("Friction coefficient") << "; set it to 0 or choose a law with friction");
  if (!law.supportsCoatings()) {
    const ParameterList& sl = P.sublist("Surfaces");
    for (auto it = sl.begin(); it != sl.end(); ++it) {
      if (!sl.isSublist(sl.name(it)) || !sl.sublist(sl.name(it)).isSublist("Coating")) continue;
      const ParameterList& coating = sl.sublist(sl.name(it)).sublist("Coating");
      const auto el = deck::getInts(coating, "Elements");
      EPAPHE_REQUIRE(el.size() != 2 || el[0] * el[1] == 0,
                     ctx << " takes no abradable coating, but '" << deck::pathOf(coating, "Elements")
                         << "' gives one; remove the coating or choose a law with coatings");
    }
  }
  law.check(cp, origin);
}

/// The bodies' Reduction lists against the rest of the deck, as each method answers: a method that
/// cannot take penalty contact (the massless boundary) takes Lagrange; a diagonal mass (the full model
/// with lumped mass) only damping that keeps M/h^2 + D/2h diagonal; a method that keeps every node no
/// retained set.
void checkReductions(const ParameterList& P, const DampingOptions& damping, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  const ParameterList& dp = P.sublist("Time").sublist("Damping");
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& bp = bl.sublist(bl.name(it));
    const ParameterList& rp = bp.sublist("Reduction");
    const auto method = reductionMethod(rp);
    const std::string ctx = origin + ": body '" + bl.name(it) + "', '" + deck::pathOf(rp, "Method") + "' = '" +
                            rp.get<std::string>("Method") + "'";
    if (const std::string why = method->penaltyContactProblem(); !why.empty()) {
      const ParameterList& cp = P.sublist("Contact");
      EPAPHE_REQUIRE(contactLaw(cp.get<std::string>("Method")).closesGaps(),
                     ctx << " with '" << deck::pathOf(cp, "Method") << "' = '" << cp.get<std::string>("Method")
                         << "', a law that does not close the gaps: " << why);
    }
    if (method->diagonalMass()) {
      const std::string problem = fullModelDampingProblem(damping);
      EPAPHE_REQUIRE(problem.empty(), ctx << " with '" << deck::pathOf(dp, "Type") << "' = '"
                                          << dp.get<std::string>("Type") << "': " << problem);
    }
    if (!method->retainsNodes())
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
  const auto method = reductionMethod(rp);
  const bool reduced = method->retainsNodes();

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
  for (const BodyLoad& load : bodyLoads(bp, origin))
    if (!load.nodeSet.empty()) mesh.nodeSet(load.nodeSet, origin + ": '" + load.path + "->Node set'");
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
  ReductionMeshFacts facts;
  facts.context = ctx;
  facts.reduction = &rp;
  facts.freeDofs = freeDofs;
  facts.retainedDofs = 3 * static_cast<int>(retained.size());
  facts.clampedSet = clampedSet;
  facts.gravity = deck::getVec3(bp, "Gravity", origin);
  method->checkMesh(facts);

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

std::vector<BodyLoad> bodyLoads(const ParameterList& bp, const std::string& origin) {
  std::vector<BodyLoad> loads;
  if (!bp.isSublist("Loads")) return loads;
  const ParameterList& ll = bp.sublist("Loads");
  for (auto it = ll.begin(); it != ll.end(); ++it) {
    const ParameterList& lp = ll.sublist(ll.name(it));
    BodyLoad load;
    load.name = ll.name(it);
    load.path = deck::pathOf(ll, load.name);
    load.nodeSet = lp.get<std::string>("Node set");
    load.reducedDofs = deck::getInts(lp, "Reduced DOFs");
    load.reducedForces = deck::getDoubles(lp, "Reduced forces");
    if (load.reducedDofs.empty()) {
      EPAPHE_REQUIRE(load.reducedForces.empty(),
                     origin << ": '" << deck::pathOf(lp, "Reduced forces") << "' has " << load.reducedForces.size()
                            << " value(s) but 'Reduced DOFs' is empty; list the model's coordinates they act on");
      EPAPHE_REQUIRE(!load.nodeSet.empty(),
                     origin << ": '" << deck::pathOf(lp, "Node set")
                            << "' is empty; name the node set the force acts on (or give 'Reduced DOFs')");
      load.force = deck::getVec3(lp, "Force", origin);
    } else {
      EPAPHE_REQUIRE(load.nodeSet.empty(),
                     origin << ": '" << load.path << "' has both 'Node set' = '" << load.nodeSet
                            << "' and 'Reduced DOFs': a load acts on nodes or on the model's coordinates; split it "
                               "into two loads");
      EPAPHE_REQUIRE(load.reducedForces.size() == load.reducedDofs.size(),
                     origin << ": '" << deck::pathOf(lp, "Reduced forces") << "' has " << load.reducedForces.size()
                            << " value(s) for " << load.reducedDofs.size()
                            << " 'Reduced DOFs'; give one force for each DOF");
      for (int j : load.reducedDofs)
        EPAPHE_REQUIRE(j >= 0, origin << ": '" << deck::pathOf(lp, "Reduced DOFs") << "' holds " << j
                                      << "; the model's coordinates are numbered from 0");
    }
    const std::string at = origin + ": '" + load.path + "'";
    switch (deck::getEnum<LoadTimeKind>(lp, "Time function")) {
      case LoadTimeKind::Constant:
        load.g = LoadTimeFunction::constant();
        break;
      case LoadTimeKind::Harmonic: {
        const double nu = lp.get<double>("Frequency");
        EPAPHE_REQUIRE(nu > 0, origin << ": '" << deck::pathOf(lp, "Frequency") << "' = " << nu
                                      << " Hz: a Harmonic load needs the frequency of its drive, > 0; set it, or use "
                                         "'Time function' = Constant for a static load");
        load.g = LoadTimeFunction::harmonic(nu, lp.get<double>("Phase"));
        break;
      }
      case LoadTimeKind::Table:
        load.g = LoadTimeFunction::table(deck::getDoubles(lp, "Times"), deck::getDoubles(lp, "Values"),
                                         at + ", 'Time function' = Table ('Times', 'Values')");
        break;
      case LoadTimeKind::Ramp: {
        const double T = lp.get<double>("Ramp time");
        EPAPHE_REQUIRE(T > 0, origin << ": '" << deck::pathOf(lp, "Ramp time") << "' = " << T
                                     << " s: a Ramp load needs the time it takes to rise, > 0; set it");
        load.g = LoadTimeFunction::ramp(T);
        break;
      }
    }
    loads.push_back(std::move(load));
  }
  return loads;
}

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
    EPAPHE_REQUIRE(reductionMethod(bp.sublist("Reduction"))->projectsCoriolis(),
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

/// A body with a thermal model: a speed constant in time, and its 'Thermal' list.
void checkThermalScene(const ParameterList& P, const std::string& body, const std::string& origin) {
  const ParameterList& bp = P.sublist("Bodies").sublist(body);
  const std::string ctx = origin + ": body '" + body + "'";
  const ParameterList& bl = P.sublist("Bodies");
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& other = bl.sublist(bl.name(it));
    if (!other.isSublist("Rotation") || !other.sublist("Rotation").isSublist("Speed law")) continue;
    const ParameterList& law = other.sublist("Rotation").sublist("Speed law");
    EPAPHE_REQUIRE(law.get<std::string>("Type") == "Constant",
                   ctx << ": '" << deck::pathOf(bp, "Thermal") << "' with '" << deck::pathOf(law, "Type") << "' = '"
                       << law.get<std::string>("Type")
                       << "': the frictional heat is made with a constant speed only; remove one of them");
  }
  EPAPHE_REQUIRE(hasBuiltInMesh(bp) || hasCalculixMesh(bp),
                 ctx << ": '" << deck::pathOf(bp, "Thermal") << "' needs the mesh's elements (the thermal model is "
                     << "assembled on them), and 'Mesh->Type' = '" << bp.sublist("Mesh").get<std::string>("Type")
                     << "' imports matrices and nodes only; use a built-in mesh or a CalculiX import, or remove it");
  checkThermal(bp, buildThermalMesh(body, bp, origin), ctx, body, origin);
}

std::vector<double> instanceFactors(const ParameterList& bp, const std::string& ctx) {
  const ParameterList& ip = bp.sublist("Instances");
  const int count = ip.get<int>("Count");
  std::vector<double> f = deck::getDoubles(ip, "Stiffness factors");
  const double sigma = ip.get<double>("Mistuning standard deviation");
  if (!f.empty()) {
    EPAPHE_REQUIRE(sigma == 0, ctx << ": 'Instances' gives both 'Stiffness factors' and 'Mistuning standard "
                                      "deviation' = "
                                   << sigma << "; keep one");
    EPAPHE_REQUIRE(static_cast<int>(f.size()) == count, ctx << ": 'Instances->Stiffness factors' has " << f.size()
                                                            << " values for 'Count' = " << count
                                                            << " instances; give one per instance");
    for (std::size_t k = 0; k < f.size(); ++k)
      EPAPHE_REQUIRE(f[k] > 0, ctx << ": 'Instances->Stiffness factors' value " << k << " is " << f[k]
                                   << "; a stiffness factor must be > 0 (1: tuned)");
    return f;
  }
  f.assign(static_cast<std::size_t>(count), 1.0);
  if (sigma == 0) return f;
  std::mt19937_64 gen(static_cast<std::uint64_t>(ip.get<int>("Seed")));
  const double scale = 1.0 / 18446744073709551616.0;  // 2^-64: a uniform in [0, 1)
  for (std::size_t k = 0; k < f.size(); k += 2) {
    const double u1 = (static_cast<double>(gen()) + 0.5) * scale, u2 = static_cast<double>(gen()) * scale;
    const double r = std::sqrt(-2 * std::log(u1));
    f[k] = 1 + sigma * r * std::cos(2 * M_PI * u2);
    if (k + 1 < f.size()) f[k + 1] = 1 + sigma * r * std::sin(2 * M_PI * u2);
  }
  // sigma <= 0.3 (the schema): a factor <= 0 is a draw beyond 3.3 sigma, which this refuses
  for (double v : f)
    EPAPHE_REQUIRE(v > 0, ctx << ": 'Instances->Mistuning standard deviation' = " << sigma
                              << " drew a stiffness factor of " << v << " <= 0; give a smaller deviation or "
                              << "another 'Seed'");
  return f;
}

namespace {

/// A stage ('Instances' with Count > 1): its factors, a steady speed, no mistuning at speed; no other
/// body with contact nodes, no surface carried by it, no coating (each instance would wear its own copy).
void checkInstances(const ParameterList& P, const std::string& origin) {
  const ParameterList& bl = P.sublist("Bodies");
  const ParameterList& surfs = P.sublist("Surfaces");
  std::string staged;
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& bp = bl.sublist(bl.name(it));
    if (bp.sublist("Instances").get<int>("Count") == 1) continue;
    const std::string ctx = origin + ": body '" + bl.name(it) + "'";
    const std::vector<double> f = instanceFactors(bp, ctx);
    EPAPHE_REQUIRE(staged.empty(), ctx << " and body '" << staged
                                       << "' both have 'Instances': a deck holds one stage; instance one body");
    staged = bl.name(it);
    const ParameterList& rot = bp.sublist("Rotation");
    EPAPHE_REQUIRE(!speedLawOf(rot).ramp, ctx << ": 'Instances' with a run-up ('Rotation->Speed law' Type Ramp): a "
                                                 "stage runs at a steady speed; remove the Speed law or the "
                                                 "Instances list");
    const bool tuned = std::all_of(f.begin(), f.end(), [](double v) { return v == 1; });
    EPAPHE_REQUIRE(tuned || rot.get<double>("Speed") == 0,
                   ctx << ": mistuning ('Instances') of a body at speed (" << rot.get<double>("Speed")
                       << " rad/s) would scale its stress stiffening and spin softening with its elastic "
                          "stiffness; mistune a body at rest, or remove the stiffness factors");
    for (auto s = surfs.begin(); s != surfs.end(); ++s) {
      const ParameterList& sp = surfs.sublist(surfs.name(s));
      EPAPHE_REQUIRE(
          deck::getEnum<SurfaceType>(sp, "Type") != SurfaceType::BodyFace || sp.get<std::string>("Body") != staged,
          origin << ": surface '" << surfs.name(s) << "' is carried by body '" << staged
                 << "', which has 'Instances'; a surface is carried by one body (the casing), not by "
                    "the instances of a stage");
      EPAPHE_REQUIRE(!sp.isSublist("Coating") || deck::getInts(sp.sublist("Coating"), "Elements")[0] == 0,
                     origin << ": surface '" << surfs.name(s) << "' has a Coating and body '" << staged
                            << "' has 'Instances': each instance would wear its own copy of the coating; remove "
                               "the Coating or the Instances list");
    }
  }
  if (staged.empty()) return;
  for (auto it = bl.begin(); it != bl.end(); ++it)
    EPAPHE_REQUIRE(bl.name(it) == staged || bl.sublist(bl.name(it)).get<std::string>("Contact node set").empty(),
                   origin << ": body '" << bl.name(it) << "' has contact nodes beside the stage of body '" << staged
                          << "' ('Instances'): each instance meets its own copy of the surfaces, which no "
                             "other body sees; remove its 'Contact node set'");
}

}  // namespace

void checkScene(const Deck& scene, const std::string& outputPath, bool restart) {
  const ParameterList& P = *scene.params;
  const std::string& origin = scene.origin;
  const ParameterList& bl = P.sublist("Bodies");
  EPAPHE_REQUIRE(bl.numParams() > 0, origin << ": 'Epaphe->Bodies' is empty; add a <ParameterList name=\"MyBody\">");
  checkGeometry(P, origin);
  numberOfSteps(P, origin);
  const ParameterList& tp = P.sublist("Time");
  const DampingOptions damping = dampingOptions(tp, origin);
  checkContactLaw(P, origin);
  checkReductions(P, damping, origin);
  checkBodyFaceReferences(P, origin);
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& bp = bl.sublist(bl.name(it));
    bodyModelFiles(bl.name(it), bp, origin);  // the files an imported model reads exist
    bodyLoads(bp, origin);                    // the loads' keys (their node sets with the mesh)
    if (hasBuiltInMesh(bp)) checkBodyMesh(P, bl.name(it), buildBodyMesh(bl.name(it), bp, origin), origin);
    if (hasThermalModel(bp)) checkThermalScene(P, bl.name(it), origin);
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
      const auto method = reductionMethod(bp.sublist("Reduction"));
      EPAPHE_REQUIRE(method->hasParametricModel(),
                     ctx << "->Speed range: the parametric model over a speed range is built by Craig-Bampton, "
                         << "Guyan or the massless boundary, not by '"
                         << bp.sublist("Reduction").get<std::string>("Method")
                         << "'; set 'Reduction->Method' to Craig-Bampton, or remove 'Speed range' (the model is then "
                            "reduced at 'Speed' directly)");
      method->checkSpeedRange(bp, ctx);
    }
  }
  checkBodyFacesNotOwnContact(P, origin);
  checkInstances(P, origin);
  if (const SteadyStateOptions ss = steadyStateOptions(P, origin); ss.enabled) {
    const ParameterList& bp = bl.sublist(ss.body);
    if (hasBuiltInMesh(bp))
      buildBodyMesh(ss.body, bp, origin).nodeSet(ss.nodeSet, origin + ": 'Steady state->Node set'");
  }
  if (tp.get<std::string>("Initial state") == "Static equilibrium") {
    // eq. 71 holds the touching nodes where they are: exact with a law that closes gaps, on surfaces at rest
    const ParameterList& cp = P.sublist("Contact");
    EPAPHE_REQUIRE(cp.get<std::string>("Method") == "Lagrange",
                   origin << ": 'Time->Initial state' = Static equilibrium holds the touching nodes exactly, as "
                             "Lagrange contact does, but 'Contact->Method' = '"
                          << cp.get<std::string>("Method") << "' (a penalty spring would first have to compress); use "
                          << "Lagrange, or start 'At rest'");
    bool contactNodes = false;
    for (auto it = bl.begin(); it != bl.end(); ++it) {
      const ParameterList& bp = bl.sublist(bl.name(it));
      contactNodes = contactNodes || !bp.get<std::string>("Contact node set").empty();
      // measured (verification.preload): a stuck massless boundary leaves its static start within a step
      EPAPHE_REQUIRE(cp.get<double>("Friction coefficient") == 0.0 ||
                         bp.sublist("Reduction").get<std::string>("Method") != "Massless boundary",
                     origin << ": 'Time->Initial state' = Static equilibrium with friction ('Contact->Friction "
                               "coefficient' = "
                            << cp.get<double>("Friction coefficient") << ") on body '" << bl.name(it)
                            << "', a Massless boundary: its stuck start does not yet stand still; reduce it by "
                               "Craig-Bampton, or set the friction coefficient to 0, or start 'At rest'");
    }
    EPAPHE_REQUIRE(contactNodes, origin << ": 'Time->Initial state' = Static equilibrium needs contact nodes "
                                           "('Contact node set') that touch a surface at t = 0");
    const ParameterList& surfs = P.sublist("Surfaces");
    for (auto it = surfs.begin(); it != surfs.end(); ++it) {
      const ParameterList& s = surfs.sublist(surfs.name(it));
      EPAPHE_REQUIRE(
          deck::getEnum<SurfaceType>(s, "Type") != SurfaceType::BodyFace && s.get<double>("Rotation speed") == 0.0,
          origin << ": 'Time->Initial state' = Static equilibrium holds the contact nodes against surfaces at "
                    "rest, but surface '"
                 << surfs.name(it)
                 << "' is carried by a body or turns; start 'At rest' (or make the surface rigid and still)");
    }
  }
  checkRunUp(P, origin);
  checkCoriolis(P, origin);
  // The files the run creates: the history, and each reduced-model cache.
  if (!restart) io::Hdf5File::checkCreatable(outputPath);
  for (auto it = bl.begin(); it != bl.end(); ++it) {
    const ParameterList& rp = bl.sublist(bl.name(it)).sublist("Reduction");
    if (rp.get<bool>("Cache") && reductionMethod(rp)->cacheable())
      io::Hdf5File::checkCreatable(cacheFileOf(rp, outputPath, bl.name(it)));
  }
}

}  // namespace epaphe
