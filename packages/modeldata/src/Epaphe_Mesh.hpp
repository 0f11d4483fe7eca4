#pragma once
// A volume mesh as Epaphe needs it: node coordinates, 8-node hexahedra, named node sets.
// Meshes imported from FE codes keep the code's node numbers (nodeIds) and show their other
// elements by their corner nodes as (possibly degenerate) hexahedra, for output only.
#include <array>
#include <map>
#include <string>
#include <vector>

namespace epaphe {

/// Nodes of a structured face in grid order: node (i, j) is nodes[i * nv + j]; the order a
/// B-spline surface is built from (i along u, j along v).
struct NodeGrid {
  /// Nodes along u and along v.
  ///@{
  int nu = 0, nv = 0;
  ///@}
  std::vector<int> nodes;  ///< nu x nv node indices, (i, j) at i * nv + j
};

/// A hexahedral mesh: node coordinates, 8-node elements, node sets and ordered faces.
struct Mesh {
  std::vector<std::array<double, 3>> coords;         ///< node coordinates (m)
  std::vector<std::array<int, 8>> hexes;             ///< node indices, VTK/Abaqus C3D8 order
  std::vector<int> nodeIds;                          ///< imported: node index -> the FE code's number; else empty
  std::map<std::string, std::vector<int>> nodeSets;  ///< sorted node indices
  std::map<std::string, NodeGrid> nodeGrids;         ///< ordered faces, for surfaces built on a body
  /// Imported (CalculiX) meshes: every element's nodes in CalculiX/Abaqus order, one per hexahedron
  /// of `hexes` and in its order; the node count tells the type: 4 (C3D4), 6 (C3D6), 8 (C3D8),
  /// 10 (C3D10), 15 (C3D15), 20 (C3D20), the corners first. Empty for built-in meshes (their
  /// elements are the hexahedra) and for imports that give no elements.
  std::vector<std::vector<int>> solids;

