#include "Epaphe_ContactDetection.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace epaphe {
/// How far a closed rigid surface can move relative to any point, per radian it turns about `axis`
/// (unit) through `center`, when it is a radial graph about that axis: rho(phi, z) over the whole
/// turn, z in a fixed range (the closed direction at constant z, angles monotone along it, z
/// monotone along the other). The surface turned by dphi then lies within Hausdorff distance
/// |dphi| max |d rho / d phi| of itself (the point at (phi, z) against the one the turn brings there),
/// and a distance to it changes by no more: for a casing out of round by a clearance law, that rate
/// is the law's slope (rotor 37's two lobes: 3.6e-4 m/rad), not the radius (0.3 m). max |d rho / d phi|
/// = rho |x_perp . t| / |(x_perp x t) . axis| (t the tangent along the closed direction) is sampled at
/// 16 x 16 points a patch and raised by half: a sampled bound, not a proof (the smooth cubic varies
/// little within a patch; the regression skip-distant-nodes checks skipping changes nothing).
/// +infinity when the surface is not such a graph.
double radialTurnRate(const BSplineSurface& S, const std::array<double, 3>& axis, const std::array<double, 3>& center) {
  constexpr double none = std::numeric_limits<double>::infinity();
  if (S.periodicU() == S.periodicV()) return none;  // closed in exactly one direction
  const bool aroundU = S.periodicU();
  auto split = [&](const double* x, double perp[3], double& z) {
    z = 0.0;
    for (int d = 0; d < 3; ++d) z += (x[d] - center[d]) * axis[d];
    for (int d = 0; d < 3; ++d) perp[d] = x[d] - center[d] - z * axis[d];
  };
  const int nAround = aroundU ? S.nu() : S.nv(), nAlong = aroundU ? S.nv() : S.nu();
  double scale = 0.0;
  std::vector<double> rowZ(static_cast<std::size_t>(nAlong));
  for (int j = 0; j < nAlong; ++j)
    for (int i = 0; i < nAround; ++i) {
      const auto g = aroundU ? S.gridPoint(i, j) : S.gridPoint(j, i);
      double perp[3], z;
      split(g.data(), perp, z);
      scale = std::max({scale, std::sqrt(perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2]), std::abs(z)});
      if (i == 0)
        rowZ[j] = z;
      else if (std::abs(z - rowZ[j]) > 1e-12 * scale)
        return none;  // a row around is not at one z
    }
  {  // once around, not twice: the grid's angles along the first row sum to one turn
    double turned = 0.0;
    for (int i = 0; i < nAround; ++i) {
      const auto g0 = aroundU ? S.gridPoint(i, 0) : S.gridPoint(0, i);
      const auto g1 = aroundU ? S.gridPoint((i + 1) % nAround, 0) : S.gridPoint(0, (i + 1) % nAround);
      double p0[3], p1[3], z0, z1;
      split(g0.data(), p0, z0);
      split(g1.data(), p1, z1);
      const double cross = (p0[1] * p1[2] - p0[2] * p1[1]) * axis[0] + (p0[2] * p1[0] - p0[0] * p1[2]) * axis[1] +
                           (p0[0] * p1[1] - p0[1] * p1[0]) * axis[2];
      turned += std::atan2(cross, p0[0] * p1[0] + p0[1] * p1[1] + p0[2] * p1[2]);
    }
    if (std::abs(std::abs(turned) - 2 * M_PI) > 1e-6) return none;
  }
  const HostSurfaceView h = S.hostView();
  constexpr int k = 16;
  double rate = 0.0;
  int turnSign = 0, alongSign = 0;
  const int aroundSamples = k * nAround, alongSamples = k * (nAlong - 1);  // the open direction: both ends
  for (int a = 0; a < aroundSamples; ++a)
    for (int b = 0; b <= alongSamples; ++b) {
      const double around = double(a) / k, along = double(b) / k;
      double x[3], xu[3], xv[3], xuu[3], xuv[3], xvv[3], perp[3], z;
      evaluate(h, aroundU ? around : along, aroundU ? along : around, x, xu, xv, xuu, xuv, xvv);
      const double* t = aroundU ? xu : xv;
      const double* w = aroundU ? xv : xu;
      split(x, perp, z);
      const double rho = std::sqrt(perp[0] * perp[0] + perp[1] * perp[1] + perp[2] * perp[2]);
      const double radial = perp[0] * t[0] + perp[1] * t[1] + perp[2] * t[2];
      const double turn = (perp[1] * t[2] - perp[2] * t[1]) * axis[0] + (perp[2] * t[0] - perp[0] * t[2]) * axis[1] +
                          (perp[0] * t[1] - perp[1] * t[0]) * axis[2];
      const double axial = w[0] * axis[0] + w[1] * axis[1] + w[2] * axis[2];
      const int ts = turn > 0 ? 1 : turn < 0 ? -1 : 0, as = axial > 0 ? 1 : axial < 0 ? -1 : 0;
      if (ts == 0 || as == 0 || (turnSign != 0 && ts != turnSign) || (alongSign != 0 && as != alongSign)) return none;
      turnSign = ts;
      alongSign = as;
      rate = std::max(rate, rho * std::abs(radial) / std::abs(turn));
    }
  return 1.5 * rate + 1e-12 * scale;
}

