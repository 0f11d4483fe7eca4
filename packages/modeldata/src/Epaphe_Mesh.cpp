#include "Epaphe_Mesh.hpp"

#include "Epaphe_Error.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>
#include <sstream>

namespace epaphe {

namespace {

/// A structured block of n0 x n1 x n2 hexahedra: node (i, j, k) is i + (n0+1) (j + (n1+1) k), at
/// position(i, j, k); the face node sets are named faces[0..5] for i = 0, i = n0, j = 0, j = n1,
/// k = 0, k = n2, plus "all". (i, j, k) must be a right-handed frame of the mapped block. With
/// `closedJ` the block closes on itself along j (a full turn): j = n1 is j = 0, so there are n1
/// node layers along j (node (i, j, k) is i + (n0+1) (j mod n1 + n1 k)), no faces at j = 0 and
/// j = n1 (faces[2], faces[3] unused), and the grids of the faces along j repeat their first row.
template <class Position>
Mesh structuredMesh(const std::array<int, 3>& n, Position position, const std::array<const char*, 6>& faces,
                    bool closedJ = false) {
  const int p0 = n[0] + 1, p1 = closedJ ? n[1] : n[1] + 1, p2 = n[2] + 1;
  auto id = [&](int i, int j, int k) { return i + p0 * (j % p1 + p1 * k); };
  Mesh m;
  m.coords.resize(static_cast<std::size_t>(p0) * p1 * p2);
  auto& all = m.nodeSets["all"];
  for (int k = 0; k < p2; ++k)
    for (int j = 0; j < p1; ++j)
      for (int i = 0; i < p0; ++i) {
        const int node = id(i, j, k);
        m.coords[node] = position(i, j, k);
        all.push_back(node);
        const int on[6] = {i == 0, i == n[0], !closedJ && j == 0, !closedJ && j == n[1], k == 0, k == n[2]};
        for (int f = 0; f < 6; ++f)
          if (on[f]) m.nodeSets[faces[f]].push_back(node);
      }
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        m.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                           id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  // One ordered grid per face, S_u x S_v along the outward normal: for the face normal to axis a,
  // (b, c) the next two axes cyclically (e_b x e_c = e_a): u along b (descending on the face at
  // index 0 of axis a), v along c.
  for (int f = 0; f < 6; ++f) {
    if (closedJ && f / 2 == 1) continue;
    const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const bool upper = f % 2 == 1;
    NodeGrid g{n[b] + 1, n[c] + 1, {}};
    for (int ib = 0; ib <= n[b]; ++ib)
      for (int ic = 0; ic <= n[c]; ++ic) {
        std::array<int, 3> ijk{};
        ijk[a] = upper ? n[a] : 0;
        ijk[b] = upper ? ib : n[b] - ib;
        ijk[c] = ic;
        g.nodes.push_back(id(ijk[0], ijk[1], ijk[2]));
      }
    m.nodeGrids[faces[f]] = std::move(g);
  }
  return m;  // node sets are sorted: nodes were visited in increasing id order
}

}  // namespace

std::vector<int> resolveNodeSets(const std::map<std::string, std::vector<int>>& sets, const std::string& spec,
                                 const std::string& context) {
  std::set<int> nodes;
  std::stringstream ss(spec);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const auto b = name.find_first_not_of(" \t"), e = name.find_last_not_of(" \t");
    name = b == std::string::npos ? "" : name.substr(b, e - b + 1);
    auto it = sets.find(name);
    if (it == sets.end()) {
      ErrorBuilder eb;
      eb << context << ": unknown node set '" << name << "'; the model has:";
      for (const auto& [n, s] : sets) eb << " '" << n << "' (" << s.size() << " nodes)";
      eb.raise();
    }
    nodes.insert(it->second.begin(), it->second.end());
  }
  return std::vector<int>(nodes.begin(), nodes.end());
}

std::vector<int> Mesh::nodeSet(const std::string& spec, const std::string& context) const {
  return resolveNodeSets(nodeSets, spec, context);
}