  /// The number of nodes.
  int numNodes() const { return static_cast<int>(coords.size()); }
  /// The number a user knows node `index` by: the FE code's number when imported, else the index.
  int nodeId(int index) const { return nodeIds.empty() ? index : nodeIds[static_cast<std::size_t>(index)]; }
  /// The named node set, or the union of several named "x-, x+, y-" (sorted, no repeats); an
  /// unknown name raises an error listing the known ones. `context` says who asked.
  std::vector<int> nodeSet(const std::string& spec, const std::string& context) const;
};

/// Resolves "name" or "name1, name2, ..." against `sets` (see Mesh::nodeSet).
std::vector<int> resolveNodeSets(const std::map<std::string, std::vector<int>>& sets, const std::string& spec,
                                 const std::string& context);

/// Structured box [x0, x0+lx] x [y0, y0+ly] x [z0, z0+lz] with nx x ny x nz hexahedra.
/// Node sets: "all", and the six faces "x-", "x+", "y-", "y+", "z-", "z+"; a node grid per face,
/// named as its set, with S_u x S_v along the outward normal (x+: u along y, v along z; y+: u
/// along z, v along x; z+: u along x, v along y; the "-" faces: u reversed).
Mesh makeBoxMesh(const std::array<double, 3>& origin, const std::array<double, 3>& lengths,
                 const std::array<int, 3>& elements);

/// A segment of a thick cylindrical ring about the z axis through `center`: radii
/// [innerRadius, innerRadius + thickness], angles [angles[0], angles[1]] (degrees, from +x towards
/// +y), z in [center.z + axial[0], center.z + axial[1]]; elements = {radial, angular, axial}.
/// Node sets: all, inner, outer (the two cylindrical faces), end- and end+ (the faces at the first
/// and last angle, where a ring is clamped), z- and z+. A node grid per face, named as its set,
/// with S_u x S_v along the outward normal: "outer", u along the angle and v along z (away from
/// the axis); "inner", u against the angle (towards the axis).
Mesh makeRingSegmentMesh(const std::array<double, 3>& center, double innerRadius, double thickness,
                         const std::array<double, 2>& angles, const std::array<double, 2>& axial,
                         const std::array<int, 3>& elements);

/// A solid ball of `radius` about `center`, made of one structured block: the cube [-1, 1]^3 of
/// elements = {nx, ny, nz} hexahedra (nx, ny even, so the lower pole is a node) mapped onto the
/// ball shell by shell. A cube point c lies on the cube surface of half-side r = max_d |c_d|; that
/// surface goes to the sphere of radius r by the smooth cube-to-sphere map
///   x' = x sqrt(1 - y^2/2 - z^2/2 + y^2 z^2/3), and cyclically, (x, y, z) = c / r,
/// so the position is center + radius r (x', y', z'): the faces of the cube become six caps, and no
/// element degenerates (the corner elements of the cube keep angles of 120 degrees at the surface).
/// `poleGrading` g in [0.02, 1] refines towards the lower pole (0, 0, -radius), where a ball lands
/// on a plane below it: before the map the cube coordinates are spaced geometrically, H(u) =
/// (exp(l u) - 1) / (exp(l) - 1) with H'(0) = l / (exp(l) - 1) = g: a = sign(s) H(|s|) along x and
/// y (s uniform in [-1, 1]; elements g times the uniform size at the z axis, g exp(l) times at the
/// surface) and c = -1 + 2 H((1 + s) / 2) along z (g times the uniform size at the lower pole,
/// g exp(l) times at the upper one). g = 1 is the uniform map; g = 0.15 (l = 3.06) makes the
/// elements at the lower pole 0.15 times, and those at the equator and the upper pole 3.2 times,
/// the uniform size.
/// Node sets: all, the caps x-, x+, y-, y+, z- (the lower cap), z+ (the faces of the mapped cube,
/// with their node grids, S_u x S_v pointing out of the ball, as makeBoxMesh's), and z-pole (the
/// lower pole's node).
Mesh makeSphereMesh(const std::array<double, 3>& center, double radius, const std::array<int, 3>& elements,
                    double poleGrading = 1.0);

/// A twisted, cambered blade (thesis chapter 5, a parametric stand-in for a compressor blade).
/// The engine axis is z; the blade stands along +y from the hub to the tip. Section at span
/// fraction s in [0, 1]: chord coordinate xi in [-chord/2, chord/2], thickness coordinate eta (plus
/// a parabolic camber line 4 camber chord (1/2 + xi/c)(1/2 - xi/c)), turned by the stagger angle
/// beta(s) = stagger + s twist about the radial direction: z = axialPosition + xi cos(beta) - eta
/// sin(beta), tangential arc t = xi sin(beta) + eta cos(beta); the radius runs from the hub to the
/// tip radius of a cone of half-angle coneAngle (r_tip(z) = tipRadius + (z - axialPosition)
/// tan(coneAngle)), and the point is wrapped on the cylinder of that radius: (r sin(t/r), r cos(t/r),
/// z), so every tip node is at the tip radius. Elements {span, chord, thickness}. Node sets: all,
/// root (clamped), tip, le and te (leading and trailing edges, smallest and largest xi), pressure
/// and suction, and tip-le, tip-te (the tip's edge nodes).
struct BladeGeometry {
  /// Radii of the hub (the root) and the tip (m).
  ///@{
  double hubRadius = 0.2, tipRadius = 0.3;
  ///@}
  /// Chord and thickness of the blade (m).
  ///@{
  double chord = 0.06, thickness = 0.004;
  ///@}
  ///@{
  double stagger = 30.0, twist = 20.0;  ///< degrees
  ///@}
  double camber = 0.05;        ///< of the chord
  double coneAngle = 0.0;      ///< degrees
  double axialPosition = 0.0;  ///< z of mid-chord (m)
};
/// The blade mesh of `geometry` with `elements` = {span, chord, thickness} elements (see BladeGeometry).
Mesh makeBladeMesh(const BladeGeometry& geometry, const std::array<int, 3>& elements);

/// How the inner radius of a casing varies around the circumference (thesis chapter 5).
enum class ClearanceLaw { None = 0, TwoLobe = 1, Harmonics = 2 };

/// A casing about the z axis: a cone of radius `radius` at z = axialPosition and half-angle
/// coneAngle, plus the clearance law gap(theta, z), theta from +x towards +y, z over axialRange:
///   None:       gap = clearance;
///   TwoLobe:    gap = c (1 - 2 exp(-((mod(theta, pi)/pi - 0.5)/0.15)^2)), c = clearance (NASA rotor
///               37, Piollet, Nyssen & Batailly 2019, eqs. 3-4): two lobes where the casing dips c
///               below the nominal cone;
///   Harmonics:  gap = clearance - sum_k A_k(z) cos(n_k theta), A_k linear in z from amplitudesFirst
///               (z = axialRange[0]) to amplitudesLast (z = axialRange[1]).
/// The rigid Casing surface and the casing mesh's inner face both follow radius(theta, z).
struct CasingGeometry {
  double radius = 0.3;         ///< m, of the cone at axialPosition
  double axialPosition = 0.0;  ///< m
  double coneAngle = 0.0;      ///< degrees
  /// z range of the casing (m); Harmonics: where amplitudesFirst and amplitudesLast apply.
  std::array<double, 2> axialRange{-0.03, 0.03};
  ClearanceLaw law = ClearanceLaw::None;  ///< how the clearance varies around the circumference
  double clearance = 0.0;                 ///< m
  std::vector<int> orders;                ///< Harmonics: n_k
  ///@{
  std::vector<double> amplitudesFirst, amplitudesLast;  ///< Harmonics: A_k at the two ends (m)
  ///@}

  /// z of station j of n equally spaced over the axial range (j = 0 .. n - 1).
  double axialStation(int j, int n) const { return axialRange[0] + (axialRange[1] - axialRange[0]) * j / (n - 1); }
  /// Cone plus clearance law at (theta, z), theta in radians.
  double radiusAt(double theta, double z) const;
};

/// A full 360-degree casing about the z axis (thesis chapter 5): a wall of `thickness` outside the
/// inner face of `geometry` (the clearance law shapes the whole wall), z over its axial range;
/// elements = {through the thickness, around the circumference (at least 4), along the axis}.
/// Closed around the axis: the seam's nodes are shared, not duplicated. Node sets: all, inner,
/// outer, front (z = first end of the axial range) and back (last end), where a casing is clamped.
/// A node grid per face, named as its set, with S_u x S_v along the outward normal: "inner", u
/// against the angle, v along z (towards the axis); "outer", u along the angle. The grids of the
/// inner and outer faces run once around and repeat their first row of nodes as the last, so that
/// a B-spline surface through them is closed (BSplineSurface detects the repeated row).
Mesh makeCasingMesh(const CasingGeometry& geometry, double thickness, const std::array<int, 3>& elements);

}  // namespace epaphe
