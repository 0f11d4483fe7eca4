#include "Epaphe_CodeAsterImport.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_ImportDetails.hpp"

#include <algorithm>

namespace epaphe {

FullModel importCodeAster(const CodeAsterFiles& files, const std::string& name,
                          const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  return Details::distributeModel(
      [&]() {
        std::vector<Details::LagrangeRow> lagrange;
        Details::RawModel raw =
            Details::readListedModel({files.nodes, files.nodeSets, files.dofs, files.stiffness, files.mass}, name,
                                     Details::Storage::Detect, &lagrange);
        const int n = static_cast<int>(raw.rowDof.size());
        raw.constrained.assign(3 * static_cast<std::size_t>(raw.mesh.numNodes()), 0);

        // The physical rows each Lagrange equation couples with in K.
        std::vector<int> lagrangeIndex(static_cast<std::size_t>(n), -1);
        for (std::size_t k = 0; k < lagrange.size(); ++k) lagrangeIndex[lagrange[k].row] = static_cast<int>(k);
        std::vector<std::vector<int>> ties(lagrange.size());
        for (std::size_t k = 0; k < raw.K.val.size(); ++k) {
          const int i = raw.K.row[k], j = raw.K.col[k];
          if (raw.K.val[k] == 0.0 || (lagrangeIndex[i] >= 0) == (lagrangeIndex[j] >= 0)) continue;
          if (lagrangeIndex[i] >= 0)
            ties[lagrangeIndex[i]].push_back(j);
          else
            ties[lagrangeIndex[j]].push_back(i);
        }
        auto dofName = [&](int dof) {
          return "node " + std::to_string(raw.mesh.nodeId(dof / 3)) + " direction " + "xyz"[dof % 3];
        };
        for (std::size_t k = 0; k < lagrange.size(); ++k) {
          auto& t = ties[k];
          std::sort(t.begin(), t.end());
          t.erase(std::unique(t.begin(), t.end()), t.end());
          const auto& l = lagrange[k];
          EPAPHE_REQUIRE(!t.empty(), files.dofs << ":" << l.line << ": the Lagrange equation of row " << l.row + 1
                                                << " is coupled to no physical DOF in " << files.stiffness
                                                << "; the DOF file and the matrices must be of the same model");
          EPAPHE_REQUIRE(t.size() == 1, files.dofs
                                            << ":" << l.line << ": the Lagrange equation of row " << l.row + 1
                                            << " ties " << t.size() << " physical DOFs (rows " << t[0] + 1 << ", "
                                            << t[1] + 1 << (t.size() > 2 ? ", ..." : "")
                                            << "): a linear relation (LIAISON_*), which Epaphe cannot drop; fix DOFs "
                                               "with DDL_IMPO only, or eliminate the relation before export");
          const int dof = raw.rowDof[t[0]];
          EPAPHE_REQUIRE(l.dof < 0 || l.dof == dof,
                         files.dofs << ":" << l.line << ": the Lagrange equation of row " << l.row + 1
                                    << " is said to fix " << dofName(l.dof) << " but K couples it to " << dofName(dof)
                                    << " (row " << t[0] + 1 << "); the DOF file does not match the matrices");
          raw.constrained[dof] = 1;
        }
        if (!files.clampedNodes.empty()) {
          Details::TextLines in(files.clampedNodes, "clamped nodes (node ids)");
          const auto index = Details::nodeIndex(raw.mesh);
          std::string line;
          while (in.next(line)) {
            const std::string t = Details::trim(line);
            if (t.empty() || t[0] == '#' || t[0] == '%') continue;
            for (const auto& f : Details::splitFields(t)) {
              long long id = 0;
              EPAPHE_REQUIRE(Details::parseInt(f, id), in.where() << ": '" << f << "' is not a node id");
              auto it = index.find(static_cast<int>(id));
              EPAPHE_REQUIRE(it != index.end(), in.where() << ": clamped node " << id << " is not in " << files.nodes);
              for (int d = 0; d < 3; ++d) raw.constrained[3 * static_cast<std::size_t>(it->second) + d] = 1;
            }
          }
        }
        return raw;
      },
      comm);
}

}  // namespace epaphe