static_assert(parallel_detail::kHostAccessible,
              "contact detection fills its per-surface data on the host: it needs a host-accessible memory space");

ContactDetection::ContactDetection(const std::vector<int>& dofs, const std::vector<double>& X,
                                   std::vector<ContactSurface> surfaces, const DetectionOptions& options,
                                   const std::vector<int>& blocks)
    : opt_(options), surfaces_(std::move(surfaces)) {
  const int nc = static_cast<int>(dofs.size() / 3);
  const int ns = static_cast<int>(surfaces_.size());
  EPAPHE_REQUIRE(
      nc > 0 && dofs.size() == 3 * std::size_t(nc) && X.size() == dofs.size(),
      "contact: " << dofs.size() << " node DOFs and " << X.size() << " coordinates; give 3 of each per node");
  EPAPHE_REQUIRE(ns > 0, "contact: no surface to contact");
  EPAPHE_REQUIRE(opt_.nrTolerance > 0.0 && opt_.nrMaxIterations > 0,
                 "contact: Newton tolerance " << opt_.nrTolerance << " and " << opt_.nrMaxIterations
                                              << " iterations; both must be > 0");
  DetectionViews& v = v_;
  v.dof = Kokkos::View<int* [3]>("epaphe::contact::dof", nc);
  v.X = DetectionViews::Vec3("epaphe::contact::X", nc);
  v.x = DetectionViews::Vec3("epaphe::contact::x", nc);
  for (int k = 0; k < nc; ++k)
    for (int d = 0; d < 3; ++d) {
      v.dof(k, d) = dofs[3 * k + d];
      v.X(k, d) = X[3 * k + d];
    }
  v.surf = Kokkos::View<SurfaceView*>("epaphe::contact::surfaces", ns);
  v.rot = Kokkos::View<double* [3][3]>("epaphe::contact::rotation", ns);
  v.turn = Kokkos::View<double* [9]>("epaphe::contact::turning", ns);
  EPAPHE_REQUIRE(blocks.empty() || blocks.size() == std::size_t(nc),
                 "contact: " << blocks.size() << " node blocks for " << nc << " nodes; give 1 per node");
  v.block = Kokkos::View<int*>("epaphe::contact::block", nc);
  for (int k = 0; k < nc; ++k) v.block(k) = blocks.empty() ? 0 : blocks[k];
  v.onlyBlock = Kokkos::View<int*>("epaphe::contact::only_block", ns);
  for (int s = 0; s < ns; ++s) v.onlyBlock(s) = surfaces_[s].onlyBlock;
  surfacesOf_.assign(nc, 0);
  for (int k = 0; k < nc; ++k)
    for (int s = 0; s < ns; ++s) surfacesOf_[k] += surfaces_[s].onlyBlock < 0 || surfaces_[s].onlyBlock == v.block(k);
  for (const int m : surfacesOf_) projectionsUnskipped_ += m;
  for (int s = 0; s < ns; ++s) {
    ContactSurface& cs = surfaces_[s];
    if (cs.moving) cs.surface = cs.moving;
    EPAPHE_REQUIRE(cs.surface, "contact: surface " << s << " is null");
    EPAPHE_REQUIRE(std::isfinite(cs.omega), "contact: surface '" << cs.surface->name() << "' turns at " << cs.omega
                                                                 << " rad/s; give a finite speed");
    EPAPHE_REQUIRE(std::isfinite(cs.phase), "contact: surface '" << cs.surface->name() << "' has the initial angle "
                                                                 << cs.phase << " rad; give a finite angle");
    const double l = std::sqrt(cs.axis[0] * cs.axis[0] + cs.axis[1] * cs.axis[1] + cs.axis[2] * cs.axis[2]);
    EPAPHE_REQUIRE(l > 0.0, "contact: surface '" << cs.surface->name() << "' has a zero rotation axis");
    for (double& a : cs.axis) a /= l;
    v.surf(s) = cs.surface->view();
    anyCarried_ = anyCarried_ || cs.moving;
    v.turn(s, 0) = cs.law.ramp ? cs.law.fastest() : cs.omega;  // the skipping's bound of the turn rate
    for (int d = 0; d < 3; ++d) {
      v.turn(s, 1 + d) = cs.axis[d];
      v.turn(s, 4 + d) = cs.center[d];
    }
    // r_s: the largest distance of a control point from the axis (the spline lies in their hull)
    double r = 0.0;
    const HostSurfaceView h = cs.surface->hostView();
    for (std::size_t i = 0; i < h.ctrl.extent(0); ++i)
      for (std::size_t j = 0; j < h.ctrl.extent(1); ++j) {
        double p[3], pa = 0.0;
        for (int d = 0; d < 3; ++d) {
          p[d] = h.ctrl(i, j, d) - cs.center[d];
          pa += p[d] * cs.axis[d];
        }
        double rr = 0.0;
        for (int d = 0; d < 3; ++d) rr += (p[d] - pa * cs.axis[d]) * (p[d] - pa * cs.axis[d]);
        r = std::max(r, std::sqrt(rr));
      }
    // a rigid turning surface that is a radial graph about its axis moves by far less (radialTurnRate)
    if (!cs.moving && (cs.omega != 0.0 || cs.law.ramp || cs.phase != 0.0))
      r = std::min(r, radialTurnRate(*cs.surface, cs.axis, cs.center));
    v.turn(s, 7) = r;
    // patch size: the shortest edge between neighbouring grid nodes
    const BSplineSurface& G = *cs.surface;
    for (int i = 0; i < G.nu(); ++i)
      for (int j = 0; j < G.nv(); ++j) {
        const auto p = G.gridPoint(i, j);
        for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
          if ((i + di >= G.nu() && !G.periodicU()) || (j + dj >= G.nv() && !G.periodicV())) continue;
          const auto n = G.gridPoint((i + di) % G.nu(), (j + dj) % G.nv());
          const double edge =
              std::sqrt((n[0] - p[0]) * (n[0] - p[0]) + (n[1] - p[1]) * (n[1] - p[1]) + (n[2] - p[2]) * (n[2] - p[2]));
          if (edge > 0.0 && edge < smallestPatch_) {
            smallestPatch_ = edge;
            smallestPatchSurface_ = s;
          }
        }
      }
    v.turn(s, 8) = cs.omega != 0.0 || cs.law.ramp || cs.phase != 0.0 ? 1.0 : 0.0;
    gridX_.emplace_back();
    gridPos_.emplace_back();
    gridDof_.emplace_back();
    gridPosH_.emplace_back();
    if (!cs.moving) continue;
    const BSplineSurface& S = *cs.surface;
    const std::size_t ng = std::size_t(S.inputNu()) * S.inputNv();
    EPAPHE_REQUIRE(cs.gridDofs.size() == 3 * ng && cs.gridX.size() == 3 * ng,
                   "contact: surface '" << S.name() << "' has " << ng << " grid nodes but " << cs.gridDofs.size() / 3
                                        << " grid DOF triples and " << cs.gridX.size() / 3 << " positions");
    gridX_.back() = Kokkos::View<double* [3]>("epaphe::contact::grid_X", ng);
    gridPos_.back() = Kokkos::View<double* [3]>("epaphe::contact::grid_x", ng);
    gridDof_.back() = Kokkos::View<int* [3]>("epaphe::contact::grid_dof", ng);
    gridPosH_.back() = Kokkos::create_mirror_view(gridPos_.back());
    for (std::size_t g = 0; g < ng; ++g)
      for (int d = 0; d < 3; ++d) {
        gridX_.back()(g, d) = cs.gridX[3 * g + d];
        gridDof_.back()(g, d) = cs.gridDofs[3 * g + d];
      }
  }
  v.uv = Kokkos::View<double** [2]>("epaphe::contact::uv", nc, ns);
  Kokkos::deep_copy(v.uv, std::nan(""));  // cold start from the nearest grid node
  v.uvRate = Kokkos::View<double** [2]>("epaphe::contact::uv_rate", nc, ns);
  v.found = Kokkos::View<Projection**>("epaphe::contact::found", nc, ns);
  v.gap = Kokkos::View<double*>("epaphe::contact::gap", nc);
  v.selected = Kokkos::View<int*>("epaphe::contact::surface", nc);
  v.normal = DetectionViews::Vec3("epaphe::contact::normal", nc);
  v.foot = Kokkos::View<double* [2]>("epaphe::contact::foot", nc);
  v.footX = DetectionViews::Vec3("epaphe::contact::foot_point", nc);
  v.iterations = Kokkos::View<int*>("epaphe::contact::iterations", nc);
  v.skip.xLast = DetectionViews::Vec3("epaphe::contact::x_last", nc);
  v.skip.tLast = Kokkos::View<double*>("epaphe::contact::t_last", nc);
  v.skip.gLast = Kokkos::View<double*>("epaphe::contact::g_last", nc);
  v.skip.eligible = Kokkos::View<int*>("epaphe::contact::eligible", nc);
  v.skip.skipped = Kokkos::View<int*>("epaphe::contact::skipped", nc);
  v.skip.refine = Kokkos::View<int*>("epaphe::contact::refine", nc);
  v.skip.bound = Kokkos::View<double*>("epaphe::contact::gap_bound", nc);
  v.skip.travel = Kokkos::View<double*>("epaphe::contact::surface_travel", ns);
  v.skip.travelLast = Kokkos::View<double**>("epaphe::contact::surface_travel_last", nc, ns);
  v.skip.correctionMove = Kokkos::View<double*>("epaphe::contact::correction_move", nc);
  ctrlLast_.resize(static_cast<std::size_t>(ns));
  v.offset = Kokkos::View<double*>("epaphe::contact::penetration_offset", nc);
  v.offsetSurf = Kokkos::View<int*>("epaphe::contact::penetration_surface", nc);
  Kokkos::deep_copy(v.offsetSurf, -1);
  std::vector<const BSplineSurface*> coated;
  std::vector<CoatingMaterial> materials;
  for (const ContactSurface& cs : surfaces_) {
    EPAPHE_REQUIRE(cs.coating.elements[0] == 0 || !cs.moving,
                   "contact: surface '" << cs.surface->name()
                                        << "' is carried by a flexible body and has a coating; a "
                                           "coating is supported on rigid surfaces only (a rigid casing behind it)");
    coated.push_back(cs.surface);
    materials.push_back(cs.coating);
  }
  v.coat = makeCoatingViews(coated, materials);
  v.element = Kokkos::View<int*>("epaphe::contact::coating_element", nc);
  Kokkos::deep_copy(v.element, -1);
  u_ = v_.untracked();
}

