#pragma once
// What the importers share: reading text files line by line with positions for error messages,
// sparse matrices stored as "row col value" lines (1-based, with or without a Matrix Market
// header), and turning a model read on rank 0 (mesh, the DOF of every matrix row, K and M; rank 1
// may parse M) into a FullModel distributed over the communicator.
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <fstream>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

namespace epaphe {
namespace Details {

/// A text file read line by line; where() gives "path:line" for messages.
class TextLines {
public:
  /// `what` says what the file should hold ("stiffness matrix"); an unreadable file is an Error.
  TextLines(const std::string& path, const std::string& what);
  bool next(std::string& line);
  int line() const { return line_; }
  const std::string& path() const { return path_; }
  std::string where() const { return path_ + ":" + std::to_string(line_); }

private:
  std::string path_;
  std::ifstream in_;
  int line_ = 0;
};

/// Splits at blanks and commas, dropping empty fields.
std::vector<std::string> splitFields(const std::string& line);
std::string trim(const std::string& s);
std::string upper(std::string s);
/// Whole-token conversions; false when the token is not entirely a number. Doubles accept a
/// Fortran 'D' exponent, and parse "nan"/"inf" (which the callers refuse with their own message).
bool parseInt(const std::string& token, long long& value);
bool parseDouble(const std::string& token, double& value);
/// "1".."3", "x".."z", "dx".."dz" (any case) -> 0..2, else -1.
int parseDirection(const std::string& token);
/// A directory prefix to resolve `file` relative to `relativeTo` (a file path).
std::string siblingPath(const std::string& relativeTo, const std::string& file);

/// How a coordinate file stores a symmetric matrix.
enum class Storage {
  General,   // every nonzero, both triangles; symmetry is checked
  Triangle,  // one triangle (either one), mirrored
  Detect     // Triangle when every entry lies in one triangle, else General
};

/// Entries of a square sparse matrix as read, 0-based, with the line each came from.
struct SparseEntries {
  std::string path;
  std::string what;         // "stiffness matrix"
  int size = -1;            // rows = columns; -1 while unknown
  bool triangle = false;    // one triangle stored: mirror off-diagonal entries on use
  std::string storageNote;  // why a file without header was read in full (for messages)
  std::vector<int> row, col, line;
  std::vector<double> val;
};

/// Reads "i j v" lines (1-based). A "%%MatrixMarket matrix coordinate real general|symmetric"
/// header and its size line are honoured (`storage` then comes from the header); lines starting
/// with '%' or '#' are comments. `size` (>= 0) is the size the DOF map implies, named
/// `sizeSource` in messages; entries outside it, NaN/Inf, a non-square or short file are Errors.
SparseEntries readSparse(const std::string& path, const std::string& what, Storage storage, int size,
                         const std::string& sizeSource);

/// The arguments of readSparse.
struct SparseFile {
  std::string path, what;
  Storage storage = Storage::Detect;
  int size = -1;
  std::string sizeSource;
};

/// readSparse(k) and readSparse(m), at once when a second core is free: inside distributeModel's
/// `read` on 2 or more MPI ranks, rank 1 (idle until the model is read) parses the mass matrix and
/// sends its entries to rank 0; on one rank, a second thread parses it when Kokkos has 2 or more host
/// threads. Otherwise one after the other. The same entries and the same Errors (the stiffness
/// matrix's first) either way.
void readSparsePair(const SparseFile& k, const SparseFile& m, SparseEntries& K, SparseEntries& M);

/// Refuses a matrix stored in full whose (i, j) and (j, i) entries differ beyond round-off.
void checkSymmetric(const SparseEntries& A);

/// A model as read on rank 0, before it is distributed.
struct RawModel {
  std::string name;
  Mesh mesh;
  std::vector<int> rowDof;        // per matrix row: 3 * node + direction, or -1 for a row to drop
  std::vector<int> rowLine;       // per matrix row: the line of the DOF map that names it
  std::string dofPath;            // the DOF map (for messages)
  std::vector<char> constrained;  // 3 * numNodes: DOFs fixed by boundary conditions (rows dropped)
  SparseEntries K, M;
};

/// Node ids -> indices of a mesh (nodeId(index) -> index).
std::unordered_map<int, int> nodeIndex(const Mesh& mesh);

/// Nodes from "id x y z" lines ('#' and '%' comment lines): coordinates and nodeIds, node set "all".
Mesh readNodes(const std::string& path);

/// Adds node sets from "name id id ..." lines (ids may continue on several lines of one set only
/// by repeating the name). Unknown node ids are Errors.
void readNodeSets(const std::string& path, Mesh& mesh);

/// A row of the DOF map that is a Lagrange multiplier (code_aster's dualized conditions).
struct LagrangeRow {
  int row, line;
  int dof;  // 3 * node + direction it says it ties, or -1 when the line does not say
};

/// One line per matrix row: "node direction", node as a number or a code_aster name "N12",
/// direction 1..3, x..z or DX..DZ. With `lagrange`, a Lagrange row is "LAGR", "node LAGR",
/// "node LAGR:DX" or code_aster's numeric form "node -c" (ties component c of node) / "0 0";
/// Lagrange rows get rowDof -1 and are listed in `lagrangeRows`. Fills raw.rowDof, rowLine, dofPath.
void readDofMap(const std::string& path, RawModel& raw, bool lagrange, std::vector<LagrangeRow>* lagrangeRows);

/// The files of a model exported as lists (Matrix Market, code_aster): nodes, optional node sets
/// ("" for none), the DOF map and K and M in coordinate form, read into a RawModel named `name`.
/// With `lagrangeRows`, the DOF map may hold Lagrange rows (readDofMap), listed there.
struct ListedModelFiles {
  std::string nodes, nodeSets, dofs, stiffness, mass;
};
RawModel readListedModel(const ListedModelFiles& files, const std::string& name, Storage storage,
                         std::vector<LagrangeRow>* lagrangeRows);

/// Runs `read` on rank 0 only (rank 1 may parse a matrix for it: readSparsePair), then gives every rank the same
/// FullModel: free DOFs numbered in the order of the matrix rows (rows of constrained DOFs and dropped rows left out),
/// row map contiguous and uniform. An Error on rank 0 is raised on every rank with the same message. Checks: matrix
/// sizes against the DOF map, a DOF named twice, positive diagonals of K and M.
FullModel distributeModel(const std::function<RawModel()>& read, const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

}  // namespace Details
}  // namespace epaphe
