#include "Epaphe_ImportDetails.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <future>
#include <limits>
#include <numeric>
#include <system_error>

namespace epaphe {
namespace Details {

TextLines::TextLines(const std::string& path, const std::string& what) : path_(path), in_(path) {
  EPAPHE_REQUIRE(in_.good(), path << ": cannot open the " << what << " file ("
                                  << (errno ? std::strerror(errno) : "unreadable")
                                  << "); check the path and that the FE code wrote it");
}

bool TextLines::next(std::string& line) {
  if (!std::getline(in_, line)) return false;
  ++line_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',' || std::isspace(static_cast<unsigned char>(c))) {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

bool parseInt(const std::string& token, long long& value) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(token.c_str(), &end, 10);
  return errno == 0 && end == token.c_str() + token.size();
}

bool parseDouble(const std::string& token, double& value) {
  if (token.empty()) return false;
  std::string t = token;
  for (char& c : t)
    if (c == 'd' || c == 'D') c = 'e';  // Fortran 1.0D+03
  char* end = nullptr;
  value = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size();
}

int parseDirection(const std::string& token) {
  const std::string t = upper(token);
  if (t == "1" || t == "X" || t == "DX") return 0;
  if (t == "2" || t == "Y" || t == "DY") return 1;
  if (t == "3" || t == "Z" || t == "DZ") return 2;
  return -1;
}

std::string siblingPath(const std::string& relativeTo, const std::string& file) {
  if (!file.empty() && file[0] == '/') return file;
  const auto slash = relativeTo.find_last_of('/');
  return slash == std::string::npos ? file : relativeTo.substr(0, slash + 1) + file;
}

namespace {

/// A file read in blocks of 4 MiB and split into lines (numbered from 1) as TextLines does: large
/// matrix files (ccx writes about 35 bytes per entry) are read in large blocks rather than line by
/// line, and never held whole in memory (a line longer than a block grows the block).
class BufferedLines {
public:
  BufferedLines(const std::string& path, const std::string& what) : path_(path), in_(path, std::ios::binary) {
    TextLines check(path, what);  // the same Error as every reader for a missing or unreadable file
    buf_.resize(kBlock);
  }
  /// The next line as [begin, end) without its '\n' (and '\r'); valid until the next call.
  bool next(const char*& b, const char*& e) {
    const char* nl = nullptr;
    while ((nl = static_cast<const char*>(std::memchr(buf_.data() + p_, '\n', end_ - p_))) == nullptr && !eof_)
      refill();
    if (p_ >= end_) return false;
    b = buf_.data() + p_;
    e = nl != nullptr ? nl : buf_.data() + end_;  // the last line may have no '\n'
    p_ = static_cast<std::size_t>(e - buf_.data()) + (nl != nullptr ? 1 : 0);
    if (e > b && e[-1] == '\r') --e;
    ++line_;
    return true;
  }
  int line() const { return line_; }
  std::string where() const { return path_ + ":" + std::to_string(line_); }

private:
  static constexpr std::size_t kBlock = std::size_t(4) << 20;
  /// Moves the unread part to the front and reads behind it (growing the buffer when it is full).
  void refill() {
    std::memmove(buf_.data(), buf_.data() + p_, end_ - p_);
    end_ -= p_;
    p_ = 0;
    if (end_ == buf_.size()) buf_.resize(2 * buf_.size());
    in_.read(buf_.data() + end_, static_cast<std::streamsize>(buf_.size() - end_));
    const auto got = in_.gcount();
    end_ += static_cast<std::size_t>(got);
    if (got == 0 || !in_) eof_ = true;
  }
  std::string path_;
  std::ifstream in_;
  std::vector<char> buf_;
  std::size_t p_ = 0, end_ = 0;  // the unread bytes: [p_, end_)
  bool eof_ = false;
  int line_ = 0;
};

/// "i j v" with blanks or commas between, nothing else: the common case, parsed without copies.
/// Anything else (headers, comments, Fortran exponents, malformed lines) is left to the general
/// path, which gives the messages.
bool fastEntry(const char* p, const char* e, long long& i, long long& j, double& v) {
  auto blank = [](char c) { return c == ' ' || c == '\t'; };
  while (p < e && blank(*p)) ++p;
  auto r = std::from_chars(p, e, i);
  if (r.ec != std::errc() || r.ptr == e || !(blank(*r.ptr) || *r.ptr == ',')) return false;
  p = r.ptr;
  while (p < e && (blank(*p) || *p == ',')) ++p;
  r = std::from_chars(p, e, j);
  if (r.ec != std::errc() || r.ptr == e || !(blank(*r.ptr) || *r.ptr == ',')) return false;
  p = r.ptr;
  while (p < e && (blank(*p) || *p == ',')) ++p;
  if (p < e && *p == '+') ++p;  // from_chars takes no leading '+'; strtod does
  if (p < e && (*p == '+' || *p == '-') && p[-1] == '+') return false;
  const auto d = std::from_chars(p, e, v);
  if (d.ec != std::errc()) return false;
  p = d.ptr;
  while (p < e && blank(*p)) ++p;
  return p == e;
}

}  // namespace

SparseEntries readSparse(const std::string& path, const std::string& what, Storage storage, int size,
                         const std::string& sizeSource) {
  BufferedLines in(path, what);
  SparseEntries A;
  A.path = path;
  A.what = what;
  A.size = size;
  {  // ccx writes about 33 bytes per entry: one allocation instead of a doubling series of copies
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    const std::size_t guess = ec ? 0 : static_cast<std::size_t>(bytes / 24);
    A.row.reserve(guess);
    A.col.reserve(guess);
    A.val.reserve(guess);
    A.line.reserve(guess);
  }
  bool header = false, sizeLine = false;
  long long declared = -1;
  const char* lb = nullptr;
  const char* le = nullptr;
  while (in.next(lb, le)) {
    long long i = 0, j = 0;
    double v = 0;
    if ((!header || sizeLine) && fastEntry(lb, le, i, j, v) && std::isfinite(v) && i >= 1 && j >= 1 &&
        (A.size < 0 || (i <= A.size && j <= A.size))) {
      A.row.push_back(static_cast<int>(i - 1));
      A.col.push_back(static_cast<int>(j - 1));
      A.val.push_back(v);
      A.line.push_back(in.line());
      continue;
    }
    const std::string line(lb, le);
    const std::string t = trim(line);
    if (t.empty()) continue;
    if (upper(t).rfind("%%MATRIXMARKET", 0) == 0) {
      const auto f = splitFields(upper(t));
      EPAPHE_REQUIRE(f.size() == 5 && f[1] == "MATRIX" && f[2] == "COORDINATE",
                     in.where() << ": Matrix Market header '" << t << "' is not 'matrix coordinate'; write the " << what
                                << " as a sparse coordinate matrix");
      EPAPHE_REQUIRE(f[3] == "REAL" || f[3] == "INTEGER" || f[3] == "DOUBLE",
                     in.where() << ": the " << what << " has field '" << f[3] << "'; only real matrices are read");
      EPAPHE_REQUIRE(f[4] == "GENERAL" || f[4] == "SYMMETRIC",
                     in.where() << ": the " << what << " has symmetry '" << f[4]
                                << "'; write it 'general' (both triangles) or 'symmetric' (one triangle)");
      storage = f[4] == "SYMMETRIC" ? Storage::Triangle : Storage::General;
      header = true;
      continue;
    }
    if (t[0] == '%' || t[0] == '#') continue;
    const auto f = splitFields(t);
    if (header && !sizeLine) {
      long long m = 0, n = 0;
      EPAPHE_REQUIRE(
          f.size() == 3 && parseInt(f[0], m) && parseInt(f[1], n) && parseInt(f[2], declared) && m >= 0 &&
              declared >= 0,
          in.where() << ": expected the size line 'rows columns entries' of the " << what << ", read '" << t << "'");
      EPAPHE_REQUIRE(m == n, in.where() << ": the " << what << " is " << m << " x " << n
                                        << "; stiffness and mass matrices must be square");
      EPAPHE_REQUIRE(size < 0 || m == size,
                     in.where() << ": the " << what << " is " << m << " x " << n << " but " << sizeSource << " has "
                                << size << " DOFs; export the matrices and the DOF map of the same model");
      A.size = static_cast<int>(m);
      sizeLine = true;
      continue;
    }
    EPAPHE_REQUIRE(f.size() == 3 && parseInt(f[0], i) && parseInt(f[1], j) && parseDouble(f[2], v),
                   in.where() << ": expected 'row column value' in the " << what << ", read '" << t << "'");
    EPAPHE_REQUIRE(std::isfinite(v), in.where() << ": the " << what << " entry (" << i << ", " << j << ") is '" << f[2]
                                                << "' (NaN or Inf); the export is broken, regenerate it");
    EPAPHE_REQUIRE(i >= 1 && j >= 1 && (A.size < 0 || (i <= A.size && j <= A.size)),
                   in.where() << ": the " << what << " entry (" << i << ", " << j << ") is outside 1.." << A.size
                              << " (" << (header ? "the header size" : sizeSource)
                              << "); indices are 1-based and the matrix must match the DOF map");
    A.row.push_back(static_cast<int>(i - 1));
    A.col.push_back(static_cast<int>(j - 1));
    A.val.push_back(v);
    A.line.push_back(in.line());
  }
  EPAPHE_REQUIRE(!header || sizeLine, path << ": the Matrix Market " << what << " has a header but no size line");
  EPAPHE_REQUIRE(declared < 0 || declared == static_cast<long long>(A.val.size()),
                 path << ": the header of the " << what << " announces " << declared << " entries but the file has "
                      << A.val.size() << "; the file is truncated or the header is wrong");
  EPAPHE_REQUIRE(A.size >= 0, path << ": the size of the " << what << " is unknown (no header and no DOF map)");

  // Which triangle(s) hold entries: the first entry strictly above and strictly below.
  std::size_t above = A.val.size(), below = A.val.size();
  for (std::size_t k = 0; k < A.val.size(); ++k) {
    if (A.row[k] < A.col[k] && above == A.val.size()) above = k;
    if (A.row[k] > A.col[k] && below == A.val.size()) below = k;
  }
  const bool both = above < A.val.size() && below < A.val.size();
  if (storage == Storage::Triangle)
    EPAPHE_REQUIRE(!both, path << ": the " << what << " is stored as one triangle (symmetric) but line "
                               << A.line[above] << " holds (" << A.row[above] + 1 << ", " << A.col[above] + 1
                               << ") above and line " << A.line[below] << " holds (" << A.row[below] + 1 << ", "
                               << A.col[below] + 1
                               << ") below the diagonal; store one triangle, or declare the file 'general'");
  A.triangle = storage == Storage::Triangle || (storage == Storage::Detect && !both);
  if (storage == Storage::Detect && both)
    A.storageNote = " (read as a full matrix since line " + std::to_string(A.line[above]) +
                    " holds an entry above and line " + std::to_string(A.line[below]) + " one below the diagonal)";
  if (!A.triangle) checkSymmetric(A);
  return A;
}

void checkSymmetric(const SparseEntries& A) {
  if (A.triangle) return;
  // Sum duplicates per (i, j), then compare each off-diagonal entry with its mirror.
  std::vector<std::size_t> order(A.val.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return A.row[a] != A.row[b] ? A.row[a] < A.row[b] : A.col[a] < A.col[b];
  });
  struct E {
    int i, j, line;
    double v;
  };
  std::vector<E> e;
  std::vector<double> diag(static_cast<std::size_t>(A.size), 0.0);
  for (std::size_t k : order) {
    if (!e.empty() && e.back().i == A.row[k] && e.back().j == A.col[k])
      e.back().v += A.val[k];
    else
      e.push_back({A.row[k], A.col[k], A.line[k], A.val[k]});
    if (A.row[k] == A.col[k]) diag[A.row[k]] += A.val[k];
  }
  auto find = [&](int i, int j) -> const E* {
    auto it = std::lower_bound(e.begin(), e.end(), std::make_pair(i, j), [](const E& x, const std::pair<int, int>& p) {
      return x.i != p.first ? x.i < p.first : x.j < p.second;
    });
    return it != e.end() && it->i == i && it->j == j ? &*it : nullptr;
  };
  for (const E& x : e) {
    if (x.i == x.j) continue;
    const E* y = find(x.j, x.i);
    const double w = y ? y->v : 0.0;
    // Round-off of an assembly: relative to the entries and to the diagonal scale of the pair.
    const double tol =
        1e-10 * std::max(std::abs(x.v), std::abs(w)) + 1e-12 * std::sqrt(std::abs(diag[x.i] * diag[x.j]));
    EPAPHE_REQUIRE(std::abs(x.v - w) <= tol,
                   A.path << ":" << x.line << ": the " << A.what << " is not symmetric: entry (" << x.i + 1 << ", "
                          << x.j + 1 << ") = " << x.v << " but (" << x.j + 1 << ", " << x.i + 1 << ") = " << w
                          << (y ? " (line " + std::to_string(y->line) + ")" : std::string(" (absent)")) << A.storageNote
                          << "; Epaphe needs symmetric K and M: export the symmetric matrix, or one triangle of it");
  }
}

namespace {

/// Rank 1's offer to parse a matrix for rank 0 while distributeModel runs `read` on rank 0: set there
/// on rank 0 only. Protocol (tag-free point-to-point between ranks 0 and 1, in this order): rank 0
/// sends one job flag, then the job if there is one; rank 1 answers with whether it can open the file
/// (it may not share rank 0's file system), then with the entries or the error message.
struct ReadHelper {
  const Teuchos::Comm<int>* comm = nullptr;
  bool asked = false;  // the one job was sent (or declined by sending no job)
};
ReadHelper* readHelper = nullptr;

enum : int { kNoJob = 0, kJob = 1 };

void sendString(const Teuchos::Comm<int>& comm, const std::string& s, int to) {
  const int n = static_cast<int>(s.size());
  Teuchos::send(comm, n, to);
  if (n > 0) Teuchos::send(comm, n, s.data(), to);
}

std::string receiveString(const Teuchos::Comm<int>& comm, int from) {
  int n = 0;
  Teuchos::receive(comm, from, &n);
  std::string s(static_cast<std::size_t>(n), '\0');
  if (n > 0) Teuchos::receive(comm, from, n, &s[0]);
  return s;
}

template <class T>
void sendArray(const Teuchos::Comm<int>& comm, const std::vector<T>& v, int to) {
  if (!v.empty()) Teuchos::send(comm, static_cast<int>(v.size()), v.data(), to);
}

template <class T>
void receiveArray(const Teuchos::Comm<int>& comm, std::vector<T>& v, int count, int from) {
  v.resize(static_cast<std::size_t>(count));
  if (count > 0) Teuchos::receive(comm, from, count, v.data());
}

/// Rank 1: serves the job rank 0 may send while it reads the model (distributeModel).
void serveRead(const Teuchos::Comm<int>& comm) {
  int job = kNoJob;
  Teuchos::receive(comm, 0, &job);
  if (job != kJob) return;
  SparseFile f;
  f.path = receiveString(comm, 0);
  f.what = receiveString(comm, 0);
  f.sizeSource = receiveString(comm, 0);
  int storage = 0;
  Teuchos::receive(comm, 0, &storage);
  Teuchos::receive(comm, 0, &f.size);
  f.storage = static_cast<Storage>(storage);
  const int canOpen = std::ifstream(f.path, std::ios::binary).good() ? 1 : 0;
  Teuchos::send(comm, canOpen, 0);
  if (!canOpen) return;
  std::string error;
  SparseEntries A;
  try {
    A = readSparse(f.path, f.what, f.storage, f.size, f.sizeSource);
    EPAPHE_REQUIRE(A.val.size() <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                   f.path << ": " << A.val.size() << " entries exceed one message");
  } catch (const std::exception& e) {
    error = e.what();
    if (error.empty()) error = "reading " + f.path + " failed";
  }
  sendString(comm, error, 0);
  if (!error.empty()) return;
  const int head[3] = {A.size, A.triangle ? 1 : 0, static_cast<int>(A.val.size())};
  Teuchos::send(comm, 3, head, 0);
  sendString(comm, A.storageNote, 0);
  sendArray(comm, A.row, 0);
  sendArray(comm, A.col, 0);
  sendArray(comm, A.line, 0);
  sendArray(comm, A.val, 0);
}

/// Rank 0: asks rank 1 to parse `f`; false when rank 1 cannot open it.
bool askRead(const Teuchos::Comm<int>& comm, const SparseFile& f) {
  Teuchos::send(comm, static_cast<int>(kJob), 1);
  sendString(comm, f.path, 1);
  sendString(comm, f.what, 1);
  sendString(comm, f.sizeSource, 1);
  Teuchos::send(comm, static_cast<int>(f.storage), 1);
  Teuchos::send(comm, f.size, 1);
  int canOpen = 0;
  Teuchos::receive(comm, 1, &canOpen);
  return canOpen != 0;
}

/// Rank 0: rank 1's answer to askRead; its Error is thrown here.
SparseEntries collectRead(const Teuchos::Comm<int>& comm, const SparseFile& f) {
  const std::string error = receiveString(comm, 1);
  if (!error.empty()) throw Error(error);
  int head[3] = {0, 0, 0};
  Teuchos::receive(comm, 1, 3, head);
  SparseEntries A;
  A.path = f.path;
  A.what = f.what;
  A.size = head[0];
  A.triangle = head[1] != 0;
  A.storageNote = receiveString(comm, 1);
  receiveArray(comm, A.row, head[2], 1);
  receiveArray(comm, A.col, head[2], 1);
  receiveArray(comm, A.line, head[2], 1);
  receiveArray(comm, A.val, head[2], 1);
  return A;
}

}  // namespace

void readSparsePair(const SparseFile& k, const SparseFile& m, SparseEntries& K, SparseEntries& M) {
  auto read = [](const SparseFile& f) { return readSparse(f.path, f.what, f.storage, f.size, f.sizeSource); };
  // K here while M is parsed elsewhere; `mass()` waits for M. K's Error first, as when read one
  // after the other, but M is still waited for (rank 1 is sending it, the thread is running).
  auto readKThen = [&](auto&& mass) {
    try {
      K = read(k);
    } catch (...) {
      try {
        mass();
      } catch (...) {
      }
      throw;
    }
    M = mass();
  };
  if (readHelper != nullptr && !readHelper->asked) {
    readHelper->asked = true;
    const Teuchos::Comm<int>& comm = *readHelper->comm;
    if (askRead(comm, m)) return readKThen([&] { return collectRead(comm, m); });
  } else if (readHelper == nullptr && Kokkos::is_initialized() &&
             Kokkos::DefaultHostExecutionSpace::concurrency() >= 2) {
    auto mass = std::async(std::launch::async, read, m);
    return readKThen([&] { return mass.get(); });
  }
  K = read(k);
  M = read(m);
}

std::unordered_map<int, int> nodeIndex(const Mesh& mesh) {
  std::unordered_map<int, int> index;
  for (int n = 0; n < mesh.numNodes(); ++n) index.emplace(mesh.nodeId(n), n);
  return index;
}

Mesh readNodes(const std::string& path) {
  TextLines in(path, "node coordinates ('id x y z' per line)");
  Mesh mesh;
  std::unordered_map<int, int> seen;
  std::string line;
  while (in.next(line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const auto f = splitFields(t);
    long long id = 0;
    double x[3] = {0, 0, 0};
    bool ok = f.size() == 4 && parseInt(f[0], id) && id >= 0;
    for (int c = 0; ok && c < 3; ++c) ok = parseDouble(f[1 + c], x[c]) && std::isfinite(x[c]);
    EPAPHE_REQUIRE(ok, in.where() << ": expected 'id x y z' (finite coordinates), read '" << t << "'");
    auto [it, fresh] = seen.emplace(static_cast<int>(id), in.line());
    EPAPHE_REQUIRE(fresh, in.where() << ": node " << id << " is defined twice (also line " << it->second
                                     << "); node ids must be unique");
    mesh.nodeIds.push_back(static_cast<int>(id));
    mesh.coords.push_back({x[0], x[1], x[2]});
  }
  EPAPHE_REQUIRE(!mesh.coords.empty(), path << ": no node; the file must list 'id x y z' lines");
  auto& all = mesh.nodeSets["all"];
  for (int n = 0; n < mesh.numNodes(); ++n) all.push_back(n);
  return mesh;
}

void readNodeSets(const std::string& path, Mesh& mesh) {
  TextLines in(path, "node sets ('name id id ...' per line)");
  const auto index = nodeIndex(mesh);
  std::string line;
  while (in.next(line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const auto f = splitFields(t);
    auto& set = mesh.nodeSets[f[0]];
    for (std::size_t k = 1; k < f.size(); ++k) {
      long long id = 0;
      EPAPHE_REQUIRE(parseInt(f[k], id), in.where()
                                             << ": node set '" << f[0] << "': '" << f[k] << "' is not a node id");
      auto it = index.find(static_cast<int>(id));
      EPAPHE_REQUIRE(it != index.end(), in.where() << ": node set '" << f[0] << "' names node " << id
                                                   << ", which the node coordinates do not define");
      set.push_back(it->second);
    }
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
  }
}

RawModel readListedModel(const ListedModelFiles& files, const std::string& name, Storage storage,
                         std::vector<LagrangeRow>* lagrangeRows) {
  RawModel raw;
  raw.name = name;
  raw.mesh = readNodes(files.nodes);
  if (!files.nodeSets.empty()) readNodeSets(files.nodeSets, raw.mesh);
  readDofMap(files.dofs, raw, lagrangeRows != nullptr, lagrangeRows);
  const int n = static_cast<int>(raw.rowDof.size());
  readSparsePair({files.stiffness, "stiffness matrix", storage, n, files.dofs},
                 {files.mass, "mass matrix", storage, n, files.dofs}, raw.K, raw.M);
  return raw;
}

void readDofMap(const std::string& path, RawModel& raw, bool lagrange, std::vector<LagrangeRow>* lagrangeRows) {
  TextLines in(path, "DOF map ('node direction' per matrix row)");
  raw.dofPath = path;
  const auto index = nodeIndex(raw.mesh);
  std::string line;
  auto nodeNumber = [](std::string s, long long& id) {
    if (!s.empty() && (s[0] == 'N' || s[0] == 'n')) s = s.substr(1);
    return parseInt(s, id);
  };
  const char* grammar = lagrange ? "'node direction' (direction 1..3, x..z or DX..DZ) or a Lagrange row ('LAGR', "
                                   "'node LAGR:DX', 'node -1')"
                                 : "'node direction' (direction 1..3, x..z or DX..DZ)";
  while (in.next(line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const auto f = splitFields(t);
    const int row = static_cast<int>(raw.rowDof.size());
    long long node = 0, comp = 0;
    const std::string c = f.size() == 2 ? upper(f[1]) : f.size() == 1 ? upper(f[0]) : std::string();
    const bool numeric = f.size() == 2 && parseInt(f[1], comp);
    const bool isLagrange = c.rfind("LAGR", 0) == 0 || (numeric && comp <= 0);
    if (isLagrange) {
      EPAPHE_REQUIRE(lagrange, in.where()
                                   << ": '" << t << "' is a Lagrange multiplier row; this format takes physical DOFs "
                                   << "only (use the code_aster importer, which drops them)");
      int dof = -1;
      if (f.size() == 2 && nodeNumber(f[0], node) && node > 0) {
        auto it = index.find(static_cast<int>(node));
        EPAPHE_REQUIRE(it != index.end(), in.where()
                                              << ": Lagrange row of node " << node << ", which is not in the mesh");
        const auto colon = c.find_first_of(":_");
        const int d = numeric                      ? static_cast<int>(-comp) - 1
                      : colon == std::string::npos ? -1
                                                   : parseDirection(c.substr(colon + 1));
        if (d >= 0 && d < 3) dof = 3 * it->second + d;
      }
      raw.rowDof.push_back(-1);
      raw.rowLine.push_back(in.line());
      lagrangeRows->push_back({row, in.line(), dof});
      continue;
    }
    const int d = f.size() == 2 ? parseDirection(f[1]) : -1;
    EPAPHE_REQUIRE(f.size() == 2 && nodeNumber(f[0], node) && d >= 0,
                   in.where() << ": expected " << grammar << ", read '" << t << "'");
    auto it = index.find(static_cast<int>(node));
    EPAPHE_REQUIRE(it != index.end(),
                   in.where() << ": node " << node << " is not in the mesh (" << raw.mesh.numNodes()
                              << " nodes read); the DOF map and the node coordinates must be of the same model");
    raw.rowDof.push_back(3 * it->second + d);
    raw.rowLine.push_back(in.line());
  }
}

namespace {

const char* directionName(int d) {
  return d == 0 ? "x" : d == 1 ? "y" : "z";
}

/// Matrix entries in free-DOF numbering; `mirror`: one triangle, (j, i) stands also for (i, j).
struct Triplets {
  std::vector<int> row, col;
  std::vector<double> val;
  bool mirror = false;
};

/// Rank 0: numbers the free DOFs, checks the diagonals, renumbers the entries.
void freeSystem(RawModel& raw, FullModel& m, Triplets& K, Triplets& M) {
  const int n = static_cast<int>(raw.rowDof.size());
  const int nn = raw.mesh.numNodes();
  for (const SparseEntries* A : {&raw.K, &raw.M})
    EPAPHE_REQUIRE(A->size == n, A->path << ": the " << A->what << " is " << A->size << " x " << A->size
                                         << " but the DOF map " << raw.dofPath << " has " << n
                                         << " lines; export both from the same model");
  raw.constrained.resize(3 * static_cast<std::size_t>(nn), 0);
  m.name = raw.name;
  m.eq.assign(3 * static_cast<std::size_t>(nn), -1);
  std::vector<int> firstRow(3 * static_cast<std::size_t>(nn), -1), rowFree(static_cast<std::size_t>(n), -1);
  for (int r = 0; r < n; ++r) {
    const int d = raw.rowDof[r];
    if (d < 0) continue;
    EPAPHE_REQUIRE(firstRow[d] < 0, raw.dofPath << ":" << raw.rowLine[r] << ": node " << raw.mesh.nodeId(d / 3)
                                                << " direction " << directionName(d % 3)
                                                << " is named twice (also at line "
                                                << (firstRow[d] >= 0 ? raw.rowLine[firstRow[d]] : 0)
                                                << "); each DOF has one matrix row");
    firstRow[d] = r;
    if (raw.constrained[d]) continue;
    m.eq[d] = rowFree[r] = m.numFree++;
  }
  EPAPHE_REQUIRE(m.numFree > 0,
                 raw.dofPath << ": every DOF of body '" << raw.name << "' is constrained; nothing can move");

  for (int which = 0; which < 2; ++which) {
    const SparseEntries& A = which == 0 ? raw.K : raw.M;
    Triplets& T = which == 0 ? K : M;
    std::vector<double> diag(static_cast<std::size_t>(m.numFree), 0.0);
    std::vector<int> diagLine(static_cast<std::size_t>(m.numFree), 0);
    T.mirror = A.triangle;
    T.row.reserve(A.val.size());
    T.col.reserve(A.val.size());
    T.val.reserve(A.val.size());
    for (std::size_t k = 0; k < A.val.size(); ++k) {
      const int fi = rowFree[A.row[k]], fj = rowFree[A.col[k]];
      if (fi < 0 || fj < 0) continue;
      T.row.push_back(fi);
      T.col.push_back(fj);
      T.val.push_back(A.val[k]);
      if (fi == fj) {
        diag[fi] += A.val[k];
        if (!diagLine[fi]) diagLine[fi] = A.line[k];
      }
    }
    const char sym = which == 0 ? 'K' : 'M';
    for (int r = 0; r < n; ++r) {
      const int f = rowFree[r];
      if (f < 0) continue;
      const int d = raw.rowDof[r];
      EPAPHE_REQUIRE(diag[f] >= 0, A.path << ":" << diagLine[f] << ": the " << A.what << " has a negative diagonal "
                                          << sym << "(" << r + 1 << ", " << r + 1 << ") = " << diag[f] << " at node "
                                          << raw.mesh.nodeId(d / 3) << " direction " << directionName(d % 3)
                                          << ": the matrix is indefinite; check the export (sign, a flipped element, "
                                             "K and M swapped)");
      EPAPHE_REQUIRE(diag[f] > 0, A.path << ": the " << A.what << " has no diagonal " << sym << "(" << r + 1 << ", "
                                         << r + 1 << ") at node " << raw.mesh.nodeId(d / 3) << " direction "
                                         << directionName(d % 3) << " (DOF map line " << raw.rowLine[r]
                                         << "); a free DOF needs stiffness and mass: constrain it or check the model");
    }
  }
  m.mesh = std::move(raw.mesh);
}

template <class T>
void broadcastVector(const Teuchos::Comm<int>& comm, std::vector<T>& v) {
  int n = static_cast<int>(v.size());
  Teuchos::broadcast(comm, 0, &n);
  v.resize(static_cast<std::size_t>(n));
  if (n > 0) Teuchos::broadcast(comm, 0, n, v.data());
}

void broadcastString(const Teuchos::Comm<int>& comm, std::string& s) {
  std::vector<char> c(s.begin(), s.end());
  broadcastVector(comm, c);
  s.assign(c.begin(), c.end());
}

void broadcastMesh(const Teuchos::Comm<int>& comm, Mesh& mesh) {
  std::vector<double> x;
  std::vector<int> hex, setSizes, setNodes;
  std::string names;
  if (comm.getRank() == 0) {
    for (const auto& c : mesh.coords) x.insert(x.end(), c.begin(), c.end());
    for (const auto& h : mesh.hexes) hex.insert(hex.end(), h.begin(), h.end());
    for (const auto& [name, nodes] : mesh.nodeSets) {
      names += name + '\n';
      setSizes.push_back(static_cast<int>(nodes.size()));
      setNodes.insert(setNodes.end(), nodes.begin(), nodes.end());
    }
  }
  broadcastVector(comm, x);
  broadcastVector(comm, hex);
  broadcastVector(comm, mesh.nodeIds);
  broadcastVector(comm, setSizes);
  broadcastVector(comm, setNodes);
  broadcastString(comm, names);
  if (comm.getRank() == 0) return;
  mesh.coords.resize(x.size() / 3);
  for (std::size_t i = 0; i < mesh.coords.size(); ++i) mesh.coords[i] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
  mesh.hexes.resize(hex.size() / 8);
  for (std::size_t e = 0; e < mesh.hexes.size(); ++e)
    for (int a = 0; a < 8; ++a) mesh.hexes[e][a] = hex[8 * e + a];
  std::size_t pos = 0, at = 0;
  for (int size : setSizes) {
    const auto end = names.find('\n', pos);
    auto& set = mesh.nodeSets[names.substr(pos, end - pos)];
    set.assign(setNodes.begin() + static_cast<long>(at), setNodes.begin() + static_cast<long>(at + size));
    pos = end + 1;
    at += static_cast<std::size_t>(size);
  }
}

/// The fill-complete matrix of the entries of the rows this rank owns (T may hold other ranks'
/// rows: rank 0's), built as local CSR arrays: what insertGlobalValues and fillComplete would make,
/// bit for bit, without their per-entry insertion (about 30 ns per entry on the blades):
///  - column Map as Tpetra's makeColMap makes it: the owned GIDs in the row Map's order (every
///    owned row has its diagonal, so every owned column appears), then the remote GIDs ascending
///    (ascending GID is ascending owner on a contiguous Map); on one rank, the row Map itself;
///  - in each row, entries sorted by local column index, repeated (i, j) summed in file order.
Teuchos::RCP<CrsMatrix> buildMatrix(const Teuchos::RCP<const Map>& map, const Triplets& T) {
  const LO nLocal = static_cast<LO>(map->getNodeNumElements());
  const GO first = nLocal > 0 ? map->getMinGlobalIndex() : 0;
  auto owned = [&](GO g) { return g >= first && g < first + nLocal; };
  // Every entry (i, j, v) as it stands for the matrix: (i, j), then its mirror (j, i) if any, in
  // file order (the order of mirrored Triplets before).
  auto forEachEntry = [&](auto&& f) {
    for (std::size_t k = 0; k < T.row.size(); ++k) {
      const GO i = T.row[k], j = T.col[k];
      if (owned(i)) f(i, j, T.val[k]);
      if (T.mirror && i != j && owned(j)) f(j, i, T.val[k]);
    }
  };
  // Group the entries by row, keeping file order within a row (counting sort).
  std::vector<std::size_t> start(static_cast<std::size_t>(nLocal) + 1, 0);
  std::vector<GO> remote;
  forEachEntry([&](GO i, GO j, double) {
    ++start[i - first + 1];
    if (!owned(j)) remote.push_back(j);
  });
  for (LO l = 0; l < nLocal; ++l) start[l + 1] += start[l];
  std::sort(remote.begin(), remote.end());
  remote.erase(std::unique(remote.begin(), remote.end()), remote.end());
  auto localColumn = [&](GO g) -> LO {
    if (owned(g)) return static_cast<LO>(g - first);
    return nLocal + static_cast<LO>(std::lower_bound(remote.begin(), remote.end(), g) - remote.begin());
  };
  Teuchos::ArrayRCP<LO> col(start.back());
  Teuchos::ArrayRCP<double> val(start.back());
  std::vector<char> sorted(static_cast<std::size_t>(nLocal), 1);  // strictly ascending as filled
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    forEachEntry([&](GO i, GO j, double v) {
      const LO r = static_cast<LO>(i - first);
      const std::size_t p = fill[r]++;
      col[p] = localColumn(j);
      val[p] = v;
      if (p > start[r] && col[p] <= col[p - 1]) sorted[r] = 0;
    });
  }
  // Sort each row by column (stable: repeated entries stay in file order), merge repeats.
  Teuchos::ArrayRCP<std::size_t> rowPtr(static_cast<std::size_t>(nLocal) + 1);
  struct Entry {
    LO col;
    std::size_t at;  // position in file order: the tie-break that makes the sort stable
    double val;
    bool operator<(const Entry& o) const { return col != o.col ? col < o.col : at < o.at; }
  };
  std::vector<Entry> row;
  std::size_t out = 0;  // rows are compacted in place: out <= start[l] (the row is copied first)
  rowPtr[0] = 0;
  for (LO l = 0; l < nLocal; ++l) {
    if (sorted[l]) {  // ccx's column-major triangle fills every row in order
      for (std::size_t p = start[l]; p < start[l + 1]; ++p, ++out) {
        col[out] = col[p];
        val[out] = val[p];
      }
      rowPtr[l + 1] = out;
      continue;
    }
    row.clear();
    for (std::size_t p = start[l]; p < start[l + 1]; ++p) row.push_back({col[p], p, val[p]});
    std::sort(row.begin(), row.end());
    const std::size_t rowBegin = out;
    for (const Entry& e : row) {
      if (out > rowBegin && col[out - 1] == e.col) {
        val[out - 1] += e.val;
        continue;
      }
      col[out] = e.col;
      val[out] = e.val;
      ++out;
    }
    rowPtr[l + 1] = out;
  }
  Teuchos::RCP<const Map> colMap = map;
  if (map->getComm()->getSize() > 1) {
    std::vector<GO> gids(static_cast<std::size_t>(nLocal) + remote.size());
    std::iota(gids.begin(), gids.begin() + nLocal, first);
    std::copy(remote.begin(), remote.end(), gids.begin() + nLocal);
    colMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                  Teuchos::ArrayView<const GO>(gids), map->getIndexBase(), map->getComm()));
  }
  auto A = Teuchos::rcp(new CrsMatrix(map, colMap, rowPtr, col.persistingView(0, static_cast<long>(out)),
                                      val.persistingView(0, static_cast<long>(out))));
  A->expertStaticFillComplete(map, map);
  return A;
}

/// Rank 0 holds every entry; it sends each other rank the entries of the rows that rank owns, and
/// of a stored triangle also those whose mirror lies in its rows (point-to-point, one rank's share
/// packed at a time), and keeps them all, since buildMatrix takes only a rank's own rows: no rank
/// but 0 ever holds more than its share of the model. `map` is contiguous, its ranges ascending
/// with the rank.
void scatterRows(const Map& map, Triplets& T) {
  const Teuchos::Comm<int>& comm = *map.getComm();
  const int P = comm.getSize();
  if (P == 1) return;
  std::vector<long long> counts(static_cast<std::size_t>(P)), starts(static_cast<std::size_t>(P) + 1, 0);
  const long long mine = static_cast<long long>(map.getNodeNumElements());
  Teuchos::gatherAll(comm, 1, &mine, P, counts.data());
  for (int r = 0; r < P; ++r) starts[r + 1] = starts[r] + counts[r];
  int mirror = T.mirror ? 1 : 0;
  Teuchos::broadcast(comm, 0, &mirror);
  T.mirror = mirror != 0;
  if (comm.getRank() != 0) {
    int count = 0;
    Teuchos::receive(comm, 0, &count);
    receiveArray(comm, T.row, count, 0);
    receiveArray(comm, T.col, count, 0);
    receiveArray(comm, T.val, count, 0);
    return;
  }
  for (int r = 1; r < P; ++r) {
    Triplets share;
    auto ownedBy = [&](int g) { return g >= starts[r] && g < starts[r + 1]; };
    for (std::size_t k = 0; k < T.row.size(); ++k)
      if (ownedBy(T.row[k]) || (T.mirror && ownedBy(T.col[k]))) {
        share.row.push_back(T.row[k]);
        share.col.push_back(T.col[k]);
        share.val.push_back(T.val[k]);
      }
    EPAPHE_REQUIRE(share.row.size() <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                   "import: " << share.row.size() << " matrix entries for MPI rank " << r
                              << " exceed one message; use more ranks");
    Teuchos::send(comm, static_cast<int>(share.row.size()), r);
    sendArray(comm, share.row, r);
    sendArray(comm, share.col, r);
    sendArray(comm, share.val, r);
  }
}

}  // namespace

FullModel distributeModel(const std::function<RawModel()>& read, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  FullModel m;
  Triplets K, M;
  std::string error;
  if (comm->getRank() == 0) {
    ReadHelper helper{comm.get(), false};
    const bool lend = comm->getSize() > 1;
    if (lend) readHelper = &helper;
    try {
      RawModel raw = read();
      freeSystem(raw, m, K, M);
    } catch (const std::exception& e) {
      error = e.what();
      if (error.empty()) error = "import failed";
    }
    readHelper = nullptr;
    if (lend && !helper.asked) Teuchos::send(*comm, static_cast<int>(kNoJob), 1);
  } else if (comm->getRank() == 1) {
    serveRead(*comm);
  }
  broadcastString(*comm, error);
  if (!error.empty()) throw Error(error);
  broadcastString(*comm, m.name);
  broadcastMesh(*comm, m.mesh);
  broadcastVector(*comm, m.eq);
  Teuchos::broadcast(*comm, 0, &m.numFree);
  auto map = Teuchos::rcp(new Map(m.numFree, 0, comm));
  scatterRows(*map, K);
  scatterRows(*map, M);
  m.K = buildMatrix(map, K);
  m.M = buildMatrix(map, M);
  return m;
}

}  // namespace Details
}  // namespace epaphe