void ContactDetection::setPenetrationOffsets(const std::vector<double>& depth, double rampEnd) {
  EPAPHE_REQUIRE(depth.size() == std::size_t(numNodes()),
                 "contact: " << depth.size() << " penetration depths for " << numNodes() << " nodes");
  EPAPHE_REQUIRE(std::isfinite(rampEnd) && rampEnd > 0.0,
                 "contact: the initial penetrations' ramp ends at " << rampEnd << " s; it must be a finite time > 0");
  fence();
  for (int k = 0; k < numNodes(); ++k) {
    EPAPHE_REQUIRE(std::isfinite(depth[k]) && depth[k] >= 0.0,
                   "contact: penetration depth " << depth[k] << " of node " << k << "; give a finite value >= 0");
    v_.offset(k) = depth[k];
    v_.offsetSurf(k) = depth[k] > 0.0 ? v_.selected(k) : -1;
  }
  rampEnd_ = rampEnd;
  reset();
}

Teuchos::RCP<const Teuchos::ParameterList> ContactDetection::getValidParameters() {
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Detection"));
  deck::addDouble(*pl, "Newton tolerance", 1e-8,
                  "crit_NR: closest-point Newton stops when the parameter step is "
                  "below it",
                  1e-300, 1.0);
  deck::addInt(*pl, "Newton max iterations", 50, "Closest-point Newton iterations at most", 1, 10000);
  deck::addDouble(*pl, "Edge tolerance", 1e-3,
                  "A node beyond the edge of an open surface by less than this "
                  "fraction of a patch still touches it (nodes on a shared edge, "
                  "lateral round-off); farther, it is beyond the surface",
                  0.0, 1.0);
  deck::addBool(*pl, "Skip distant nodes", true,
                "Skip the Newton projection of a node whose last gap exceeds "
                "how far it and the surfaces can have moved since, with room for "
                "twice the last correction's move of it (results "
                "unchanged to round-off; output steps project every node); false "
                "projects every node at every step");
  deck::addBool(*pl, "Allow large motion per step", false,
                "A contact node that moves farther in one time step than the smallest patch of the surfaces (the "
                "shortest distance between neighbouring grid nodes) can cross an open surface between two "
                "detections and never be seen in contact (tunnelling); such an initial velocity is refused and such "
                "a step stops the run, unless true (then a warning, counted in the summary)");
  deck::addEnum(*pl, "Initial penetration", "Refuse", {"Refuse", "Resolve gently"},
                {int(InitialPenetration::Refuse), int(InitialPenetration::ResolveGently)},
                "Contact nodes inside a surface at t = 0 (deeper than 1e-6 of the smallest patch). Refuse: the run "
                "stops at setup with the count, the deepest node and where; Resolve gently: each such node's gap is "
                "raised by its initial depth, ramped down to zero over 'Penetration ramp time', so the bodies are "
                "pushed apart over the ramp instead of in one step");
  deck::addDouble(*pl, "Penetration ramp time", 0.0,
                  "With 'Initial penetration' = 'Resolve gently': the time (s) over which initial penetrations are "
                  "pushed out; 0: 100 time steps",
                  0.0, deck::inf);
  return pl;
}

