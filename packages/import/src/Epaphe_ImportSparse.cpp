// Sparse matrix files read in blocks, K and M at once over the ranks (Epaphe_ImportDetails.hpp).
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

}  // namespace Details
}  // namespace epaphe