Mesh makeBoxMesh(const std::array<double, 3>& origin, const std::array<double, 3>& lengths,
                 const std::array<int, 3>& elements) {
  for (int d = 0; d < 3; ++d) {
    EPAPHE_REQUIRE(lengths[d] > 0, "box mesh: length along "
                                       << "xyz"[d] << " is " << lengths[d] << ", it must be > 0");
    EPAPHE_REQUIRE(elements[d] >= 1, "box mesh: " << elements[d] << " elements along "
                                                  << "xyz"[d] << ", at least 1 is needed");
  }
  return structuredMesh(elements,
                        [&](int i, int j, int k) -> std::array<double, 3> {
                          return {origin[0] + lengths[0] * i / elements[0], origin[1] + lengths[1] * j / elements[1],
                                  origin[2] + lengths[2] * k / elements[2]};
                        },
                        {"x-", "x+", "y-", "y+", "z-", "z+"});
}

Mesh makeRingSegmentMesh(const std::array<double, 3>& center, double innerRadius, double thickness,
                         const std::array<double, 2>& angles, const std::array<double, 2>& axial,
                         const std::array<int, 3>& elements) {
  EPAPHE_REQUIRE(innerRadius > 0 && thickness > 0, "ring segment mesh: inner radius "
                                                       << innerRadius << " m and thickness " << thickness
                                                       << " m must both be > 0");
  EPAPHE_REQUIRE(angles[1] > angles[0] && angles[1] - angles[0] < 360.0,
                 "ring segment mesh: angles {" << angles[0] << ", " << angles[1]
                                               << "} degrees; give {first, last} with 0 < last - first < 360");
  EPAPHE_REQUIRE(axial[1] > axial[0], "ring segment mesh: axial range {" << axial[0] << ", " << axial[1]
                                                                         << "}; give {first, last} with last > first");
  for (int d = 0; d < 3; ++d)
    EPAPHE_REQUIRE(elements[d] >= 1, "ring segment mesh: " << elements[d] << " elements "
                                                           << (d == 0   ? "through the thickness"
                                                               : d == 1 ? "along the arc"
                                                                        : "along the axis")
                                                           << ", at least 1 is needed");
  const int nr = elements[0], nt = elements[1], nz = elements[2];
  // i radial, j angular, k axial: r x theta = z keeps every hexahedron right-handed.
  return structuredMesh(elements,
                        [&](int i, int j, int k) -> std::array<double, 3> {
                          const double r = innerRadius + thickness * i / nr;
                          const double a = (angles[0] + (angles[1] - angles[0]) * j / nt) * M_PI / 180.0;
                          return {center[0] + r * std::cos(a), center[1] + r * std::sin(a),
                                  center[2] + axial[0] + (axial[1] - axial[0]) * k / nz};
                        },
                        {"inner", "outer", "end-", "end+", "z-", "z+"});
}