GuardOptions guardOptions(const Teuchos::ParameterList& cp) {
  GuardOptions o;
  o.allowLargeMotion = cp.get<bool>("Allow large motion per step");
  o.initialPenetration = deck::getEnum<InitialPenetration>(cp, "Initial penetration");
  o.rampTime = cp.get<double>("Penetration ramp time");
  return o;
}

DetectionOptions detectionOptions(const Teuchos::ParameterList& cp) {
  DetectionOptions o;
  o.nrTolerance = cp.get<double>("Newton tolerance");
  o.nrMaxIterations = cp.get<int>("Newton max iterations");
  o.edgeTolerance = cp.get<double>("Edge tolerance");
  o.skipDistant = cp.get<bool>("Skip distant nodes");
  return o;
}

void ContactDetection::reset() {
  Kokkos::deep_copy(v_.skip.eligible, 0);
  Kokkos::deep_copy(v_.skip.travel, 0.0);  // every node projects next: the motion so far no longer matters
  Kokkos::deep_copy(v_.skip.correctionMove, 0.0);
  Kokkos::deep_copy(v_.uvRate, 0.0);
  for (auto& c : ctrlLast_) c.clear();
}

std::vector<double> ContactDetection::skipState() const {
  fence();
  const int nc = numNodes(), ns = numSurfaces();
  std::vector<double> st;
  for (int k = 0; k < nc; ++k) {
    st.push_back(v_.skip.eligible(k));
    for (int d = 0; d < 3; ++d) st.push_back(v_.skip.xLast(k, d));
    st.push_back(v_.skip.tLast(k));
    st.push_back(v_.skip.gLast(k));
    st.push_back(v_.skip.correctionMove(k));
    for (int s = 0; s < ns; ++s) st.push_back(v_.skip.travelLast(k, s));
    for (int s = 0; s < ns; ++s)
      for (int c = 0; c < 2; ++c) st.push_back(v_.uvRate(k, s, c));
  }
  for (int s = 0; s < ns; ++s) st.push_back(v_.skip.travel(s));
  for (const auto& c : ctrlLast_) {
    st.push_back(static_cast<double>(c.size()));
    st.insert(st.end(), c.begin(), c.end());
  }
  return st;
}

