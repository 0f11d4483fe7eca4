#include "Epaphe_CalculixImport.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_ImportDetails.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <unordered_map>

namespace epaphe {
namespace {

using Details::parseDouble;
using Details::parseInt;
using Details::splitFields;
using Details::TextLines;
using Details::trim;
using Details::upper;

struct ElementType {
  const char* name;
  int nodes;    // nodes per element
  int corners;  // 8 hexahedron, 6 wedge, 4 tetrahedron
};
const ElementType kElementTypes[] = {{"C3D8", 8, 8},   {"C3D8R", 8, 8},   {"C3D8I", 8, 8},
                                     {"C3D20", 20, 8}, {"C3D20R", 20, 8}, {"C3D15", 15, 6},
                                     {"C3D6", 6, 6},   {"C3D10", 10, 4},  {"C3D4", 4, 4}};

std::string supportedElementTypes() {
  std::string s;
  for (const auto& t : kElementTypes) s += (s.empty() ? "" : ", ") + std::string(t.name);
  return s;
}

struct Keyword {
  std::string name;                          // upper case, without '*'
  std::map<std::string, std::string> param;  // KEY (upper case) -> value as written
};

Keyword parseKeyword(const std::string& line) {
  Keyword k;
  std::size_t start = 1;
  bool first = true;
  while (start <= line.size()) {
    const auto comma = line.find(',', start);
    const std::string field = trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (first)
      k.name = upper(field);
    else if (!field.empty()) {
      const auto eq = field.find('=');
      if (eq == std::string::npos)
        k.param[upper(field)] = "";
      else
        k.param[upper(trim(field.substr(0, eq)))] = trim(field.substr(eq + 1));
    }
    first = false;
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return k;
}

struct InputParser {
  struct Element {
    const ElementType* type;
    long long id;
    std::vector<long long> nodes;
    std::string where;
  };
  struct Boundary {
    std::string target;  // node number or node set name
    int first, last;
    std::string where;
  };
  struct SetMember {
    long long node;
    std::string where;
  };

  std::vector<int> ids;
  std::vector<std::string> nodeWhere;
  std::vector<std::array<double, 3>> coords;
  std::vector<Element> elements;
  std::map<std::string, std::vector<SetMember>> sets;  // upper-case name -> node numbers
  std::map<std::string, std::string> setNames;         // upper-case name -> name as first written
  std::vector<Boundary> boundaries;
  CalculixMaterial material;
  int materials = 0;  // *MATERIAL cards seen

  std::vector<SetMember>& set(const std::string& name) {
    setNames.emplace(upper(name), name);
    return sets[upper(name)];
  }

  void parse(const std::string& path, int depth) {
    EPAPHE_REQUIRE(depth < 20, path << ": *INCLUDE nested more than 20 deep (an include cycle?)");
    TextLines in(path, "CalculiX input");
    enum class Mode { Skip, Node, Element, Nset, Boundary, Density, Elastic, Expansion } mode = Mode::Skip;
    int dataLines = 0;  // under the current material card
    const ElementType* type = nullptr;
    Element pending{nullptr, 0, {}, ""};
    std::vector<SetMember>* nset = nullptr;
    std::vector<SetMember>* elementNodeSet = nullptr;
    bool generate = false;
    auto finishElement = [&](const std::string& where) {
      if (pending.type == nullptr) return;
      EPAPHE_REQUIRE(static_cast<int>(pending.nodes.size()) == pending.type->nodes,
                     pending.where << ": element " << pending.id << " of type " << pending.type->name << " lists "
                                   << pending.nodes.size() << " nodes, the type has " << pending.type->nodes
                                   << " (data ended at " << where << "); continue the node list on the next line");
      pending.type = nullptr;
    };
    std::string line;
    while (in.next(line)) {
      const std::string t = trim(line);
      if (t.empty() || t.rfind("**", 0) == 0) continue;
      if (t[0] == '*') {
        finishElement(in.where());
        const Keyword k = parseKeyword(t);
        mode = Mode::Skip;
        if (k.name == "INCLUDE") {
          auto it = k.param.find("INPUT");
          EPAPHE_REQUIRE(it != k.param.end() && !it->second.empty(),
                         in.where() << ": *INCLUDE without INPUT=file; write *INCLUDE, INPUT=mesh.inp");
          parse(Details::siblingPath(path, it->second), depth + 1);
        } else if (k.name == "NODE") {
          mode = Mode::Node;
          auto it = k.param.find("NSET");
          nset = it != k.param.end() ? &set(it->second) : nullptr;
        } else if (k.name == "ELEMENT") {
          auto it = k.param.find("TYPE");
          EPAPHE_REQUIRE(it != k.param.end(),
                         in.where() << ": *ELEMENT without TYPE=; supported types: " << supportedElementTypes());
          type = nullptr;
          for (const auto& et : kElementTypes)
            if (upper(it->second) == et.name) type = &et;
          EPAPHE_REQUIRE(type != nullptr, in.where() << ": element type '" << it->second
                                                     << "' is not supported; Epaphe imports the solid elements "
                                                     << supportedElementTypes());
          mode = Mode::Element;
          auto es = k.param.find("NSET");  // not Abaqus, but harmless
          elementNodeSet = es != k.param.end() ? &set(es->second) : nullptr;
        } else if (k.name == "NSET") {
          auto it = k.param.find("NSET");
          EPAPHE_REQUIRE(it != k.param.end() && !it->second.empty(), in.where() << ": *NSET without NSET=name");
          nset = &set(it->second);
          generate = k.param.count("GENERATE") > 0;
          mode = Mode::Nset;
        } else if (k.name == "BOUNDARY") {
          mode = Mode::Boundary;
        } else if (k.name == "MATERIAL") {
          if (++materials == 2 && material.problem.empty())
            material.problem = in.where() +
                               ": a second *MATERIAL; the thermal growth of an imported model takes "
                               "one material: give the model one";
        } else if (k.name == "DENSITY" || k.name == "ELASTIC" || k.name == "EXPANSION") {
          mode = k.name == "DENSITY" ? Mode::Density : k.name == "ELASTIC" ? Mode::Elastic : Mode::Expansion;
          dataLines = 0;
          auto type = k.param.find("TYPE");
          if (type != k.param.end() && upper(type->second) != "ISO" && material.problem.empty())
            material.problem = in.where() + ": *" + k.name + ", TYPE=" + type->second +
                               "; the thermal growth takes an isotropic material (TYPE=ISO)";
          if (k.name == "EXPANSION" && k.param.count("ZERO") && material.problem.empty())
            material.problem = in.where() + ": *EXPANSION, ZERO=" + k.param.at("ZERO") +
                               "; Epaphe's thermal strain is alpha (T - T_ref) from 'Thermal->Reference "
                               "temperature': remove ZERO=";
        }
        continue;
      }
      const auto f = splitFields(t);
      if (f.empty()) continue;
      switch (mode) {
        case Mode::Skip:
          break;
        case Mode::Density:
        case Mode::Elastic:
        case Mode::Expansion: {
          double a = 0, b = 0;
          const bool elastic = mode == Mode::Elastic;
          const bool ok = parseDouble(f[0], a) && std::isfinite(a) &&
                          (!elastic || (f.size() >= 2 && parseDouble(f[1], b) && std::isfinite(b)));
          const char* card = mode == Mode::Density ? "*DENSITY" : elastic ? "*ELASTIC" : "*EXPANSION";
          if (!ok || ++dataLines > 1) {
            if (material.problem.empty())
              material.problem = in.where() + ": " + card +
                                 (ok ? " has more than one line (a table in temperature); the thermal growth takes "
                                       "constant values: give one line"
                                     : " reads '" + t + "'; expected " + (elastic ? "'E, nu'" : "a number"));
            break;
          }
          if (materials > 1) break;  // the problem says so
          if (mode == Mode::Density) {
            material.density = a;
            material.densityWhere = in.where();
          } else if (elastic) {
            material.young = a;
            material.poisson = b;
            material.elasticWhere = in.where();
          } else {
            material.expansion = a;
            material.expansionWhere = in.where();
          }
          break;
        }
        case Mode::Node: {
          long long id = 0;
          double x[3] = {0, 0, 0};
          bool ok = f.size() >= 2 && f.size() <= 4 && parseInt(f[0], id) && id > 0;
          for (std::size_t c = 1; ok && c < f.size(); ++c) ok = parseDouble(f[c], x[c - 1]) && std::isfinite(x[c - 1]);
          EPAPHE_REQUIRE(ok, in.where() << ": expected 'node, x, y, z' under *NODE, read '" << t << "'");
          ids.push_back(static_cast<int>(id));
          nodeWhere.push_back(in.where());
          coords.push_back({x[0], x[1], x[2]});
          if (nset) nset->push_back({id, in.where()});
          break;
        }
        case Mode::Element: {
          std::size_t c = 0;
          if (pending.type == nullptr) {
            pending = Element{type, 0, {}, in.where()};
            EPAPHE_REQUIRE(parseInt(f[0], pending.id) && pending.id > 0,
                           in.where() << ": expected 'element, node1, node2, ...' under *ELEMENT, read '" << t << "'");
            c = 1;
          }
          for (; c < f.size(); ++c) {
            long long node = 0;
            EPAPHE_REQUIRE(parseInt(f[c], node) && node > 0, in.where() << ": node '" << f[c] << "' of element "
                                                                        << pending.id << " is not a node number");
            EPAPHE_REQUIRE(static_cast<int>(pending.nodes.size()) < type->nodes,
                           in.where() << ": element " << pending.id << " of type " << type->name << " lists more than "
                                      << type->nodes << " nodes");
            pending.nodes.push_back(node);
            if (elementNodeSet) elementNodeSet->push_back({node, in.where()});
          }
          if (static_cast<int>(pending.nodes.size()) == type->nodes) {
            elements.push_back(pending);
            pending.type = nullptr;
          }
          break;
        }
        case Mode::Nset: {
          if (generate) {
            long long a = 0, b = 0, s = 1;
            EPAPHE_REQUIRE((f.size() == 2 || f.size() == 3) && parseInt(f[0], a) && parseInt(f[1], b) &&
                               (f.size() == 2 || parseInt(f[2], s)) && s > 0 && a > 0 && b >= a,
                           in.where() << ": expected 'first, last[, step]' under *NSET, GENERATE, read '" << t << "'");
            for (long long n = a; n <= b; n += s) nset->push_back({n, in.where()});
            break;
          }
          for (const auto& item : f) {
            long long n = 0;
            if (parseInt(item, n)) {
              nset->push_back({n, in.where()});
              continue;
            }
            auto it = sets.find(upper(item));
            EPAPHE_REQUIRE(it != sets.end(),
                           in.where() << ": '" << item << "' is neither a node number nor a node set defined above");
            const auto members = it->second;  // copy: the set may be the one being filled
            nset->insert(nset->end(), members.begin(), members.end());
          }
          break;
        }
        case Mode::Boundary: {
          long long a = 0, b = 0;
          double value = 0;
          EPAPHE_REQUIRE(
              f.size() >= 2 && f.size() <= 4 && parseInt(f[1], a) && (f.size() < 3 || parseInt(f[2], b)) &&
                  (f.size() < 4 || parseDouble(f[3], value)),
              in.where() << ": expected 'node or set, first DOF[, last DOF[, value]]' under *BOUNDARY, read '" << t
                         << "'");
          if (f.size() < 3) b = a;
          EPAPHE_REQUIRE(a >= 1 && b >= a && b <= 3,
                         in.where() << ": *BOUNDARY fixes DOFs " << a << " to " << b
                                    << "; solid models have DOFs 1 to 3 (rotations and temperatures are not imported)");
          boundaries.push_back({f[0], static_cast<int>(a), static_cast<int>(b), in.where()});
          break;
        }
      }
    }
    finishElement(in.where() + " (end of file)");
  }
};

}  // namespace

CalculixInput readCalculixInput(const std::string& path) {
  InputParser p;
  p.parse(path, 0);
  CalculixInput out;
  Mesh& mesh = out.mesh;
  mesh.nodeIds = p.ids;
  mesh.coords = p.coords;
  std::unordered_map<long long, int> index;
  for (std::size_t n = 0; n < p.ids.size(); ++n) {
    auto [it, fresh] = index.emplace(p.ids[n], static_cast<int>(n));
    EPAPHE_REQUIRE(fresh, p.nodeWhere[n] << ": node " << p.ids[n] << " is defined twice (first at "
                                         << p.nodeWhere[it->second] << "); node numbers must be unique");
  }
  EPAPHE_REQUIRE(!p.ids.empty(), path << ": no *NODE found; the input deck must define the mesh (or *INCLUDE it)");
  auto nodeOf = [&](long long id, const std::string& where, const char* who) {
    auto it = index.find(id);
    EPAPHE_REQUIRE(it != index.end(), where << ": " << who << " refers to node " << id << ", which no *NODE defines");
    return it->second;
  };
  out.used.assign(p.ids.size(), 0);
  out.material = p.material;
  for (const auto& e : p.elements) {
    std::vector<int> n(e.nodes.size());
    for (std::size_t a = 0; a < n.size(); ++a) {
      n[a] = nodeOf(e.nodes[a], e.where, ("element " + std::to_string(e.id)).c_str());
      out.used[n[a]] = 1;
    }
    mesh.solids.push_back(n);
    // Corners as a hexahedron: wedges collapse the faces' last corner, tetrahedra the top face.
    if (e.type->corners == 8)
      mesh.hexes.push_back({n[0], n[1], n[2], n[3], n[4], n[5], n[6], n[7]});
    else if (e.type->corners == 6)
      mesh.hexes.push_back({n[0], n[1], n[2], n[2], n[3], n[4], n[5], n[5]});
    else
      mesh.hexes.push_back({n[0], n[1], n[2], n[2], n[3], n[3], n[3], n[3]});
  }
  for (const auto& [key, members] : p.sets) {
    std::vector<int> nodes;
    for (const auto& m : members) nodes.push_back(nodeOf(m.node, m.where, ("node set " + p.setNames[key]).c_str()));
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    mesh.nodeSets[p.setNames[key]] = nodes;
  }
  if (!p.sets.count("ALL")) {
    auto& all = mesh.nodeSets["all"];
    for (int n = 0; n < mesh.numNodes(); ++n) all.push_back(n);
  }
  out.fixed.assign(3 * p.ids.size(), 0);
  for (const auto& b : p.boundaries) {
    std::vector<int> nodes;
    long long id = 0;
    if (parseInt(b.target, id))
      nodes.push_back(nodeOf(id, b.where, "*BOUNDARY"));
    else {
      auto it = mesh.nodeSets.find(p.setNames.count(upper(b.target)) ? p.setNames[upper(b.target)] : b.target);
      EPAPHE_REQUIRE(it != mesh.nodeSets.end(), b.where << ": *BOUNDARY names '" << b.target
                                                        << "', neither a node number nor a node set of the deck");
      nodes = it->second;
    }
    for (int n : nodes)
      for (int d = b.first; d <= b.last; ++d) out.fixed[3 * static_cast<std::size_t>(n) + d - 1] = 1;
  }
  return out;
}

FullModel importCalculix(const CalculixFiles& files, const std::string& name,
                         const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  return Details::distributeModel(
      [&]() {
        Details::RawModel raw;
        raw.name = name;
        CalculixInput input = readCalculixInput(files.input);
        const auto index = Details::nodeIndex(input.mesh);
        const int nn = input.mesh.numNodes();
        raw.dofPath = files.matrices + ".dof";
        std::vector<char> hasRow(3 * static_cast<std::size_t>(nn), 0);
        {
          TextLines in(raw.dofPath, "CalculiX DOF map ('node.direction' per matrix row)");
          std::string line;
          while (in.next(line)) {
            const std::string t = trim(line);
            if (t.empty()) continue;
            const auto dot = t.find('.');
            long long node = 0, dir = 0;
            EPAPHE_REQUIRE(dot != std::string::npos && parseInt(t.substr(0, dot), node) &&
                               parseInt(t.substr(dot + 1), dir) && dir >= 1 && dir <= 3,
                           in.where() << ": expected 'node.direction' (direction 1, 2 or 3, e.g. 12.3), read '" << t
                                      << "'; is this the .dof file of a *FREQUENCY, SOLVER=MATRIXSTORAGE run?");
            auto it = index.find(static_cast<int>(node));
            EPAPHE_REQUIRE(it != index.end(), in.where()
                                                  << ": node " << node << " is not in the mesh of " << files.input
                                                  << "; the matrices and the input deck must be of the same model");
            const int d = 3 * it->second + static_cast<int>(dir) - 1;
            EPAPHE_REQUIRE(!input.fixed[d], in.where()
                                                << ": node " << node << " direction " << dir << " has a matrix row but "
                                                << files.input << " fixes it by *BOUNDARY; "
                                                << "the matrices and the input deck must be of the same model");
            raw.rowDof.push_back(d);
            raw.rowLine.push_back(in.line());
            hasRow[d] = 1;
          }
        }
        for (int n = 0; n < nn; ++n)
          for (int d = 0; d < 3; ++d)
            EPAPHE_REQUIRE(
                !input.used[n] || hasRow[3 * n + d] || input.fixed[3 * n + d],
                files.input << ": node " << input.mesh.nodeId(n) << " direction " << d + 1
                            << " belongs to an element but has no row in " << raw.dofPath
                            << " and no *BOUNDARY: CalculiX eliminates DOFs tied by *EQUATION, MPCs or rigid "
                               "bodies, which Epaphe does not import; fix such DOFs by *BOUNDARY or remove the ties");
        const int n = static_cast<int>(raw.rowDof.size());
        Details::readSparsePair(
            {files.matrices + ".sti", "stiffness matrix", Details::Storage::Triangle, n, raw.dofPath},
            {files.matrices + ".mas", "mass matrix", Details::Storage::Triangle, n, raw.dofPath}, raw.K, raw.M);
        raw.constrained = std::move(input.fixed);
        raw.mesh = std::move(input.mesh);
        return raw;
      },
      comm);
}

std::vector<double> readCalculixEigenvalues(const std::string& datPath) {
  TextLines in(datPath, "CalculiX results (.dat)");
  std::vector<double> lambda;
  std::string line;
  bool inBlock = false;
  while (in.next(line)) {
    if (line.find("E I G E N V A L U E   O U T P U T") != std::string::npos) {
      if (!lambda.empty()) break;
      inBlock = true;
      continue;
    }
    if (!inBlock) continue;
    const auto f = splitFields(line);
    long long mode = 0;
    double value = 0;
    if (f.size() >= 2 && parseInt(f[0], mode) && parseDouble(f[1], value))
      lambda.push_back(value);
    else if (!lambda.empty())
      break;
  }
  EPAPHE_REQUIRE(!lambda.empty(), datPath << ": no EIGENVALUE OUTPUT block; run a *FREQUENCY step to get one");
  return lambda;
}

std::vector<std::string> calculixInputFiles(const std::string& path) {
  std::vector<std::string> files;
  std::function<void(const std::string&, int)> scan = [&](const std::string& p, int depth) {
    EPAPHE_REQUIRE(depth < 20, p << ": *INCLUDE nested more than 20 deep (an include cycle?)");
    files.push_back(p);
    TextLines in(p, "CalculiX input");
    std::string line;
    while (in.next(line)) {
      const std::string t = trim(line);
      if (t.size() < 2 || t[0] != '*' || t[1] == '*') continue;
      const Keyword k = parseKeyword(t);
      if (k.name != "INCLUDE") continue;
      auto it = k.param.find("INPUT");
      EPAPHE_REQUIRE(it != k.param.end() && !it->second.empty(),
                     in.where() << ": *INCLUDE without INPUT=file; write *INCLUDE, INPUT=mesh.inp");
      scan(Details::siblingPath(p, it->second), depth + 1);
    }
  };
  scan(path, 0);
  return files;
}

}  // namespace epaphe

namespace epaphe {

std::vector<double> readCalculixDisplacements(const std::string& datPath, const Mesh& mesh) {
  const auto index = Details::nodeIndex(mesh);
  std::vector<double> u(3 * static_cast<std::size_t>(mesh.numNodes()), 0.0);
  std::vector<char> seen(static_cast<std::size_t>(mesh.numNodes()), 0);
  TextLines in(datPath, "CalculiX printed output (*NODE PRINT of U in the static step)");
  std::string line;
  bool inBlock = false, eigen = false;
  while (in.next(line) && !eigen) {
    const std::string t = trim(line);
    if (t.rfind("displacements (vx,vy,vz) for set", 0) == 0) {
      inBlock = true;
      continue;
    }
    if (t.find("E I G E N V A L U E") != std::string::npos) eigen = true;  // a frequency step's output follows
    if (t.empty() || !inBlock) continue;
    const auto f = splitFields(t);
    long long node = 0;
    double x[3];
    if (f.size() != 4 || !parseInt(f[0], node) || !parseDouble(f[1], x[0]) || !parseDouble(f[2], x[1]) ||
        !parseDouble(f[3], x[2])) {
      inBlock = false;
      continue;
    }
    auto it = index.find(static_cast<int>(node));
    EPAPHE_REQUIRE(it != index.end(), in.where() << ": node " << node << " is not in the model's mesh; the printed "
                                                 << "output and the input deck must be of the same model");
    for (int d = 0; d < 3; ++d) u[3 * static_cast<std::size_t>(it->second) + d] = x[d];  // the last block wins
    seen[it->second] = 1;
  }
  for (int n = 0; n < mesh.numNodes(); ++n)
    EPAPHE_REQUIRE(seen[n], datPath << ": no displacement printed for node " << mesh.nodeId(n)
                                    << "; print every node's in the static step: *NODE PRINT, NSET=NALL then U "
                                       "(NALL holding every node)");
  return u;
}

}  // namespace epaphe