Mesh makeSphereMesh(const std::array<double, 3>& center, double radius, const std::array<int, 3>& elements,
                    double poleGrading) {
  EPAPHE_REQUIRE(radius > 0, "sphere mesh: radius " << radius << " m; it must be > 0");
  EPAPHE_REQUIRE(poleGrading >= 0.02 && poleGrading <= 1,
                 "sphere mesh: pole grading " << poleGrading << "; give a ratio in [0.02, 1] (1: no grading)");
  for (int d = 0; d < 2; ++d)
    EPAPHE_REQUIRE(elements[d] >= 2 && elements[d] % 2 == 0,
                   "sphere mesh: " << elements[d] << " elements along "
                                   << "xy"[d] << "; give an even number >= 2 (the lower pole must be a node)");
  EPAPHE_REQUIRE(elements[2] >= 2, "sphere mesh: " << elements[2] << " elements along z; give at least 2");
  // H(u) = (exp(l u) - 1) / (exp(l) - 1), geometric spacing with H'(0) = l / (exp(l) - 1) = g:
  // l solved by bisection (g decreases with l); g = 1 is l = 0, H(u) = u
  double l = 0;
  if (poleGrading < 1) {
    double lo = 0, hi = 60;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (mid / std::expm1(mid) > poleGrading ? lo : hi) = mid;
    }
    l = 0.5 * (lo + hi);
  }
  auto H = [l](double u) { return l == 0 ? u : std::expm1(l * u) / std::expm1(l); };
  // cube coordinates of node i of n: along x and y graded towards 0 (the z axis), along z
  // towards -1 (the lower pole)
  auto across = [&](int i, int n) {
    if (2 * i == n) return 0.0;
    const double s = 2.0 * i / n - 1;
    return s < 0 ? -H(-s) : H(s);
  };
  auto along = [&](int k, int n) { return k == n ? 1.0 : -1 + 2 * H(double(k) / n); };
  Mesh m = structuredMesh(
      elements,
      [&](int i, int j, int k) -> std::array<double, 3> {
        const std::array<double, 3> c{across(i, elements[0]), across(j, elements[1]), along(k, elements[2])};
        const double r = std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])});
        if (r == 0) return center;
        const double x = c[0] / r, y = c[1] / r, z = c[2] / r;  // on the cube's surface
        const double x2 = x * x, y2 = y * y, z2 = z * z;
        // the smooth cube-to-sphere map (onto the unit sphere), scaled to the shell of radius r
        const double p[3] = {x * std::sqrt(std::max(0.0, 1 - y2 / 2 - z2 / 2 + y2 * z2 / 3)),
                             y * std::sqrt(std::max(0.0, 1 - z2 / 2 - x2 / 2 + z2 * x2 / 3)),
                             z * std::sqrt(std::max(0.0, 1 - x2 / 2 - y2 / 2 + x2 * y2 / 3))};
        return {center[0] + radius * r * p[0], center[1] + radius * r * p[1], center[2] + radius * r * p[2]};
      },
      {"x-", "x+", "y-", "y+", "z-", "z+"});
  m.nodeSets["z-pole"] = {elements[0] / 2 + (elements[0] + 1) * (elements[1] / 2)};
  return m;
}

Mesh makeBladeMesh(const BladeGeometry& g, const std::array<int, 3>& elements) {
  EPAPHE_REQUIRE(g.hubRadius > 0 && g.tipRadius > g.hubRadius, "blade mesh: hub radius "
                                                                   << g.hubRadius << " m and tip radius " << g.tipRadius
                                                                   << " m; 0 < hub < tip is needed");
  EPAPHE_REQUIRE(g.chord > 0 && g.thickness > 0,
                 "blade mesh: chord " << g.chord << " m and thickness " << g.thickness << " m must both be > 0");
  EPAPHE_REQUIRE(std::abs(g.coneAngle) < 60.0,
                 "blade mesh: cone angle " << g.coneAngle << " degrees; keep it within 60");
  for (int d = 0; d < 3; ++d)
    EPAPHE_REQUIRE(elements[d] >= 1, "blade mesh: " << elements[d] << " elements "
                                                    << (d == 0   ? "along the span"
                                                        : d == 1 ? "along the chord"
                                                                 : "through the thickness")
                                                    << ", at least 1 is needed");
  const double deg = M_PI / 180.0, tanCone = std::tan(g.coneAngle * deg);
  Mesh m = structuredMesh(
      elements,
      [&](int i, int j, int k) -> std::array<double, 3> {
        const double s = double(i) / elements[0], xi = (double(j) / elements[1] - 0.5) * g.chord;
        const double f = 0.5 + xi / g.chord;
        const double eta = (double(k) / elements[2] - 0.5) * g.thickness + 4.0 * g.camber * g.chord * f * (1.0 - f);
        const double beta = (g.stagger + s * g.twist) * deg;
        const double z = g.axialPosition + xi * std::cos(beta) - eta * std::sin(beta);
        const double t = xi * std::sin(beta) + eta * std::cos(beta);
        const double r = g.hubRadius + s * (g.tipRadius + (z - g.axialPosition) * tanCone - g.hubRadius);
        return {r * std::sin(t / r), r * std::cos(t / r), z};
      },
      {"root", "tip", "le", "te", "pressure", "suction"});
  for (const char* edge : {"le", "te"}) {
    std::vector<int> both;
    std::set_intersection(m.nodeSets["tip"].begin(), m.nodeSets["tip"].end(), m.nodeSets[edge].begin(),
                          m.nodeSets[edge].end(), std::back_inserter(both));
    m.nodeSets[std::string("tip-") + edge] = both;
  }
  return m;
}