void ContactDetection::setSkipState(const std::vector<double>& st) {
  fence();
  const int nc = numNodes(), ns = numSurfaces();
  std::size_t i = 0;
  auto next = [&]() {
    EPAPHE_REQUIRE(i < st.size(),
                   "contact: the checkpoint's detection state has " << st.size() << " values, too few for this scene");
    return st[i++];
  };
  for (int k = 0; k < nc; ++k) {
    v_.skip.eligible(k) = static_cast<int>(next());
    for (int d = 0; d < 3; ++d) v_.skip.xLast(k, d) = next();
    v_.skip.tLast(k) = next();
    v_.skip.gLast(k) = next();
    v_.skip.correctionMove(k) = next();
    for (int s = 0; s < ns; ++s) v_.skip.travelLast(k, s) = next();
    for (int s = 0; s < ns; ++s)
      for (int c = 0; c < 2; ++c) v_.uvRate(k, s, c) = next();
  }
  for (int s = 0; s < ns; ++s) v_.skip.travel(s) = next();
  for (auto& c : ctrlLast_) {
    c.resize(static_cast<std::size_t>(next()));
    for (double& x : c) x = next();
  }
  EPAPHE_REQUIRE(i == st.size(), "contact: the checkpoint's detection state has " << st.size() << " values, " << i
                                                                                  << " expected for this scene");
}

std::vector<double> ContactDetection::warmStarts() const {
  const std::size_t nc = static_cast<std::size_t>(numNodes()), ns = surfaces_.size();
  std::vector<double> all(2 * nc * ns);
  fence();
  for (std::size_t s = 0; s < ns; ++s)
    for (std::size_t k = 0; k < nc; ++k)
      for (int c = 0; c < 2; ++c) all[2 * (s * nc + k) + c] = v_.uv(k, s, c);
  return all;
}

void ContactDetection::setWarmStarts(const std::vector<double>& all) {
  const std::size_t nc = static_cast<std::size_t>(numNodes()), ns = surfaces_.size();
  EPAPHE_REQUIRE(all.size() == 2 * nc * ns, "contact: " << all.size() << " warm-start parameters given, " << 2 * nc * ns
                                                        << " expected (2 per node, " << nc << " nodes, " << ns
                                                        << " surfaces)");
  fence();
  for (std::size_t s = 0; s < ns; ++s)
    for (std::size_t k = 0; k < nc; ++k)
      for (int c = 0; c < 2; ++c) v_.uv(k, s, c) = all[2 * (s * nc + k) + c];
  reset();
}

