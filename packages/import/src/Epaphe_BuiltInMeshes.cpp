// The built-in meshes (Epaphe_BuiltInMeshes.hpp) as importers, registered under their deck names.
#include "Epaphe_BuiltInMeshes.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ModelImporter.hpp"

#include <sstream>

namespace epaphe {

using Teuchos::ParameterList;
using namespace deck;

namespace {

template <class T>
std::string listed(const std::vector<T>& v) {
  std::ostringstream os;
  os << "{";
  for (std::size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  return os.str() + "}";
}

/// Every built-in mesh's keys, each with its one documentation.
Teuchos::ParameterList allMeshKeys() {
  ParameterList mesh;
  addDoubleArray(mesh, "Origin", {0, 0, 0},
                 "Box: corner with the smallest coordinates; Ring segment: a point of "
                 "its axis (m)");
  addDoubleArray(mesh, "Lengths", {0.2, 0.02, 0.02}, "Box: edge lengths along x, y, z (m)");
  addIntArray(mesh, "Elements", {100, 1, 1},
              "Box: hexahedra along x, y, z; Ring segment: through the "
              "thickness, along the arc, along the axis; Casing: through the "
              "thickness, around the circumference, along the axis; Sphere: "
              "hexahedra along x, y, z of the mapped cube (x, y even)");
  addDouble(mesh, "Inner radius", 0.15,
            "Ring segment: inner radius; Casing: radius of the inner cone at the Axial "
            "position, before the clearance law (m)",
            1e-300);
  addDouble(mesh, "Thickness", 0.03, "Ring segment, Casing: radial thickness (m)", 1e-300);
  addDoubleArray(mesh, "Angles", {135, 225}, "Ring segment: first and last angle (degrees, from +x to +y)");
  addDoubleArray(mesh, "Axial range", {-0.05, 0.05},
                 "Ring segment: first and last z, from Origin; Casing: first "
                 "and last z (m)");
  addDoubleArray(mesh, "Center", {0, 0, 0}, "Sphere: centre of the ball (m)");
  addDouble(mesh, "Radius", 0.01, "Sphere: radius of the ball (m)", 1e-300);
  addDouble(mesh, "Pole grading", 1.0,
            "Sphere: element size at the lower pole (and across the z axis) as a "
            "fraction of the uniform size, in [0.02, 1]; 1: no grading. Geometric "
            "spacing: the elements grow away from the pole and the axis (to 3.2 "
            "times the uniform size for 0.15). Refines where a ball dropped along -z "
            "touches (Hertz contact radius sqrt(R delta))",
            0.02, 1.0);
  addDouble(mesh, "Hub radius", 0.2, "Blade: radius of the root (m)", 1e-300);
  addDouble(mesh, "Tip radius", 0.3, "Blade: radius of the tip at the Axial position (m)", 1e-300);
  addDouble(mesh, "Chord", 0.06, "Blade: chord length (m)", 1e-300);
  addDouble(mesh, "Blade thickness", 0.004, "Blade: thickness (m)", 1e-300);
  addDouble(mesh, "Stagger", 30.0, "Blade: angle of the root chord to the engine axis (degrees)");
  addDouble(mesh, "Twist", 20.0, "Blade: stagger added from root to tip (degrees)");
  addDouble(mesh, "Camber", 0.05, "Blade: height of the parabolic camber line, as a fraction of the chord");
  addDouble(mesh, "Cone angle", 0.0,
            "Blade: half-angle of the tip cone; Casing: of the inner cone (degrees; the "
            "radius grows by tan(angle) per metre along z)",
            -60.0, 60.0);
  addDouble(mesh, "Axial position", 0.0,
            "Blade: z of mid-chord; Casing: z where the inner cone's radius is the "
            "Inner radius (m)");
  addClearanceLaw(mesh, "Casing", "Inner radius");
  return mesh;
}

/// A built-in mesh: the keys it reads, its mesh; the full model assembled with the body's Material.
class BuiltInMesh : public ModelImporter {
public:
  BuiltInMesh(std::string name, std::vector<std::string> keys, std::string doc)
      : name_(std::move(name)), doc_(std::move(doc)), keys_(std::move(keys)) {}
  std::string name() const override { return name_; }
  std::string documentation() const override { return doc_; }
  Teuchos::RCP<const ParameterList> getValidParameters() const override {
    static const ParameterList all = allMeshKeys();
    auto pl = Teuchos::rcp(new ParameterList("Mesh"));
    for (const std::string& k : keys_) pl->setEntry(k, all.getEntry(k));
    return pl;
  }
  bool builtInMesh() const override { return true; }
  Mesh mesh(const ImportRequest& r) const override {
    const auto el = getInts(r.mesh(), "Elements");
    EPAPHE_REQUIRE(el.size() == 3, r.context()
                                       << ": 'Mesh->Elements' has " << el.size() << " values; give {nx, ny, nz}");
    return make(r, {el[0], el[1], el[2]});
  }
  FullModel build(const ImportRequest& r, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const override {
    Mesh m = mesh(r);
    const ParameterList& mp = r.bodyParams->sublist("Material");
    Material mat;
    mat.density = mp.get<double>("Density");
    mat.young = mp.get<double>("Young's modulus");
    mat.poisson = mp.get<double>("Poisson's ratio");
    if (mp.isParameter("Element formulation") && mp.get<std::string>("Element formulation") == "Incompatible modes")
      mat.formulation = HexFormulation::IncompatibleModes;
    std::vector<int> clamped;
    if (const std::string cs = r.bodyParams->get<std::string>("Clamped node set"); !cs.empty())
      clamped = m.nodeSet(cs, r.context() + ", 'Clamped node set'");
    return assembleHexModel(r.body, std::move(m), mat, clamped, comm);
  }

protected:
  virtual Mesh make(const ImportRequest& r, const std::array<int, 3>& el) const = 0;

private:
  std::string name_, doc_;
  std::vector<std::string> keys_;
};

class BoxMesh : public BuiltInMesh {
public:
  BoxMesh()
      : BuiltInMesh("Box", {"Origin", "Lengths", "Elements"},
                    "structured 8-node hexahedra, node sets all, x-, x+, y-, y+, z-, z+") {}
  void check(const ImportRequest& r) const override {
    const auto L = getVec3(r.mesh(), "Lengths", r.deckPath);
    for (int d = 0; d < 3; ++d)
      EPAPHE_REQUIRE(L[d] > 0, r.deckPath << ": '" << pathOf(r.mesh(), "Lengths") << "' = {" << L[0] << ", " << L[1]
                                          << ", " << L[2] << "}: the length along "
                                          << "xyz"[d] << " is " << L[d] << "; every edge length must be positive");
  }

protected:
  Mesh make(const ImportRequest& r, const std::array<int, 3>& el) const override {
    const ParameterList& mp = r.mesh();
    const auto origin = getVec3(mp, "Origin", r.deckPath), lengths = getVec3(mp, "Lengths", r.deckPath);
    try {
      return makeBoxMesh(origin, lengths, el);
    } catch (const Error& e) {
      throw Error(r.context() + ", Mesh Type Box ('" + pathOf(mp, "Elements") + "', 'Lengths'): " + e.what());
    }
  }
};

class RingSegmentMesh : public BuiltInMesh {
public:
  RingSegmentMesh()
      : BuiltInMesh("Ring segment", {"Origin", "Elements", "Inner radius", "Thickness", "Angles", "Axial range"},
                    "a thick cylindrical arc about the z axis through Origin, node sets all, inner, outer, end-, "
                    "end+, z-, z+") {}

protected:
  Mesh make(const ImportRequest& r, const std::array<int, 3>& el) const override {
    const ParameterList& mp = r.mesh();
    const auto ang = getDoubles(mp, "Angles"), ax = getDoubles(mp, "Axial range");
    EPAPHE_REQUIRE(ang.size() == 2 && ax.size() == 2, r.context() << ": 'Mesh->Angles' and 'Mesh->Axial range' "
                                                                     "must each be {first, last}");
    return makeRingSegmentMesh(getVec3(mp, "Origin", r.deckPath), mp.get<double>("Inner radius"),
                               mp.get<double>("Thickness"), {ang[0], ang[1]}, {ax[0], ax[1]}, el);
  }
};

class BladeMesh : public BuiltInMesh {
public:
  BladeMesh()
      : BuiltInMesh("Blade",
                    {"Elements", "Hub radius", "Tip radius", "Chord", "Blade thickness", "Stagger", "Twist", "Camber",
                     "Cone angle", "Axial position"},
                    "a twisted, cambered blade standing along +y about the engine axis z (Hub radius .. Tip radius, "
                    "Chord, Blade thickness, Stagger, Twist, Camber, Cone angle, Axial position; Elements {span, "
                    "chord, thickness}), node sets all, root, tip, le, te, pressure, suction, tip-le, tip-te; each "
                    "tip node at the tip radius of its cone") {}

protected:
  Mesh make(const ImportRequest& r, const std::array<int, 3>& el) const override {
    const ParameterList& mp = r.mesh();
    BladeGeometry g;
    g.hubRadius = mp.get<double>("Hub radius");
    g.tipRadius = mp.get<double>("Tip radius");
    g.chord = mp.get<double>("Chord");
    g.thickness = mp.get<double>("Blade thickness");
    g.stagger = mp.get<double>("Stagger");
    g.twist = mp.get<double>("Twist");
    g.camber = mp.get<double>("Camber");
    g.coneAngle = mp.get<double>("Cone angle");
    g.axialPosition = mp.get<double>("Axial position");
    return makeBladeMesh(g, el);
  }
};

class CasingMesh : public BuiltInMesh {
public:
  CasingMesh()
      : BuiltInMesh(
            "Casing",
            {"Elements", "Inner radius", "Thickness", "Axial range", "Cone angle", "Axial position", "Clearance law",
             "Clearance", "Harmonic orders", "Amplitudes at first end", "Amplitudes at last end"},
            "a full 360-degree casing about the z axis whose inner face follows the Clearance law of the "
            "rigid Casing surface (Inner radius at Axial position, Cone angle, Axial range in absolute z), a "
            "wall of Thickness outside it; Elements {through the thickness, around the circumference (at "
            "least 4), along the axis}; node sets all, inner, outer, front and back (the faces at the first "
            "and last z, where it is clamped); the node grids inner and outer are closed around the axis "
            "(their B-splines are periodic)") {}
  void check(const ImportRequest& r) const override { checkCasingMesh(r.body, r.mesh(), r.deckPath); }

protected:
  Mesh make(const ImportRequest& r, const std::array<int, 3>& el) const override {
    const ParameterList& mp = r.mesh();
    checkCasingMesh(r.body, mp, r.deckPath);
    try {
      return makeCasingMesh(casingGeometry(mp, "Inner radius", r.deckPath), mp.get<double>("Thickness"), el);
    } catch (const Error& e) {
      throw Error(r.context() + ", Mesh Type Casing: " + e.what());
    }
  }
};

class SphereMesh : public BuiltInMesh {
public:
  SphereMesh()
      : BuiltInMesh("Sphere", {"Center", "Radius", "Elements", "Pole grading"},
                    "a solid ball of Radius about Center, a cube of Elements {nx, ny, nz} (nx, ny even) mapped onto "
                    "it shell by shell (smooth cube-to-sphere map), optionally graded towards the lower pole (Pole "
                    "grading); node sets all, the six caps x-, x+, y-, y+, z- (the lower cap, around the pole (0, 0, "
                    "-Radius) from Center), z+ (each with its node grid, outward), and z-pole (the pole's node)") {}

protected:
  Mesh make(const ImportRequest& r, const std::array<int, 3>& el) const override {
    const ParameterList& mp = r.mesh();
    try {
      return makeSphereMesh(getVec3(mp, "Center", r.deckPath), mp.get<double>("Radius"), el,
                            mp.get<double>("Pole grading"));
    } catch (const Error& e) {
      throw Error(r.context() + ", Mesh Type Sphere ('" + pathOf(mp, "Elements") +
                  "', 'Radius', 'Pole grading'): " + e.what());
    }
  }
};

}  // namespace

void addClearanceLaw(Teuchos::ParameterList& pl, const std::string& who, const std::string& radiusKey) {
  addEnum(pl, "Clearance law", "None", {"None", "Two-lobe", "Harmonics"},
          {int(ClearanceLaw::None), int(ClearanceLaw::TwoLobe), int(ClearanceLaw::Harmonics)},
          who + ": radius = " + radiusKey +
              " + (z - Axial position) tan(Cone angle) + gap(theta, z), theta from +x towards "
              "+y. None: gap = Clearance; Two-lobe (NASA rotor 37, Piollet, Nyssen & Batailly 2019, eqs. 3-4): gap = "
              "c (1 - 2 exp(-((mod(theta, pi)/pi - 0.5)/0.15)^2)), c = Clearance; Harmonics: gap = Clearance - "
              "sum_k A_k(z) cos(n_k theta), A_k linear in z between its values at the two ends of the Axial range");
  addDouble(pl, "Clearance", 0.0, who + ": c of the clearance law (m)");
  addIntArray(pl, "Harmonic orders", {}, who + ", Harmonics: the orders n_k");
  addDoubleArray(pl, "Amplitudes at first end", {}, who + ", Harmonics: A_k at the first end of the Axial range (m)");
  addDoubleArray(pl, "Amplitudes at last end", {}, who + ", Harmonics: A_k at the last end of the Axial range (m)");
}

std::vector<std::string> builtInMeshKeys() {
  const ParameterList all = allMeshKeys();
  std::vector<std::string> keys;
  for (auto it = all.begin(); it != all.end(); ++it) keys.push_back(all.name(it));
  return keys;
}

CasingGeometry casingGeometry(const ParameterList& pl, const std::string& radiusKey, const std::string& origin) {
  CasingGeometry g;
  g.radius = pl.get<double>(radiusKey);
  g.axialPosition = pl.get<double>("Axial position");
  g.coneAngle = pl.get<double>("Cone angle");
  const auto ax = getDoubles(pl, "Axial range");
  EPAPHE_REQUIRE(ax.size() == 2 && ax[1] > ax[0], origin << ": '" << pathOf(pl, "Axial range") << "' = " << listed(ax)
                                                         << "; give {first, last} with last > first (m)");
  g.axialRange = {ax[0], ax[1]};
  g.law = getEnum<ClearanceLaw>(pl, "Clearance law");
  g.clearance = pl.get<double>("Clearance");
  g.orders = getInts(pl, "Harmonic orders");
  g.amplitudesFirst = getDoubles(pl, "Amplitudes at first end");
  g.amplitudesLast = getDoubles(pl, "Amplitudes at last end");
  if (g.law == ClearanceLaw::Harmonics)
    EPAPHE_REQUIRE(
        !g.orders.empty() && g.amplitudesFirst.size() == g.orders.size() && g.amplitudesLast.size() == g.orders.size(),
        origin << ": '" << pathOf(pl, "Harmonic orders") << "' has " << g.orders.size() << " orders, the amplitudes "
               << g.amplitudesFirst.size() << " and " << g.amplitudesLast.size()
               << "; give one amplitude per order at each end");
  return g;
}

void checkCasingMesh(const std::string& body, const ParameterList& mp, const std::string& origin) {
  const auto el = getInts(mp, "Elements");
  const std::string where = origin + ": body '" + body + "', '" + pathOf(mp, "Elements") + "' = " + listed(el);
  EPAPHE_REQUIRE(el.size() == 3, where << "; a Casing mesh needs {through the thickness, around the circumference, "
                                          "along the axis}, e.g. {1, 48, 3}");
  EPAPHE_REQUIRE(el[1] >= 4, where << ": " << el[1] << " element(s) around the circumference; a Casing needs at least "
                                   << "4 (its inner face is a closed bicubic B-spline through one node per element): "
                                   << "give e.g. {" << el[0] << ", 48, " << el[2] << "}");
  EPAPHE_REQUIRE(el[0] >= 1 && el[2] >= 1,
                 where << "; give at least 1 element through the thickness and along the axis");
  casingGeometry(mp, "Inner radius", origin);
}

void registerBuiltInMeshes(const std::function<void(const std::string&, ImporterRegistry::Factory)>& add) {
  add("Box", [] { return std::make_unique<BoxMesh>(); });
  add("Ring segment", [] { return std::make_unique<RingSegmentMesh>(); });
  add("Blade", [] { return std::make_unique<BladeMesh>(); });
  add("Casing", [] { return std::make_unique<CasingMesh>(); });
  add("Sphere", [] { return std::make_unique<SphereMesh>(); });
}

}  // namespace epaphe