double CasingGeometry::radiusAt(double theta, double z) const {
  const double w = (z - axialRange[0]) / (axialRange[1] - axialRange[0]);
  double gap = clearance;
  if (law == ClearanceLaw::TwoLobe) {
    const double m = std::fmod(theta, M_PI) / M_PI - 0.5;
    gap = clearance * (1.0 - 2.0 * std::exp(-(m / 0.15) * (m / 0.15)));
  } else if (law == ClearanceLaw::Harmonics) {
    for (std::size_t k = 0; k < orders.size(); ++k)
      gap -= ((1 - w) * amplitudesFirst[k] + w * amplitudesLast[k]) * std::cos(orders[k] * theta);
  }
  return radius + (z - axialPosition) * std::tan(coneAngle * M_PI / 180.0) + gap;
}

Mesh makeCasingMesh(const CasingGeometry& g, double thickness, const std::array<int, 3>& elements) {
  EPAPHE_REQUIRE(g.radius > 0 && thickness > 0,
                 "casing mesh: radius " << g.radius << " m and thickness " << thickness << " m must both be > 0");
  EPAPHE_REQUIRE(g.axialRange[1] > g.axialRange[0], "casing mesh: axial range {"
                                                        << g.axialRange[0] << ", " << g.axialRange[1]
                                                        << "}; give {first, last} with last > first");
  EPAPHE_REQUIRE(g.law != ClearanceLaw::Harmonics ||
                     (g.amplitudesFirst.size() == g.orders.size() && g.amplitudesLast.size() == g.orders.size()),
                 "casing mesh: " << g.orders.size() << " harmonic orders but " << g.amplitudesFirst.size() << " and "
                                 << g.amplitudesLast.size() << " amplitudes; give one amplitude per order at each end");
  EPAPHE_REQUIRE(elements[0] >= 1 && elements[1] >= 4 && elements[2] >= 1,
                 "casing mesh: elements {" << elements[0] << ", " << elements[1] << ", " << elements[2]
                                           << "}; at least 1 through the thickness, 4 around the circumference and 1 "
                                              "along the axis are needed");
  const int nr = elements[0], nt = elements[1], nz = elements[2];
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j < nt; ++j)
      EPAPHE_REQUIRE(g.radiusAt(2.0 * M_PI * j / nt, g.axialStation(k, nz + 1)) > 0,
                     "casing mesh: the inner radius at "
                         << 360.0 * j / nt << " degrees, z = " << g.axialStation(k, nz + 1) << " m is "
                         << g.radiusAt(2.0 * M_PI * j / nt, g.axialStation(k, nz + 1))
                         << " m; the cone and the clearance law must keep it > 0 "
                            "(raise the radius, or lower the clearance or the amplitudes)");
  // i radial, j around the axis, k axial: r x theta = z keeps every hexahedron right-handed.
  return structuredMesh(
      elements,
      [&](int i, int j, int k) -> std::array<double, 3> {
        const double th = 2.0 * M_PI * j / nt, z = g.axialStation(k, nz + 1);
        const double r = g.radiusAt(th, z) + thickness * i / nr;
        return {r * std::cos(th), r * std::sin(th), z};
      },
      {"inner", "outer", nullptr, nullptr, "front", "back"}, true);
}

}  // namespace epaphe