void ContactDetection::rebuildCarried(const DenseVector& q) {
  // Surfaces carried by a body: rebuilt from their moved grid nodes (operators reused, eq. 2.26).
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    if (!surfaces_[s].moving) continue;
    // a copy of a surface already rebuilt (the instances of a stage share one carried surface)
    std::size_t first = 0;
    while (surfaces_[first].moving != surfaces_[s].moving) ++first;
    if (first < s) {
      v_.surf(s) = v_.surf(first);
      v_.skip.travel(s) = v_.skip.travel(first);
      v_.turn(s, 7) = v_.turn(first, 7);
      continue;
    }
    const auto gX = gridX_[s];
    const auto gx = gridPos_[s];
    const auto gdof = gridDof_[s];
    forEach(
        "epaphe::contact::surface_nodes", gx.extent(0), 5, KOKKOS_LAMBDA(const int g) {
          for (int d = 0; d < 3; ++d) gx(g, d) = gX(g, d) + (gdof(g, d) >= 0 ? q(gdof(g, d)) : 0.0);
        });
    Kokkos::deep_copy(gridPosH_[s], gx);
    // (ng x 3, LayoutRight: the layout update() reads). Without the broad phase's bucket grid: a
    // cold start on it (the first detection, a restart's nodes never projected) takes the brute
    // force, the same nearest node, where rebuilding the grid cost about 9 us at every step of
    // stage-flexible-casing
    surfaces_[s].moving->update(gridPosH_[s].data(), false);
    v_.surf(s) = surfaces_[s].moving->view();
    // The skipping's bounds (top of Epaphe_ContactDetection.hpp): T_s += max |dP|, r_s now.
    const HostSurfaceView h = surfaces_[s].moving->hostView();
    const std::size_t n = h.ctrl.extent(0) * h.ctrl.extent(1);
    std::vector<double>& last = ctrlLast_[s];
    const ContactSurface& cs = surfaces_[s];
    double step = 0.0, r = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double* P = h.ctrl.data() + 3 * i;
      if (last.size() == 3 * n) {
        const double* L = last.data() + 3 * i;
        step = std::max(step, std::sqrt((P[0] - L[0]) * (P[0] - L[0]) + (P[1] - L[1]) * (P[1] - L[1]) +
                                        (P[2] - L[2]) * (P[2] - L[2])));
      }
      double p[3], pa = 0.0;
      for (int d = 0; d < 3; ++d) {
        p[d] = P[d] - cs.center[d];
        pa += p[d] * cs.axis[d];
      }
      double rr = 0.0;
      for (int d = 0; d < 3; ++d) rr += (p[d] - pa * cs.axis[d]) * (p[d] - pa * cs.axis[d]);
      r = std::max(r, std::sqrt(rr));
    }
    last.assign(h.ctrl.data(), h.ctrl.data() + 3 * n);
    v_.skip.travel(s) += step;
    v_.turn(s, 7) = r;
  }
}

void ContactDetection::setReferencePositions(const std::vector<double>& X) {
  EPAPHE_REQUIRE(X.size() == 3 * std::size_t(numNodes()),
                 "contact: " << X.size() / 3 << " reference positions for " << numNodes() << " nodes");
  fence();
  for (int k = 0; k < numNodes(); ++k)
    for (int d = 0; d < 3; ++d) v_.X(k, d) = X[3 * k + d];
}

void ContactDetection::detect(const DenseVector& q, double t, bool all) {
  fence();
  time_ = t;
  q_ = q;
  if (anyCarried_) rebuildCarried(q);
  // Turning surfaces: R(omega t + phase) by Rodrigues' formula.
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    const ContactSurface& cs = surfaces_[s];
    const double th = (cs.law.ramp ? cs.law.angle(t) : cs.omega * t) + cs.phase, c = std::cos(th), sn = std::sin(th);
    const auto& a = cs.axis;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double cross = (i == j) ? 0.0 : ((j == (i + 1) % 3) ? -a[3 - i - j] : a[3 - i - j]);
        v_.rot(s, i, j) = (i == j ? c : 0.0) + (1 - c) * a[i] * a[j] + sn * cross;
      }
  }
  project(all, false);
}

int ContactDetection::refine() {
  fence();
  int n = 0;
  for (int k = 0; k < numNodes(); ++k) n += v_.skip.refine(k) != 0;
  if (n > 0) project(true, true);
  return n;
}

DetectionViews DetectionViews::untracked() const {
  DetectionViews u;
  u.dof = unmanaged(dof);
  u.X = unmanaged(X);
  u.x = unmanaged(x);
  u.surf = unmanaged(surf);
  u.rot = unmanaged(rot);
  u.turn = unmanaged(turn);
  u.onlyBlock = unmanaged(onlyBlock);
  u.block = unmanaged(block);
  u.uv = unmanaged(uv);
  u.uvRate = unmanaged(uvRate);
  u.found = unmanaged(found);
  u.gap = unmanaged(gap);
  u.selected = unmanaged(selected);
  u.normal = unmanaged(normal);
  u.foot = unmanaged(foot);
  u.footX = unmanaged(footX);
  u.iterations = unmanaged(iterations);
  u.skip = SkipViews{unmanaged(skip.xLast),         unmanaged(skip.tLast),   unmanaged(skip.gLast),
                     unmanaged(skip.eligible),      unmanaged(skip.skipped), unmanaged(skip.refine),
                     unmanaged(skip.bound),         unmanaged(skip.travel),  unmanaged(skip.travelLast),
                     unmanaged(skip.correctionMove)};
  u.offset = unmanaged(offset);
  u.offsetSurf = unmanaged(offsetSurf);
  u.coat = CoatingViews{unmanaged(coat.law), unmanaged(coat.grid), unmanaged(coat.wear), unmanaged(coat.area),
                        unmanaged(coat.surface)};
  u.element = unmanaged(element);
  return u;
}

void ContactDetection::project(bool all, bool refineOnly) {
  // local copies of the views it owns, unmanaged (no reference counted); nothing allocated
  const DetectionViews& v = u_;
  const DenseVector q = unmanaged(q_);
  const int nc = numNodes(), ns = numSurfaces();
  const double tol = opt_.nrTolerance;
  const int maxIt = opt_.nrMaxIterations;
  const double edgeTol = opt_.edgeTolerance > opt_.nrTolerance ? opt_.edgeTolerance : opt_.nrTolerance;
  const bool skip = opt_.skipDistant && !all;
  const double t = time_;
  const double rampEnd = t < rampEnd_ ? rampEnd_ : 0.0;  // 0: no offsets any more
  // about 0.6 us per projection of a node on a surface on one thread (warm-started Newton on a
  // bicubic patch), 30 ns per skipped node; as many projections expected as at the last step
  const long long expected = skip && !refineOnly ? std::max(lastProjections_, 1LL) : projectionsUnskipped_;
  // The nodes in blocks of kDetectBlock: a block's projections (a node on a surface) are gathered
  // and made kProjectionLanes at a time, their Newton iterations interleaved (closestPoints(): each
  // projection's result depends on its own node alone, on any number of threads), then each node
  // picks its surface from its projections, in the surfaces' order.
  constexpr int kDetectBlock = 16, W = kProjectionLanes;
  const int blocks = (nc + kDetectBlock - 1) / kDetectBlock;
  forEach(
      "epaphe::contact::detect", blocks, kDetectBlock * (30L + static_cast<long>(600 * expected / nc)),
      KOKKOS_LAMBDA(const int blk) {
        const int k0 = blk * kDetectBlock, k1 = k0 + kDetectBlock < nc ? k0 + kDetectBlock : nc;
        bool todo[kDetectBlock];
        double lx[W][3], lu[W], lv[W];
        int lk[W], n = 0;
        Projection lp[W];
        auto flush = [&](int s) {  // the gathered projections on surface s
          closestPoints(v.surf(s), n, lx, lu, lv, tol, maxIt, lp);
          for (int l = 0; l < n; ++l) v.found(lk[l], s) = lp[l];
          n = 0;
        };
        for (int k = k0; k < k1; ++k) {
          todo[k - k0] = false;
          if (refineOnly && !v.skip.refine(k)) continue;
          double x[3];
          for (int d = 0; d < 3; ++d) x[d] = v.X(k, d) + q(v.dof(k, d));
          for (int d = 0; d < 3; ++d) v.x(k, d) = x[d];
          if (skip && v.skip.eligible(k)) {
            double dx = 0.0;
            for (int d = 0; d < 3; ++d) dx += (x[d] - v.skip.xLast(k, d)) * (x[d] - v.skip.xLast(k, d));
            double move = ::sqrt(dx);
            for (int s = 0; s < ns; ++s)
              if (v.onlyBlock(s) < 0 || v.onlyBlock(s) == v.block(k))
                move += ::fabs(v.turn(s, 0)) * (t - v.skip.tLast(k)) * v.turn(s, 7) +
                        (v.skip.travel(s) - v.skip.travelLast(k, s));
            // The distance to a surface is 1-Lipschitz in the node's position and moves by at most the
            // surface's own motion: the gap now is at least the last one less `move`, and the node cannot
            // have crossed the surface (a crossing needs a segment at least gLast long). A lower bound of
            // the gap, b > 0: out of contact for certain (b is kept for the add passes' refine test).
            // Skipped only with room for twice the last correction's move of the node: within b of
            // the surface, the correction would likely send it to refine(), a projection of its own.
            const double b = v.skip.gLast(k) - move;
            if (b > 2.0 * v.skip.correctionMove(k)) {
              v.skip.skipped(k) = 1;
              v.skip.bound(k) = b;
              v.iterations(k) = 0;
              continue;
            }
          }
          todo[k - k0] = true;
          v.skip.skipped(k) = 0;
          v.skip.refine(k) = 0;
        }
        for (int s = 0; s < ns; ++s) {       // by surface: a batch projects on one surface
          const SurfaceView& S = v.surf(s);  // a reference: a copy would copy its 4 views per node and surface
          for (int k = k0; k < k1; ++k) {
            if (!todo[k - k0] || (v.onlyBlock(s) >= 0 && v.onlyBlock(s) != v.block(k)))
              continue;  // (another instance's copy)
            double* xs = lx[n];
            for (int d = 0; d < 3; ++d) xs[d] = v.x(k, d);
            if (v.turn(s, 8) != 0.0) {
              // in the surface's frame: x_s = c + R^T (x - c)
              const double c0 = v.turn(s, 4), c1 = v.turn(s, 5), c2 = v.turn(s, 6);
              const double r[3] = {xs[0] - c0, xs[1] - c1, xs[2] - c2}, cc[3] = {c0, c1, c2};
              for (int i = 0; i < 3; ++i)
                xs[i] = cc[i] + v.rot(s, 0, i) * r[0] + v.rot(s, 1, i) * r[1] + v.rot(s, 2, i) * r[2];
            }
            const double uLast = v.uv(k, s, 0), vLast = v.uv(k, s, 1), dt = t - v.skip.tLast(k);
            double u0 = uLast, v0 = vLast;
            if (!(uLast == uLast && vLast == vLast)) {
              nearestGridPoint(S, xs, u0, v0);
            } else if (dt != 0.0) {
              // predicted: moved on by its last rate, if by less than a patch; or back, for an output
              // step's measurement at t_n after the step's detection at t_n+1 (dt = -h): the foot the
              // detection at t_n found, x having moved since only by the correction
              const double du = v.uvRate(k, s, 0) * dt, dv = v.uvRate(k, s, 1) * dt;
              if (::fabs(du) < 1.0 && ::fabs(dv) < 1.0) {
                u0 += du;
                v0 += dv;
              }
            }
            lu[n] = u0;
            lv[n] = v0;
            lk[n] = k;
            if (++n == W) flush(s);
          }
          if (n > 0) flush(s);
        }
        for (int k = k0; k < k1; ++k) {
          if (!todo[k - k0]) continue;
          int best = -1, its = 0, element = -1;
          double g = 1e300, gmin = 1e300;
          bool eligible = true;
          for (int s = 0; s < ns; ++s) {
            if (v.onlyBlock(s) >= 0 && v.onlyBlock(s) != v.block(k)) continue;
            const SurfaceView& S = v.surf(s);
            const Projection& p = v.found(k, s);
            const double uLast = v.uv(k, s, 0), vLast = v.uv(k, s, 1), dt = t - v.skip.tLast(k);
            if (uLast == uLast && vLast == vLast &&
                dt > 0.0) {  // a closed direction's parameter wraps: the shortest way round
              double du = p.u - uLast, dv = p.v - vLast;
              if (S.periodicU) du -= S.nu * ::floor(du / S.nu + 0.5);
              if (S.periodicV) dv -= S.nv * ::floor(dv / S.nv + 0.5);
              v.uvRate(k, s, 0) = du / dt;
              v.uvRate(k, s, 1) = dv / dt;
            }
            v.uv(k, s, 0) = p.u;
            v.uv(k, s, 1) = p.v;
            its = p.iterations > its ? p.iterations : its;
            eligible = eligible && p.converged && !(p.beyond > 0.0);
            v.skip.travelLast(k, s) = v.skip.travel(s);
            // through a coating: the gap to its current profile; the bound's to the unworn one
            const int e = v.coat.element(s, S, p.u, p.v, v.selected(k) == s ? v.element(k) : -1);
            const double pg = p.gap - v.coat.offset(s, e);
            const double gUnworn = e < 0 ? p.gap : p.gap - v.coat.law(s, 0);
            gmin = gUnworn < gmin ? gUnworn : gmin;
            if (!(p.beyond > edgeTol) && pg < g) {
              g = pg;
              best = s;
              element = e;
              for (int d = 0; d < 3; ++d) {  // back to the bodies' frame: n = R n_s, S = c + R (S_s - c)
                v.normal(k, d) =
                    v.rot(s, d, 0) * p.normal[0] + v.rot(s, d, 1) * p.normal[1] + v.rot(s, d, 2) * p.normal[2];
                double y = v.turn(s, 4 + d);
                for (int e = 0; e < 3; ++e) y += v.rot(s, d, e) * (p.point[e] - v.turn(s, 4 + e));
                v.footX(k, d) = y;
              }
              v.foot(k, 0) = p.u;
              v.foot(k, 1) = p.v;
            }
          }
          if (rampEnd > 0.0 && best >= 0 && best == v.offsetSurf(k)) {
            g += v.offset(k) * (1.0 - t / rampEnd);  // a gently resolved initial penetration
            eligible = false;
          }
          v.gap(k) = g;
          v.selected(k) = best;
          v.element(k) = element;
          v.iterations(k) = its;
          for (int d = 0; d < 3; ++d) v.skip.xLast(k, d) = v.x(k, d);
          v.skip.tLast(k) = t;
          v.skip.gLast(k) = gmin;
          v.skip.eligible(k) = eligible && gmin > 0.0 ? 1 : 0;
        }
      });
  fence();
  int projected = 0, iters = 0;
  long long projections = 0;
  for (int k = 0; k < nc; ++k) {
    projected += v.iterations(k) > 0;
    projections += v.iterations(k) > 0 ? surfacesOf_[k] : 0;
    iters = std::max(iters, v.iterations(k));
  }
  lastProjected_ = projected;  // after refine(): this step's projections so far
  lastProjections_ = projections;
  lastIterations_ = iters;
}

}  // namespace epaphe
